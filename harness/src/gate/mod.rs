//! `harness gate RUN_DIR`: the regression gate of issue 7. Our runners' rows of a run
//! (ids starting with `ours`) are compared with a committed baseline
//! (`reports/baseline/ci.json`) under reviewed tolerances
//! (`reports/baseline/tolerances.toml`); the gate prints a table of what regressed,
//! improved or is new, and exits 1 on any regression. `--update` rewrites the baseline
//! from the run instead (a deliberate act, reviewed in the diff).
//!
//! Submodules: [`data`] (baseline rows, tolerances, errors), [`check`] (the comparison).
//! The gate reads records only; it never runs a mesher and never computes a metric.

pub mod check;
pub mod data;

pub use check::{compare, Finding, Verdict};
pub use data::{Baseline, GateError, GateRow, Tolerances};

use crate::records;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `harness gate`.
#[derive(clap::Args, Debug)]
pub struct GateArgs {
    /// Run directory holding results.jsonl (from `harness run`).
    pub run_dir: PathBuf,
    /// The committed baseline.
    #[arg(long, default_value = "reports/baseline/ci.json")]
    pub baseline: PathBuf,
    /// Tolerances file (default: tolerances.toml beside the baseline).
    #[arg(long)]
    pub tolerances: Option<PathBuf>,
    /// Rewrite the baseline from this run instead of comparing.
    #[arg(long)]
    pub update: bool,
    /// Also list the checks that passed.
    #[arg(long)]
    pub all: bool,
}

/// The gate's rows of a run directory: ours and the peers the ratios need.
pub fn run_rows(run_dir: &Path, tol: &Tolerances) -> Result<Vec<GateRow>, GateError> {
    let path = run_dir.join("results.jsonl");
    let records = records::read_jsonl(&path).map_err(|source| GateError::Io {
        path: path.clone(),
        source,
    })?;
    if records.is_empty() {
        return Err(GateError::EmptyRun(run_dir.to_path_buf()));
    }
    let peers = tol.all_peers();
    let mut rows: Vec<GateRow> = records
        .iter()
        .filter(|r| data::is_ours(&r.mesher) || peers.contains(&r.mesher.as_str()))
        .map(GateRow::from_record)
        .collect();
    rows.sort_by(|a, b| (&a.mesher, &a.model).cmp(&(&b.mesher, &b.model)));
    Ok(rows)
}

/// `harness gate`: 0 when nothing regressed (or the baseline was updated), 1 otherwise.
pub fn cli(args: GateArgs) -> anyhow::Result<ExitCode> {
    let tol_path = args.tolerances.clone().unwrap_or_else(|| {
        args.baseline
            .parent()
            .unwrap_or(Path::new("."))
            .join("tolerances.toml")
    });
    let tol = Tolerances::read(&tol_path)?;
    let rows = run_rows(&args.run_dir, &tol)?;
    if args.update {
        let records = records::read_jsonl(&args.run_dir.join("results.jsonl"))?;
        let first = records.first();
        let baseline = Baseline {
            git_revision: first.map(|r| r.git_revision.clone()).unwrap_or_default(),
            machine: first.map(|r| r.machine.clone()).unwrap_or_default(),
            created: crate::run::rfc3339_now(),
            rows,
        };
        baseline.write(&args.baseline)?;
        println!(
            "harness gate: baseline {} rewritten from {} ({} rows)",
            args.baseline.display(),
            args.run_dir.display(),
            baseline.rows.len()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let baseline = Baseline::read(&args.baseline)?;
    let findings = compare(&baseline.rows, &rows, &tol);
    print!("{}", render(&findings, args.all));
    let regressed = count(&findings, Verdict::Regressed);
    println!(
        "harness gate: {} vs {} (baseline {}, {}): {regressed} regressed, {} improved, {} new, {} passed",
        args.run_dir.display(),
        args.baseline.display(),
        baseline.git_revision,
        baseline.created,
        count(&findings, Verdict::Improved),
        count(&findings, Verdict::New),
        count(&findings, Verdict::Pass),
    );
    Ok(if regressed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Number of findings with a verdict.
pub fn count(findings: &[Finding], v: Verdict) -> usize {
    findings.iter().filter(|f| f.verdict == v).count()
}

/// The findings as a Markdown table, regressions first; passes only with `all`.
pub fn render(findings: &[Finding], all: bool) -> String {
    let mut shown: Vec<&Finding> = findings
        .iter()
        .filter(|f| all || f.verdict != Verdict::Pass)
        .collect();
    shown.sort_by_key(|f| f.verdict);
    if shown.is_empty() {
        return String::new();
    }
    let mut rows = vec![[
        "verdict".to_string(),
        "runner".into(),
        "model".into(),
        "check".into(),
        "baseline".into(),
        "now".into(),
        "limit".into(),
    ]];
    rows.extend(shown.iter().map(|f| {
        [
            format!("{:?}", f.verdict).to_uppercase(),
            f.runner.clone(),
            f.subject.clone(),
            f.check.to_string(),
            f.baseline.clone(),
            f.now.clone(),
            f.limit.clone(),
        ]
    }));
    let widths: Vec<usize> = (0..7)
        .map(|i| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0))
        .collect();
    let line = |r: &[String; 7]| {
        let cells: Vec<String> = r
            .iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect();
        format!("| {} |\n", cells.join(" | "))
    };
    let mut out = line(&rows[0]);
    let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
    out.push_str(&format!("|-{}-|\n", rule.join("-|-")));
    rows[1..].iter().for_each(|r| out.push_str(&line(r)));
    out
}
