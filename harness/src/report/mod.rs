//! Reports from recorded runs: tables in the layout of the paper's Table 1, plots, HTML.

use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `harness report`.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// A run directory holding `results.jsonl`.
    pub run_dir: PathBuf,
}

/// `harness report`.
pub fn cli(_args: ReportArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("harness report: not implemented yet")
}
