//! Plots with `plotters`, each written as SVG and PNG ([`super::render`]): per model,
//! the `Q_K` histogram and the normalised edge-length histogram with one series per
//! mesher (the paper's bins, as percentages of each mesher's tets or edges), and tets/s
//! versus tets on log-log axes across the corpus with one series per mesher.

use std::path::Path;

use mesher::quality::Histogram;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::records::{FrontIteration, Record, Status};
use crate::report::data::{tets_per_second, RunData};
use crate::report::render::{render, Figure};
use crate::report::table::mesher_label;
use crate::report::ReportError;

/// Size of every plot, pixels.
const SIZE: (u32, u32) = (760, 420);

/// Series colours by mesher position (canonical order), then plotters' palette.
const COLORS: [RGBColor; 7] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

/// Picks one histogram out of a record.
type PickHistogram = fn(&Record) -> Option<&Histogram>;

/// What a plot shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotKind {
    /// `Q_K` histogram of one model.
    Quality,
    /// Normalised edge-length histogram of one model.
    EdgeLength,
    /// Tets/s versus tets across the corpus.
    Rate,
    /// Front convergence of one model (ours): front size, points proposed and inserted
    /// per iteration.
    Front,
    /// One measure per mesher over the nightly history ([`crate::report::trend`]).
    Trend,
}

/// One written plot.
#[derive(Debug, Clone)]
pub struct Plot {
    /// SVG file name inside the report directory.
    pub file: String,
    /// PNG file name inside the report directory (same figure).
    pub png: String,
    /// Caption.
    pub title: String,
    /// The model (index into `RunData::models`), `None` for corpus-wide plots.
    pub model: Option<usize>,
    /// What it shows.
    pub kind: PlotKind,
}

/// Colour of mesher `k`.
pub fn color(k: usize) -> RGBColor {
    match COLORS.get(k) {
        Some(c) => *c,
        None => {
            let c = Palette99::pick(k).to_rgba();
            RGBColor(c.0, c.1, c.2)
        }
    }
}

/// A file-name-safe form of a model id.
pub fn slug(id: &str) -> String {
    id.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Draws every plot into `out` and lists them.
pub fn write_all(run: &RunData, out: &Path) -> Result<Vec<Plot>, ReportError> {
    let mut plots = Vec::new();
    for (m, info) in run.models.iter().enumerate() {
        let kinds: [(PlotKind, &str, PickHistogram); 2] = [
            (PlotKind::Quality, "qk", |r| {
                r.quality.as_ref().map(|q| &q.histogram)
            }),
            (PlotKind::EdgeLength, "edges", |r| {
                r.edge_lengths.as_ref().map(|e| &e.histogram)
            }),
        ];
        for (kind, prefix, pick) in kinds {
            let series = histogram_series(run, m, pick);
            if series.is_empty() {
                continue;
            }
            let (title, x_desc, y_desc) = match kind {
                PlotKind::Quality => (
                    format!("{}: Q_K histogram", info.id),
                    "Q_K (bin lower edges)",
                    "% of tets",
                ),
                _ => (
                    format!("{}: normalised edge lengths", info.id),
                    "normalised length (bin lower edges)",
                    "% of edges",
                ),
            };
            let stem = format!("{prefix}-{}", slug(&info.id));
            let fig = HistogramFigure {
                title: &title,
                descs: (x_desc, y_desc),
                series: &series,
            };
            plots.push(write_figure(
                out,
                &stem,
                &fig,
                title.clone(),
                Some(m),
                kind,
            )?);
        }
    }
    for m in 0..run.models.len() {
        plots.extend(front_plots(run, m, out)?);
    }
    if let Some(p) = rate_plot(run, out)? {
        plots.push(p);
    }
    Ok(plots)
}

/// One front convergence plot per mesher of model `m` whose record has a series.
fn front_plots(run: &RunData, m: usize, out: &Path) -> Result<Vec<Plot>, ReportError> {
    let mut plots = Vec::new();
    for k in 0..run.meshers.len() {
        let Some(front) = run.get(m, k).and_then(|r| r.front.as_deref()) else {
            continue;
        };
        if front.is_empty() {
            continue;
        }
        let (model, mesher) = (&run.models[m].id, &run.meshers[k].id);
        let title = format!("{model}: front convergence ({mesher})");
        let fig = FrontFigure {
            title: &title,
            front,
        };
        let stem = format!("front-{}-{}", slug(model), slug(mesher));
        plots.push(write_figure(
            out,
            &stem,
            &fig,
            title.clone(),
            Some(m),
            PlotKind::Front,
        )?);
    }
    Ok(plots)
}

/// One histogram series: label, colour, bin lower edges, percentages.
struct Series {
    label: String,
    color: RGBColor,
    edges: Vec<f64>,
    percent: Vec<f64>,
}

fn histogram_series(run: &RunData, m: usize, pick: PickHistogram) -> Vec<Series> {
    let mut out = Vec::new();
    for k in 0..run.meshers.len() {
        let Some(r) = run.get(m, k).filter(|r| r.status == Status::Ok) else {
            continue;
        };
        let Some(h) = pick(r).filter(|h| h.total() > 0) else {
            continue;
        };
        let total = h.total() as f64;
        out.push(Series {
            label: mesher_label(run, k),
            color: color(k),
            edges: h.edges.clone(),
            percent: h.counts.iter().map(|&c| 100.0 * c as f64 / total).collect(),
        });
    }
    out
}

/// Renders `fig` to `out/stem.svg` and `out/stem.png`.
fn write_figure(
    out: &Path,
    stem: &str,
    fig: &impl Figure,
    title: String,
    model: Option<usize>,
    kind: PlotKind,
) -> Result<Plot, ReportError> {
    let (file, png) = (format!("{stem}.svg"), format!("{stem}.png"));
    render(fig, SIZE, &out.join(&file), &out.join(&png))?;
    Ok(Plot {
        file,
        png,
        title,
        model,
        kind,
    })
}

fn text<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

fn tick_label(edges: &[f64], x: f64) -> String {
    let i = x.round();
    if (x - i).abs() > 1e-6 || i < 0.0 {
        return String::new();
    }
    match edges.get(i as usize) {
        Some(e) => format!("{}", (e * 100.0).round() / 100.0),
        None if i as usize == edges.len() => "inf".into(),
        None => String::new(),
    }
}

/// Bars side by side per bin; the x axis is the bin index, labelled with the bin edges.
struct HistogramFigure<'a> {
    title: &'a str,
    descs: (&'a str, &'a str),
    series: &'a [Series],
}

impl Figure for HistogramFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let series = self.series;
        let edges = series[0].edges.clone();
        let n = edges.len();
        let y_max = series
            .iter()
            .flat_map(|s| s.percent.iter().copied())
            .fold(1.0f64, f64::max)
            * 1.1;
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0f64..n as f64, 0f64..y_max)
            .map_err(text)?;
        chart
            .configure_mesh()
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 15))
            .disable_x_mesh()
            .light_line_style(TRANSPARENT)
            .x_labels(n + 1)
            .x_label_formatter(&|x| tick_label(&edges, *x))
            .x_desc(self.descs.0)
            .y_desc(self.descs.1)
            .draw()
            .map_err(text)?;
        let w = 0.8 / series.len() as f64;
        for (j, s) in series.iter().enumerate() {
            let c = s.color;
            let bars = s.percent.iter().enumerate().map(move |(i, &p)| {
                let x0 = i as f64 + 0.1 + j as f64 * w;
                Rectangle::new([(x0, 0.0), (x0 + w, p)], c.filled())
            });
            chart
                .draw_series(bars)
                .map_err(text)?
                .label(s.label.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
        }
        legend(chart)
    }
}

fn legend<'a, DB, CT>(mut chart: ChartContext<'a, DB, CT>) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(text)
}

/// Tets/s against tets, log-log: (mesher index, tets, rate) points with their labels.
struct RateFigure<'a> {
    title: &'a str,
    points: Vec<(usize, f64, f64)>,
    labels: Vec<String>,
}

impl Figure for RateFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let points = &self.points;
        let range = |f: fn(&(usize, f64, f64)) -> f64| {
            let lo = points.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = points.iter().map(f).fold(0.0, f64::max);
            // Whole decades, so that the axes carry their power-of-ten labels.
            10f64.powf(lo.log10().floor())..10f64.powf((hi * 1.01).log10().ceil())
        };
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(range(|p| p.1).log_scale(), range(|p| p.2).log_scale())
            .map_err(text)?;
        chart
            .configure_mesh()
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(TRANSPARENT)
            .x_desc("tets")
            .y_desc("tets per wall second")
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(text)?;
        for (k, label) in self.labels.iter().enumerate() {
            let c = color(k);
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.0 == k)
                .map(|p| (p.1, p.2))
                .collect();
            if pts.is_empty() {
                continue;
            }
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 5, c.filled())))
                .map_err(text)?
                .label(label.clone())
                .legend(move |(x, y)| Circle::new((x + 6, y), 5, c.filled()));
        }
        legend(chart)
    }
}

/// Picks one count out of a front iteration.
type PickCount = fn(&FrontIteration) -> usize;

/// Front faces, points proposed and inserted per iteration (the paper's convergence
/// figure), linear axes.
struct FrontFigure<'a> {
    title: &'a str,
    front: &'a [FrontIteration],
}

impl Figure for FrontFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let n = self.front.len();
        let y_max = self
            .front
            .iter()
            .map(|f| f.front.max(f.proposed).max(f.inserted))
            .max()
            .unwrap_or(1)
            .max(1) as f64
            * 1.1;
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(75)
            .build_cartesian_2d(1f64..(n.max(2) as f64), 0f64..y_max)
            .map_err(text)?;
        chart
            .configure_mesh()
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(TRANSPARENT)
            .x_desc("iteration")
            .y_desc("count")
            .x_labels(n.clamp(2, 12))
            .x_label_formatter(&|x| {
                let whole = (x - x.round()).abs() < 1e-6;
                if whole {
                    format!("{x:.0}")
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|y| format!("{y:.0}"))
            .draw()
            .map_err(text)?;
        let series: [(&str, PickCount); 3] = [
            ("front faces", |f| f.front),
            ("points proposed", |f| f.proposed),
            ("points inserted", |f| f.inserted),
        ];
        for (j, (label, pick)) in series.into_iter().enumerate() {
            let c = color(j);
            let pts: Vec<(f64, f64)> = self
                .front
                .iter()
                .enumerate()
                .map(|(i, f)| ((i + 1) as f64, pick(f) as f64))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                .map_err(text)?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 14, y)], c.stroke_width(2)));
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))
                .map_err(text)?;
        }
        legend(chart)
    }
}

/// Tets/s against tets for every ok run, log-log, one series per mesher.
fn rate_plot(run: &RunData, out: &Path) -> Result<Option<Plot>, ReportError> {
    let points: Vec<(usize, f64, f64)> = (0..run.meshers.len())
        .flat_map(|k| {
            run.ok_records(k).filter_map(move |r| {
                let t = r.tets? as f64;
                let rate = tets_per_second(r)?;
                (t > 0.0 && rate > 0.0).then_some((k, t, rate))
            })
        })
        .collect();
    if points.is_empty() {
        return Ok(None);
    }
    let title = "tets/s against tets (all models)".to_string();
    let fig = RateFigure {
        title: &title,
        points,
        labels: (0..run.meshers.len())
            .map(|k| mesher_label(run, k))
            .collect(),
    };
    write_figure(out, "rate", &fig, title.clone(), None, PlotKind::Rate).map(Some)
}
