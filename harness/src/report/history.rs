//! The nightly history (`reports/history.csv`): one row per mesher per nightly run with
//! the summary table's figures (models ok, worst Q_K over the fine models, % Q_K < 3,
//! tets/s), read and written with the `csv` crate. [`summarize`] is the one place these
//! figures are aggregated from records; the summary table and the history both use it.
//!
//! `harness history RUN_DIR [--history FILE] [--date YYYY-MM-DD]` appends a run's rows,
//! replacing rows of the same date and mesher (a resumed nightly rewrites its own row).

use crate::records::Record;
use crate::report::data::{tets_per_second, RunData};
use crate::report::{load_records, ReportError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The cross-model figures of one mesher in one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MesherSummary {
    /// Models the mesher meshed.
    pub models_ok: usize,
    /// Models it was run on.
    pub models: usize,
    /// Worst Q_K over the models whose surface does not cap the quality.
    pub worst_q_k_fine: Option<f64>,
    /// Worst Q_K over every ok model.
    pub worst_q_k_all: Option<f64>,
    /// % of all its tets with Q_K < 3.
    pub well_shaped_percent: Option<f64>,
    /// Total tets over total wall seconds.
    pub tets_per_second: Option<f64>,
    /// Largest peak RSS, bytes.
    pub peak_rss_bytes: Option<u64>,
}

fn max_opt(a: Option<f64>, x: f64) -> Option<f64> {
    Some(a.map_or(x, |a| a.max(x)))
}

/// The summary of mesher `k` over the run's models.
pub fn summarize(run: &RunData, k: usize) -> MesherSummary {
    let limited = |r: &Record| {
        run.models
            .iter()
            .find(|m| m.id == r.model)
            .is_some_and(|m| m.surface_limited())
    };
    let mut s = MesherSummary {
        models: (0..run.models.len())
            .filter(|&m| run.get(m, k).is_some())
            .count(),
        ..MesherSummary::default()
    };
    let (mut good, mut count, mut tets, mut wall) = (0u64, 0u64, 0f64, 0f64);
    for r in run.ok_records(k) {
        s.models_ok += 1;
        if let Some(q) = &r.quality {
            good += q.well_shaped;
            count += q.count;
            s.worst_q_k_all = max_opt(s.worst_q_k_all, q.worst_q_k);
            if !limited(r) {
                s.worst_q_k_fine = max_opt(s.worst_q_k_fine, q.worst_q_k);
            }
        }
        if let (Some(t), Some(_)) = (r.tets, tets_per_second(r)) {
            tets += t as f64;
            wall += r.wall_seconds.unwrap_or(0.0);
        }
        s.peak_rss_bytes = s.peak_rss_bytes.max(r.peak_rss_bytes);
    }
    s.well_shaped_percent = (count > 0).then(|| 100.0 * good as f64 / count as f64);
    s.tets_per_second = (wall > 0.0).then(|| tets / wall);
    s
}

/// One row of `reports/history.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryRow {
    /// Date of the nightly, YYYY-MM-DD.
    pub date: String,
    /// Git revision the run was made from.
    pub git_commit: String,
    /// Runner id.
    pub mesher: String,
    /// Models meshed.
    pub models_ok: usize,
    /// Models run.
    pub models: usize,
    /// Worst Q_K over the fine models (empty when none meshed; `inf` for a degenerate tet).
    pub worst_q_k: Option<f64>,
    /// % of tets with Q_K < 3.
    pub well_shaped_percent: Option<f64>,
    /// Tets per wall second over the run.
    pub tets_per_second: Option<f64>,
}

/// The history rows of a run: one per mesher.
pub fn rows_of(run: &RunData, date: &str) -> Vec<HistoryRow> {
    let commit = run.distinct(|r| &r.git_revision).join("+");
    (0..run.meshers.len())
        .map(|k| {
            let s = summarize(run, k);
            HistoryRow {
                date: date.to_string(),
                git_commit: commit.clone(),
                mesher: run.meshers[k].id.clone(),
                models_ok: s.models_ok,
                models: s.models,
                worst_q_k: s.worst_q_k_fine,
                well_shaped_percent: s.well_shaped_percent,
                tets_per_second: s.tets_per_second,
            }
        })
        .collect()
}

fn csv_error(path: &Path, e: csv::Error) -> ReportError {
    ReportError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    }
}

/// Reads the history (a missing file is an empty history).
pub fn read(path: &Path) -> Result<Vec<HistoryRow>, ReportError> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let mut reader = csv::Reader::from_path(path).map_err(|e| csv_error(path, e))?;
    reader
        .deserialize()
        .collect::<Result<Vec<HistoryRow>, _>>()
        .map_err(|e| csv_error(path, e))
}

/// Adds `new` to the history at `path`, replacing rows of the same date and mesher, and
/// rewrites the file sorted by date then mesher.
pub fn append(path: &Path, new: &[HistoryRow]) -> Result<(), ReportError> {
    let mut rows = read(path)?;
    rows.retain(|r| !new.iter().any(|n| n.date == r.date && n.mesher == r.mesher));
    rows.extend_from_slice(new);
    rows.sort_by(|a, b| (&a.date, &a.mesher).cmp(&(&b.date, &b.mesher)));
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    let mut writer = csv::Writer::from_path(path).map_err(|e| csv_error(path, e))?;
    for r in &rows {
        writer.serialize(r).map_err(|e| csv_error(path, e))?;
    }
    writer.flush().map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Arguments of `harness history`.
#[derive(clap::Args, Debug)]
pub struct HistoryArgs {
    /// A run directory holding `results.jsonl`.
    pub run_dir: PathBuf,
    /// The history file.
    #[arg(long, default_value = "reports/history.csv")]
    pub history: PathBuf,
    /// Date of the row (default: today, UTC).
    #[arg(long)]
    pub date: Option<String>,
}

/// `harness history`: appends the run's summary rows and prints them.
pub fn cli(args: HistoryArgs) -> anyhow::Result<ExitCode> {
    let loaded = load_records(&args.run_dir.join("results.jsonl"))?;
    let run = RunData::new(loaded.records);
    let date = args
        .date
        .unwrap_or_else(|| crate::run::rfc3339_now()[..10].to_string());
    let rows = rows_of(&run, &date);
    append(&args.history, &rows)?;
    for r in &rows {
        println!(
            "{} {:<20} ok {}/{}  worst Q_K {}  % Q_K<3 {}  tets/s {}",
            r.date,
            r.mesher,
            r.models_ok,
            r.models,
            r.worst_q_k.map_or("-".into(), |v| format!("{v:.3}")),
            r.well_shaped_percent
                .map_or("-".into(), |v| format!("{v:.2}")),
            r.tets_per_second.map_or("-".into(), |v| format!("{v:.0}")),
        );
    }
    eprintln!(
        "harness history: {} rows into {}",
        rows.len(),
        args.history.display()
    );
    Ok(ExitCode::SUCCESS)
}
