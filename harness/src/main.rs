//! `harness`: side-by-side runs of the mesher and its peers (issue "harness").
//!
//! For now only `harness version`; the corpus, runners, metrics and reports come with the harness issue.

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "harness",
    about = "Compare the mesher with TetGen, CGAL, fTetWild and Gmsh"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print the version of the harness and of the mesher library it measures.
    Version,
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Version => println!("harness {}", env!("CARGO_PKG_VERSION")),
    }
    Ok(())
}
