//! The `mesher` command line: thin wrappers over the library.
//!
//! - `mesher delaunay INPUT -o OUT`: Delaunay tetrahedralisation of the vertices of a
//!   surface or of a TetGen `.node` point file (paper §3).
//! - `mesher boundary SURFACE -o OUT`: the boundary mesh T(S,F) (paper §4).
//! - `mesher mesh SURFACE -o OUT`: the volume mesh: boundary mesh, control space and
//!   field points by the advancing front (paper §2-§5), with a progress bar.
//! - `mesher check SURFACE`: the defects of a surface; exit code 0 clean, 1 defects.
//! - `mesher generate KIND -o OUT`: deterministic test surfaces.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use mesher::delaunay::{triangulate, DelaunayOptions, InsertionOrder};
use mesher::io::IoError;
use mesher::surface::generate;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

mod mesh_cmd;
use mesh_cmd::mesh;

#[derive(Parser)]
#[command(
    name = "mesher",
    version,
    about = "Tetrahedral mesh generator (Frey, Borouchaki, George 1998)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Delaunay tetrahedralisation of a point set (.node) or of a surface's vertices.
    Delaunay {
        /// Input: .node points, or a surface (.off, .obj, .stl, .mesh).
        input: PathBuf,
        /// Output mesh (.mesh, .vtu, .msh, .node); nothing is written without it.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print a JSON line of statistics on stdout.
        #[arg(long)]
        stats: bool,
        /// Check every invariant and the empty-sphere property afterwards.
        #[arg(long)]
        validate: bool,
        /// Insertion order.
        #[arg(long, value_enum, default_value_t = Order::Brio)]
        order: Order,
        /// Seed of the randomised insertion order.
        #[arg(long, default_value_t = DelaunayOptions::default().seed)]
        seed: u64,
    },
    /// The boundary mesh T(S,F): the domain bounded by the surface, with no vertex but
    /// the surface's and interior Steiner points (paper §4).
    Boundary {
        /// The closed surface (.off, .obj, .stl, .mesh).
        surface: PathBuf,
        /// Output mesh (.vtu, .mesh, .msh, .node); nothing is written without it.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print the report as JSON on stdout.
        #[arg(long)]
        stats: bool,
        /// Check every adjacency and orientation invariant afterwards.
        #[arg(long)]
        validate: bool,
        /// Seed of the insertion order and of a shuffled edge recovery order (the
        /// default is the sorted order); another seed gives another, equally valid,
        /// boundary mesh, or more attempts (see `attempts` in --stats).
        #[arg(long)]
        seed: Option<u64>,
    },
    /// The volume mesh of the domain bounded by a closed surface (paper §2-§5).
    Mesh(Box<MeshArgs>),
    /// Check a surface: open, non-manifold, self-intersecting, degenerate.
    Check {
        /// The surface (.off, .obj, .stl, .mesh).
        surface: PathBuf,
        /// Print the report as JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Write a generated test surface.
    Generate {
        /// What to generate.
        #[arg(value_enum)]
        kind: Kind,
        /// Subdivision level (sphere: 20 * 4^level triangles) or resolution.
        #[arg(short, long, default_value_t = 4)]
        level: u32,
        /// Output surface (.off).
        #[arg(short, long)]
        output: PathBuf,
    },
}

#[derive(clap::Args)]
struct MeshArgs {
    /// The closed surface (.off, .obj, .stl, .mesh).
    surface: PathBuf,
    /// Output mesh (.mesh, .vtu, .msh, .node).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// A constant size instead of the boundary-derived control space.
    #[arg(long, conflicts_with = "size_map")]
    size: Option<f64>,
    /// A background mesh (.mesh) whose vertices carry sizes (from --size-sol, else the
    /// .sol beside it).
    #[arg(long)]
    size_map: Option<PathBuf>,
    /// The Medit .sol with one size per vertex of --size-map.
    #[arg(long, requires = "size_map")]
    size_sol: Option<PathBuf>,
    /// Gradation control of the boundary-derived sizes: at most this growth of the size
    /// per unit length (e.g. 0.3); off by default.
    #[arg(long, conflicts_with_all = ["size", "size_map"])]
    gradation: Option<f64>,
    /// Skip the optimisation (paper §6).
    #[arg(long)]
    no_optimize: bool,
    /// Bound on the optimisation passes over the bad tets.
    #[arg(long, default_value_t = mesher::optimize::OptimizeOptions::default().max_passes)]
    optimize_passes: usize,
    /// The optimisation works on the tets with Q_K above this.
    #[arg(long, default_value_t = mesher::optimize::OptimizeOptions::default().bad_quality)]
    optimize_above: f64,
    /// Normalised edge lengths: from the end-point sizes, or piecewise along the
    /// background tets.
    #[arg(long, value_enum, default_value_t = Length::Endpoints)]
    length: Length,
    /// Which surviving unacceptable tets the remedial rule accepts.
    #[arg(long, value_enum, default_value_t = RemedialArg::Front)]
    remedial: RemedialArg,
    /// Acceptance bound on normalised edge lengths (paper §5.2's delta).
    #[arg(long, default_value_t = mesher::front::FrontParams::default().delta)]
    delta: f64,
    /// Filtration distance, normalised (paper §5.2's delta_f).
    #[arg(long, default_value_t = mesher::front::FrontParams::default().delta_f)]
    delta_f: f64,
    /// Smallest normalised distance from a field point to an existing vertex.
    #[arg(long, default_value_t = mesher::front::FrontParams::default().delta_v)]
    delta_v: f64,
    /// delta_f and delta_v for the optimal points of boundary faces (the first layer)
    #[arg(long, default_value_t = mesher::front::FrontParams::default().delta_boundary)]
    delta_boundary: f64,
    /// Target normalised length of the optimal point's edges (paper: 1)
    #[arg(long, default_value_t = mesher::front::FrontParams::default().point.length)]
    point_length: f64,
    /// Cube side of the seed lattices inserted before the first front, in their sizes (inf: none)
    #[arg(long, default_value_t = mesher::front::FrontParams::default().seed_spacing)]
    seed_spacing: f64,
    /// Filter the field points against the vertices of every unacceptable tet
    #[arg(long)]
    filter_all_vertices: bool,
    /// Shape bound of acceptance: a tet with Q_K above it is unacceptable
    #[arg(long, default_value_t = mesher::front::FrontParams::default().q_accept)]
    q_accept: f64,
    /// Accepted tets worse than this Q_K join the cavity of a point next to them (inf: never)
    #[arg(long, default_value_t = mesher::front::FrontParams::default().absorb_q_k)]
    absorb_q_k: f64,
    /// Points proposed per front face: the optimal point and deeper ones along the normal
    #[arg(long, default_value_t = mesher::front::FrontParams::default().layers)]
    front_layers: usize,
    /// Layers of field points the filtration merges into the nearest kept point instead of dropping them (0: none, the paper's filtration; 1: the optimal points; 2: and the first deeper layer)
    #[arg(long, default_value_t = mesher::front::FrontParams::default().merge_layers)]
    merge_layers: usize,
    /// Bound on the front iterations.
    #[arg(long, default_value_t = mesher::front::FrontParams::default().max_iterations)]
    max_iterations: usize,
    /// Write the report (with the per-iteration front series) as JSON to this file.
    #[arg(long)]
    stats: Option<PathBuf>,
    /// Check every adjacency and orientation invariant afterwards.
    #[arg(long)]
    validate: bool,
    /// Wall-clock limit in seconds, checked between the phases (boundary mesh, front,
    /// optimisation).
    #[arg(long)]
    time_limit: Option<f64>,
    /// Past --time-limit: write the best valid mesh so far (the later phases skipped), or
    /// fail with an error and write nothing.
    #[arg(long, value_enum, default_value_t = TimeLimitArg::Best, requires = "time_limit")]
    time_limit_action: TimeLimitArg,
}

#[derive(Clone, Copy, ValueEnum)]
enum TimeLimitArg {
    Best,
    Error,
}

#[derive(Clone, Copy, ValueEnum)]
enum Length {
    Endpoints,
    Piecewise,
}

#[derive(Clone, Copy, ValueEnum)]
enum RemedialArg {
    Front,
    All,
}

#[derive(Clone, Copy, ValueEnum)]
enum Order {
    Brio,
    Hilbert,
    Input,
}

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    Sphere,
    Torus,
    Cube,
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("mesher: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Delaunay {
            input,
            output,
            stats,
            validate,
            order,
            seed,
        } => {
            let order = match order {
                Order::Brio => InsertionOrder::Brio,
                Order::Hilbert => InsertionOrder::Hilbert,
                Order::Input => InsertionOrder::Input,
            };
            delaunay(
                &input,
                output.as_deref(),
                stats,
                validate,
                DelaunayOptions { order, seed },
            )
        }
        Command::Check { surface, json } => check(&surface, json),
        Command::Mesh(args) => mesh(&args),
        Command::Boundary {
            surface,
            output,
            stats,
            validate,
            seed,
        } => boundary(&surface, output.as_deref(), stats, validate, seed),
        Command::Generate {
            kind,
            level,
            output,
        } => {
            let s = match kind {
                Kind::Sphere => generate::icosphere(level),
                Kind::Torus => generate::torus(
                    8 * level.max(1) as usize,
                    4 * level.max(1) as usize,
                    1.0,
                    0.35,
                ),
                Kind::Cube => generate::cube(level.max(1) as usize),
            };
            mesher::io::write_surface(&output, &s)
                .with_context(|| format!("writing {}", output.display()))?;
            eprintln!(
                "mesher: wrote {} ({} vertices, {} triangles)",
                output.display(),
                s.vertices.len(),
                s.triangles.len()
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Tells that input faces were turned to agree in orientation (not a defect: the
/// surface bounds the same solid).
pub(crate) fn note_reoriented(turned: usize, faces: usize) {
    if turned > 0 {
        eprintln!(
            "mesher: note: {turned} of {faces} input faces were listed the other way round from \
             their neighbours and were turned to agree"
        );
    }
}

fn read_points(input: &Path) -> Result<Vec<mesher::Point>> {
    let is_node = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("node"));
    if is_node {
        Ok(mesher::io::tetgen::read_points(input)?)
    } else {
        Ok(mesher::io::read_surface_unwelded(input)?.vertices)
    }
}

fn delaunay(
    input: &Path,
    output: Option<&Path>,
    stats: bool,
    validate: bool,
    options: DelaunayOptions,
) -> Result<ExitCode> {
    let t_read = Instant::now();
    let points = read_points(input)?;
    let read_s = t_read.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let tr = triangulate(&points, &options)?;
    let insert_s = t0.elapsed().as_secs_f64();
    if validate {
        tr.mesh
            .validate(true)
            .context("the triangulation failed validation")?;
    }
    let tets = tr.mesh.num_finite_tets();
    if let Some(out) = output {
        mesher::io::write_volume(out, &tr.mesh.to_volume_mesh())
            .with_context(|| format!("writing {}", out.display()))?;
    }
    if stats {
        let s = serde_json::json!({
            "peer": "ours",
            "points": points.len(),
            "vertices": tr.mesh.num_vertices(),
            "duplicates": tr.duplicates,
            "tets": tets,
            "read_seconds": read_s,
            "insert_seconds": insert_s,
            "validated": validate,
            "walk_steps": tr.stats.walk_steps,
            "cavity_tets": tr.stats.cavity_tets,
        });
        println!("{s}");
    } else {
        eprintln!(
            "mesher: {} points -> {} vertices ({} duplicates), {} tets in {:.3} s",
            points.len(),
            tr.mesh.num_vertices(),
            tr.duplicates,
            tets,
            insert_s
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn check(path: &Path, json: bool) -> Result<ExitCode> {
    let read = mesher::io::read_surface(path)?;
    let report = read.surface.check();
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{}: {} welded vertices",
            path.display(),
            read.welded_vertices
        );
        println!("{report}");
    }
    if report.is_clean() {
        Ok(ExitCode::SUCCESS)
    } else {
        Ok(ExitCode::from(1))
    }
}

fn boundary(
    path: &Path,
    output: Option<&Path>,
    stats: bool,
    validate: bool,
    seed: Option<u64>,
) -> Result<ExitCode> {
    use mesher::boundary::{boundary_mesh, BoundaryError, BoundaryOptions, EdgeOrder};
    let read = match mesher::io::read_surface(path) {
        Ok(r) => r,
        Err(e @ (IoError::Os { .. } | IoError::UnknownFormat { .. })) => return Err(e.into()),
        // A parse error names the file and line; the input is refused as by `mesh`.
        Err(e) => {
            eprintln!("mesher: refused: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    let t0 = Instant::now();
    let mut options = BoundaryOptions::default();
    if let Some(seed) = seed {
        options.seed = seed;
        options.edge_order = EdgeOrder::Shuffled(seed);
    }
    let (bm, report) = match boundary_mesh(&read.surface, &options) {
        Ok(r) => r,
        Err(e @ (BoundaryError::Defective { .. } | BoundaryError::VertexOnEntity { .. })) => {
            eprintln!("mesher: refused: {}: {e}", path.display());
            return Ok(ExitCode::from(1));
        }
        Err(e) => return Err(e).with_context(|| format!("boundary mesh of {}", path.display())),
    };
    let seconds = t0.elapsed().as_secs_f64();
    note_reoriented(report.faces_reoriented, report.surface_triangles);
    if validate {
        bm.mesh
            .validate(false)
            .context("the boundary mesh failed validation")?;
    }
    if let Some(out) = output {
        mesher::io::write_volume(out, &bm.to_volume_mesh())
            .with_context(|| format!("writing {}", out.display()))?;
    }
    if stats {
        let mut v = serde_json::to_value(&report)?;
        v["seconds"] = serde_json::json!(seconds);
        println!("{v}");
    } else {
        eprintln!(
            "mesher: {} triangles -> {} tets, {} region(s); missing {} edges, {} faces; {} interior Steiner point(s); {:.3} s",
            report.surface_triangles,
            report.tets,
            report.regions,
            report.missing_edges,
            report.missing_faces,
            report.steiner_interior,
            seconds
        );
    }
    Ok(ExitCode::SUCCESS)
}
