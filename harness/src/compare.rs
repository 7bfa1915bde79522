//! `harness compare`: `harness run` then `harness report` in one step, the main job.
//!
//! The records go to `OUT/run/` (`results.jsonl`, `results.csv`) and the report
//! (tables, plots, `index.html`) to `OUT/` itself, `reports/latest/` by default. Both
//! steps are the ones of `harness run` ([`crate::run::execute`]) and `harness report`
//! ([`crate::report::write_report`]); this module only chains them.

use crate::runners::RunArgs;
use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;

/// Where `harness compare` writes when `--out` is not given.
pub const DEFAULT_OUT: &str = "reports/latest";

/// Arguments of `harness compare`: those of `harness run`; `--out` names the report
/// folder (default [`DEFAULT_OUT`]) and the records go to its `run/` subfolder.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// What to run (as `harness run`).
    #[command(flatten)]
    pub run: RunArgs,
}

/// `harness compare`: runs into `OUT/run`, reports into `OUT`; returns `OUT`.
pub fn execute(args: CompareArgs) -> anyhow::Result<PathBuf> {
    let CompareArgs { mut run } = args;
    let out = run.out.take().unwrap_or_else(|| PathBuf::from(DEFAULT_OUT));
    run.out = Some(out.join("run"));
    let run_dir = crate::run::execute(&run)?;
    let report = crate::report::write_report(&run_dir, &out)
        .with_context(|| format!("reporting {}", run_dir.display()))?;
    for w in &report.warnings {
        eprintln!("harness compare: warning: {w}");
    }
    eprintln!(
        "harness compare: {} report files in {}",
        report.files.len(),
        out.display()
    );
    Ok(out)
}

/// `harness compare` as a command.
pub fn cli(args: CompareArgs) -> anyhow::Result<ExitCode> {
    let out = execute(args)?;
    println!("{}", out.join("index.html").display());
    Ok(ExitCode::SUCCESS)
}
