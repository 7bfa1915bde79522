//! SVG plots with `plotters` (its SVG backend needs no system fonts): per model, the
//! `Q_K` histogram and the normalised edge-length histogram with one series per mesher
//! (the paper's bins, as percentages of each mesher's tets or edges), and tets/s versus
//! tets on log-log axes across the corpus with one series per mesher.

use std::path::{Path, PathBuf};

use mesher::quality::Histogram;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::records::{Record, Status};
use crate::report::data::{tets_per_second, RunData};
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
}

/// One written plot.
#[derive(Debug, Clone)]
pub struct Plot {
    /// File name inside the report directory.
    pub file: String,
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
            let file = format!("{prefix}-{}.svg", slug(&info.id));
            let path = out.join(&file);
            grouped_histogram(&path, &title, (x_desc, y_desc), &series)?;
            plots.push(Plot {
                file,
                title,
                model: Some(m),
                kind,
            });
        }
    }
    if let Some(p) = rate_plot(run, out)? {
        plots.push(p);
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

fn plot_error(path: &Path, e: impl std::fmt::Display) -> ReportError {
    ReportError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
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
fn grouped_histogram(
    path: &Path,
    title: &str,
    (x_desc, y_desc): (&str, &str),
    series: &[Series],
) -> Result<(), ReportError> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_error(path, e))?;
    let edges = series[0].edges.clone();
    let n = edges.len();
    let y_max = series
        .iter()
        .flat_map(|s| s.percent.iter().copied())
        .fold(1.0f64, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0f64..n as f64, 0f64..y_max)
        .map_err(|e| plot_error(path, e))?;
    chart
        .configure_mesh()
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .disable_x_mesh()
        .light_line_style(TRANSPARENT)
        .x_labels(n + 1)
        .x_label_formatter(&|x| tick_label(&edges, *x))
        .x_desc(x_desc)
        .y_desc(y_desc)
        .draw()
        .map_err(|e| plot_error(path, e))?;
    let w = 0.8 / series.len() as f64;
    for (j, s) in series.iter().enumerate() {
        let c = s.color;
        let bars = s.percent.iter().enumerate().map(move |(i, &p)| {
            let x0 = i as f64 + 0.1 + j as f64 * w;
            Rectangle::new([(x0, 0.0), (x0 + w, p)], c.filled())
        });
        chart
            .draw_series(bars)
            .map_err(|e| plot_error(path, e))?
            .label(s.label.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
    }
    finish(&root, chart, path)
}

fn finish<'a, DB, CT>(
    root: &DrawingArea<DB, Shift>,
    mut chart: ChartContext<'a, DB, CT>,
    path: &Path,
) -> Result<(), ReportError>
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
        .map_err(|e| plot_error(path, e))?;
    root.present().map_err(|e| plot_error(path, e))
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
    let range = |f: fn(&(usize, f64, f64)) -> f64| {
        let lo = points.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = points.iter().map(f).fold(0.0, f64::max);
        // Whole decades, so that the axes carry their power-of-ten labels.
        10f64.powf(lo.log10().floor())..10f64.powf((hi * 1.01).log10().ceil())
    };
    let file = "rate.svg".to_string();
    let path: PathBuf = out.join(&file);
    let title = "tets/s against tets (all models)".to_string();
    let root = SVGBackend::new(&path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_error(&path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(&title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(range(|p| p.1).log_scale(), range(|p| p.2).log_scale())
        .map_err(|e| plot_error(&path, e))?;
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
        .map_err(|e| plot_error(&path, e))?;
    for k in 0..run.meshers.len() {
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
            .map_err(|e| plot_error(&path, e))?
            .label(mesher_label(run, k))
            .legend(move |(x, y)| Circle::new((x + 6, y), 5, c.filled()));
    }
    finish(&root, chart, &path)?;
    Ok(Some(Plot {
        file,
        title,
        model: None,
        kind: PlotKind::Rate,
    }))
}
