//! `cgal-dt3 pts.node [--validate]`: CGAL's Delaunay tetrahedralisation of a
//! point set; prints one JSON line with counts and the insertion time.

#[cfg(has_cgal)]
fn main() {
    // One line on failure (no backtrace): the bench script keeps stderr tails.
    if let Err(e) = run() {
        eprintln!("cgal-dt3: {e:#}");
        std::process::exit(1);
    }
}

#[cfg(has_cgal)]
fn run() -> anyhow::Result<()> {
    use clap::Parser;

    /// Delaunay tetrahedralisation of a .node point set with CGAL (EPICK, range insertion).
    #[derive(Parser)]
    struct Args {
        /// TetGen .node file.
        input: std::path::PathBuf,
        /// Also run `T.is_valid()` and report it (slow on large inputs).
        #[arg(long)]
        validate: bool,
    }

    let args = Args::parse();
    let pts = reference::node::read_node(&args.input)?;
    let r = reference::cgal::delaunay_3(&pts, args.validate)?;
    let mut out = serde_json::json!({
        "peer": "cgal-dt3",
        "points": pts.len(),
        "vertices": r.vertices,
        "finite_tets": r.finite_tets,
        "insert_seconds": r.insert_seconds,
    });
    if let Some(v) = r.is_valid {
        out["is_valid"] = v.into();
    }
    println!("{out}");
    if r.is_valid == Some(false) {
        std::process::exit(1);
    }
    Ok(())
}

#[cfg(not(has_cgal))]
fn main() {
    eprintln!(
        "cgal-dt3: built without CGAL (headers not found at build time); run scripts/setup.sh and rebuild"
    );
    std::process::exit(2);
}
