//! `cgal-mesh3 INPUT.off -o OUT.mesh --edge-length H [--seed S]`: CGAL Mesh_3 on a closed
//! OFF surface, written as Medit; prints one JSON line with counts and the meshing time.
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
        /// cell_size h.
        #[arg(long)]
        edge_length: f64,
        /// Seed of CGAL's random generators.
        #[arg(long, default_value_t = 0)]
        seed: u32,
    }

    let args = Args::parse();
    let r = reference::mesh3::mesh_3(&args.input, &args.output, args.edge_length, args.seed)?;
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
