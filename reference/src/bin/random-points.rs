//! `random-points N --seed S -o pts.node`: N uniform random points in the
//! unit cube, reproducible from the seed, as a TetGen .node file.

use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::Context;
use clap::Parser;

/// Uniform random points in [0,1)^3 (SplitMix64) as a TetGen .node file.
#[derive(Parser)]
struct Args {
    /// Number of points.
    n: usize,
    /// Seed of the generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output file (standard output if absent).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn main() {
    if let Err(e) = run() {
        eprintln!("random-points: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> anyhow::Result<()> {
    let args = Args::parse();
    let pts = reference::rng::unit_cube_points(args.n, args.seed);
    let sink: Box<dyn Write> = match &args.output {
        Some(p) => {
            Box::new(std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?)
        }
        None => Box::new(std::io::stdout().lock()),
    };
    reference::node::write_node(BufWriter::new(sink), &pts).context("writing points")?;
    Ok(())
}
