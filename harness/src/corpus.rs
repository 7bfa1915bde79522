//! The corpus of models (issue "harness"): manifest, fetching, checking, refining.

use std::process::ExitCode;

/// Arguments of `harness corpus`.
#[derive(clap::Args, Debug)]
pub struct CorpusArgs {
    /// What to do: list or check.
    #[arg(default_value = "list")]
    pub action: String,
}

/// `harness corpus`.
pub fn cli(_args: CorpusArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("harness corpus: not implemented yet")
}
