//! `harness`: side-by-side runs of the mesher and its peers.

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "Compare the mesher with TetGen, CGAL, fTetWild and Gmsh"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The corpus of models: list, check, fetch, refine.
    Corpus(harness::corpus::CorpusArgs),
    /// Run meshers on corpus models and record the measurements.
    Run(harness::runners::RunArgs),
    /// Render tables and plots from recorded runs (never runs a mesher).
    Report(harness::report::ReportArgs),
    /// Run, then report: records in OUT/run, the report in OUT (default reports/latest).
    Compare(harness::compare::CompareArgs),
    /// Compare our rows of a run with the committed baseline; exit 1 on a regression.
    Gate(harness::gate::GateArgs),
    /// Append a run's per-mesher summary to the nightly history (reports/history.csv).
    History(harness::report::history::HistoryArgs),
    /// Combine the shard directories of one run (`run --shard K/N`) into one.
    Merge(harness::merge::MergeArgs),
}

fn main() -> std::process::ExitCode {
    let result = match Cli::parse().command {
        Command::Corpus(a) => harness::corpus::cli(a),
        Command::Run(a) => harness::runners::cli(a),
        Command::Report(a) => harness::report::cli(a),
        Command::Compare(a) => harness::compare::cli(a),
        Command::Gate(a) => harness::gate::cli(a),
        Command::History(a) => harness::report::history::cli(a),
        Command::Merge(a) => harness::merge::cli(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("harness: error: {e:#}");
            std::process::ExitCode::from(2)
        }
    }
}
