//! `cgal-mesh3 INPUT.off -o OUT.mesh --edge-length H [--radius-edge R] [--sizes FILE]
//! [--seed S]`: CGAL Mesh_3 on a closed OFF surface, written as Medit; prints one JSON
//! line with counts and the meshing time.
//!
//! `--sizes FILE` (lines `x y z size`) makes every size criterion a field: the size of
//! the nearest listed point (the harness passes the input vertices with their sizes
//! h(P) of NOTES.md §3).
//!
//! Exit codes: 0 success, 1 meshing failed (message on stderr), 2 built without CGAL.

#[cfg(has_cgal)]
fn main() {
    // One line on failure (no backtrace): the harness keeps stderr tails.
    if let Err(e) = run() {
        eprintln!("cgal-mesh3: {e:#}");
        std::process::exit(1);
    }
}

/// Reads `x y z size` lines (blank lines skipped).
#[cfg(has_cgal)]
fn read_samples(path: &std::path::Path) -> anyhow::Result<Vec<[f64; 4]>> {
    use anyhow::Context;
    let text = std::fs::read_to_string(path).with_context(|| path.display().to_string())?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .with_context(|| format!("{}:{}", path.display(), i + 1))?;
        let [x, y, z, h] = v[..] else {
            anyhow::bail!("{}:{}: expected `x y z size`", path.display(), i + 1);
        };
        out.push([x, y, z, h]);
    }
    Ok(out)
}

#[cfg(has_cgal)]
fn run() -> anyhow::Result<()> {
    use clap::Parser;

    /// Tetrahedral mesh of the volume bounded by a closed OFF surface, with CGAL Mesh_3.
    #[derive(Parser)]
    struct Args {
        /// Closed triangle surface (OFF); nested shells bound hollow regions.
        input: std::path::PathBuf,
        /// Output Medit mesh.
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Mean input edge length h: edge_size h, facet_size 0.7h, facet_distance 0.05h,
        /// cell_size h (unless --sizes is given).
        #[arg(long)]
        edge_length: f64,
        /// Bound on the cells' radius-edge ratio.
        #[arg(long, default_value_t = 2.0)]
        radius_edge: f64,
        /// Size samples, one `x y z size` line each: sizes from the nearest sample.
        #[arg(long)]
        sizes: Option<std::path::PathBuf>,
        /// Seed of CGAL's random generators.
        #[arg(long, default_value_t = 0)]
        seed: u32,
    }

    let args = Args::parse();
    let samples = match &args.sizes {
        Some(p) => read_samples(p)?,
        None => Vec::new(),
    };
    let opts = reference::mesh3::Mesh3Options {
        edge_length: args.edge_length,
        radius_edge: args.radius_edge,
        samples,
        seed: args.seed,
    };
    let r = reference::mesh3::mesh_3(&args.input, &args.output, &opts)?;
    let out = serde_json::json!({
        "peer": "cgal-mesh3",
        "vertices": r.vertices,
        "cells": r.cells,
        "boundary_facets": r.facets,
        "mesh_seconds": r.mesh_seconds,
    });
    println!("{out}");
    Ok(())
}

#[cfg(not(has_cgal))]
fn main() {
    eprintln!(
        "cgal-mesh3: built without CGAL (headers not found at build time); run scripts/setup.sh and rebuild"
    );
    std::process::exit(2);
}
