//! Reports from recorded runs: tables in the layout of the paper's Table 1, plots, HTML.
//!
//! `harness report RUN_DIR [--out DIR]` reads `RUN_DIR/results.jsonl` only (it never runs
//! a mesher) and writes `table.md`, `targets.md` (the issues' targets per model,
//! [`targets`]), `table.tex`, one SVG and one PNG per plot and `index.html`; with
//! `--history FILE` also the nightly trend plots ([`trend`], from [`history`]).
//! Lines that do not parse as a [`Record`] are skipped with a warning naming the line, so
//! a report still comes out of a run written by an older or newer harness.
//!
//! Layout: [`data`] groups the records by model and mesher, [`table`] builds the tables
//! (rendered to Markdown, LaTeX and HTML), [`plots`] draws the figures, [`render`] turns
//! each into an SVG and a PNG, [`html`] writes the page.

pub mod data;
pub mod history;
pub mod html;
pub mod plots;
pub mod render;
pub mod table;
pub mod targets;
pub mod trend;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

pub use data::{load_records, Loaded, RunData};

/// Arguments of `harness report`.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// A run directory holding `results.jsonl`.
    pub run_dir: PathBuf,
    /// Where to write the report (default: the run directory).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A nightly history (`reports/history.csv`): adds its trend plots to the report.
    #[arg(long)]
    pub history: Option<PathBuf>,
}

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// `results.jsonl` held no readable record.
    #[error("{0}: no readable record")]
    NoRecords(PathBuf),
    /// Drawing a plot failed.
    #[error("plot {path}: {message}")]
    Plot {
        /// The SVG being drawn.
        path: PathBuf,
        /// The backend's error text.
        message: String,
    },
    /// The font for the plots' text could not be loaded.
    #[error("font {path}: {message}")]
    Font {
        /// The font file.
        path: PathBuf,
        /// Why it is unusable.
        message: String,
    },
}

/// What `write_report` produced.
#[derive(Debug, Clone)]
pub struct ReportFiles {
    /// Every file written, in order.
    pub files: Vec<PathBuf>,
    /// Warnings about skipped lines of `results.jsonl`.
    pub warnings: Vec<String>,
}

/// Writes `path`, naming it in the error.
pub(crate) fn write_file(path: &Path, text: &str) -> Result<(), ReportError> {
    std::fs::write(path, text).map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads `run_dir/results.jsonl` and writes the whole report into `out`.
pub fn write_report(run_dir: &Path, out: &Path) -> Result<ReportFiles, ReportError> {
    write_report_with(run_dir, out, None)
}

/// [`write_report`], plus the trend plots of a nightly history when one is given.
pub fn write_report_with(
    run_dir: &Path,
    out: &Path,
    history: Option<&Path>,
) -> Result<ReportFiles, ReportError> {
    let jsonl = run_dir.join("results.jsonl");
    let loaded = load_records(&jsonl)?;
    if loaded.records.is_empty() {
        return Err(ReportError::NoRecords(jsonl));
    }
    std::fs::create_dir_all(out).map_err(|source| ReportError::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let run = RunData::new(loaded.records);
    let mut files = Vec::new();
    let md = out.join("table.md");
    write_file(&md, &table::markdown(&run))?;
    files.push(md);
    let goals = out.join("targets.md");
    write_file(&goals, &targets::markdown(&run))?;
    files.push(goals);
    let tex = out.join("table.tex");
    write_file(&tex, &table::latex(&run))?;
    files.push(tex);
    let mut plots = plots::write_all(&run, out)?;
    if let Some(h) = history {
        plots.extend(trend::write_all(&history::read(h)?, out)?);
    }
    files.extend(
        plots
            .iter()
            .flat_map(|p| [out.join(&p.file), out.join(&p.png)]),
    );
    let index = out.join("index.html");
    write_file(&index, &html::page(&run, &plots, out))?;
    files.push(index);
    Ok(ReportFiles {
        files,
        warnings: loaded.warnings,
    })
}

/// `harness report`.
pub fn cli(args: ReportArgs) -> anyhow::Result<ExitCode> {
    let out = args.out.clone().unwrap_or_else(|| args.run_dir.clone());
    let report = write_report_with(&args.run_dir, &out, args.history.as_deref())?;
    for w in &report.warnings {
        eprintln!("harness report: warning: {w}");
    }
    for f in &report.files {
        println!("{}", f.display());
    }
    Ok(ExitCode::SUCCESS)
}
