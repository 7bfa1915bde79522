//! Trend plots from the nightly history ([`super::history`]): worst Q_K (fine models),
//! % Q_K < 3 and tets/s per mesher over the nightly dates, one line per mesher, each
//! written as SVG and PNG like the other plots. Worst Q_K and tets/s use log axes (they
//! span decades across meshers); non-finite values (a degenerate tet's infinite Q_K) are
//! left out of the line.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::report::history::HistoryRow;
use crate::report::plots::{color, Plot, PlotKind};
use crate::report::render::{render, Figure};
use crate::report::ReportError;

/// Size of a trend plot, pixels.
const SIZE: (u32, u32) = (760, 420);

/// Picks one value out of a history row.
type Pick = fn(&HistoryRow) -> Option<f64>;

/// One measure over time, one series per mesher.
struct TrendFigure<'a> {
    title: &'a str,
    y_desc: &'a str,
    log: bool,
    dates: Vec<String>,
    /// (mesher, points (date index, value)).
    series: Vec<(String, Vec<(f64, f64)>)>,
}

fn y_range(series: &[(String, Vec<(f64, f64)>)], log: bool) -> (f64, f64) {
    let ys = series.iter().flat_map(|s| s.1.iter().map(|p| p.1));
    let (lo, hi) = ys.fold((f64::INFINITY, 0f64), |(a, b), y| (a.min(y), b.max(y)));
    if log {
        let lo = 10f64.powf(lo.max(1e-12).log10().floor());
        (lo, 10f64.powf((hi * 1.01).log10().ceil()).max(lo * 10.0))
    } else {
        (0.0, (hi * 1.1).max(1.0))
    }
}

impl TrendFigure<'_> {
    fn draw_on<DB, X, Y>(&self, root: &DrawingArea<DB, Shift>, x: X, y: Y) -> Result<(), String>
    where
        DB: DrawingBackend,
        X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
        Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
        X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
        Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
    {
        let text = |e: &dyn std::fmt::Display| e.to_string();
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x, y)
            .map_err(|e| text(&e))?;
        let dates = &self.dates;
        let log = self.log;
        chart
            .configure_mesh()
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(TRANSPARENT)
            .x_labels(dates.len().clamp(2, 8))
            .x_label_formatter(&|x| {
                let i = x.round();
                match ((x - i).abs() < 1e-6 && i >= 0.0).then(|| dates.get(i as usize)) {
                    Some(Some(d)) => d.clone(),
                    _ => String::new(),
                }
            })
            .y_label_formatter(&|y| {
                if log {
                    format!("{y:.0e}")
                } else {
                    format!("{y:.0}")
                }
            })
            .x_desc("nightly")
            .y_desc(self.y_desc)
            .draw()
            .map_err(|e| text(&e))?;
        for (k, (label, pts)) in self.series.iter().enumerate() {
            let c = color(k);
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                .map_err(|e| text(&e))?
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 14, y)], c.stroke_width(2)));
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 4, c.filled())))
                .map_err(|e| text(&e))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| text(&e))
    }
}

impl Figure for TrendFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let n = self.dates.len();
        // One date still gets a visible x range.
        let x = -0.5f64..(n as f64 - 0.5).max(0.5);
        let (lo, hi) = y_range(&self.series, self.log);
        if self.log {
            self.draw_on(root, x, (lo..hi).log_scale())
        } else {
            self.draw_on(root, x, lo..hi)
        }
    }
}

/// The series of one measure: per mesher, (date index, value) for finite values.
fn series_of(
    rows: &[HistoryRow],
    dates: &[String],
    pick: Pick,
    log: bool,
) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut meshers: Vec<&str> = rows.iter().map(|r| r.mesher.as_str()).collect();
    meshers.sort_unstable();
    meshers.dedup();
    meshers
        .into_iter()
        .map(|m| {
            let pts = rows
                .iter()
                .filter(|r| r.mesher == m)
                .filter_map(|r| {
                    let v = pick(r).filter(|v| v.is_finite() && (!log || *v > 0.0))?;
                    let i = dates.iter().position(|d| *d == r.date)?;
                    Some((i as f64, v))
                })
                .collect();
            (m.to_string(), pts)
        })
        .filter(|(_, pts): &(String, Vec<(f64, f64)>)| !pts.is_empty())
        .collect()
}

/// Draws the three trend plots into `out` (none when the history is empty).
pub fn write_all(rows: &[HistoryRow], out: &Path) -> Result<Vec<Plot>, ReportError> {
    let mut dates: Vec<String> = rows.iter().map(|r| r.date.clone()).collect();
    dates.sort_unstable();
    dates.dedup();
    let measures: [(&str, &str, &str, bool, Pick); 3] = [
        (
            "trend-worst-qk",
            "worst Q_K (fine models) per nightly",
            "worst Q_K",
            true,
            |r| r.worst_q_k,
        ),
        (
            "trend-qk3",
            "% Q_K<3 per nightly",
            "% of tets with Q_K<3",
            false,
            |r| r.well_shaped_percent,
        ),
        (
            "trend-rate",
            "tets/s per nightly",
            "tets per wall second",
            true,
            |r| r.tets_per_second,
        ),
    ];
    let mut plots = Vec::new();
    for (stem, title, y_desc, log, pick) in measures {
        let series = series_of(rows, &dates, pick, log);
        if series.is_empty() {
            continue;
        }
        let fig = TrendFigure {
            title,
            y_desc,
            log,
            dates: dates.clone(),
            series,
        };
        let (file, png) = (format!("{stem}.svg"), format!("{stem}.png"));
        render(&fig, SIZE, &out.join(&file), &out.join(&png))?;
        plots.push(Plot {
            file,
            png,
            title: title.to_string(),
            model: None,
            kind: PlotKind::Trend,
        });
    }
    Ok(plots)
}
