//! `mesher mesh`: reads the surface and the size map, runs [`mesher::mesh`] with a
//! progress bar over the front iterations, writes the mesh, the statistics JSON and a
//! summary line.

use super::{Length, MeshArgs, RemedialArg, TimeLimitArg};
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use mesher::boundary::BoundaryError;
use mesher::delaunay::DelaunayError;
use mesher::front::Remedial;
use mesher::io::IoError;
use mesher::limit::TimeLimitAction;
use mesher::sizing::LengthMode;
use mesher::{MeshError, Params, SizeSpec};
use std::process::ExitCode;

/// Exit code of a refused input (unreadable, defective, degenerate): the reason is on
/// stderr as `mesher: refused: FILE: REASON`. Other errors exit 2.
const EXIT_REFUSED: u8 = 1;

pub fn mesh(args: &MeshArgs) -> Result<ExitCode> {
    let read = match mesher::io::read_surface(&args.surface) {
        Ok(r) => r,
        Err(e @ (IoError::Os { .. } | IoError::UnknownFormat { .. })) => return Err(e.into()),
        // The parse errors name the file and line themselves.
        Err(e) => {
            eprintln!("mesher: refused: {e}");
            return Ok(ExitCode::from(EXIT_REFUSED));
        }
    };
    let surface = read.surface;
    let params = params_from(args)?;
    let bar = ProgressBar::new(params.front.max_iterations as u64);
    bar.set_style(
        ProgressStyle::with_template("front {pos:>2}/{len} {bar:30} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut progress = |it: &mesher::front::Iteration| {
        bar.inc(1);
        bar.set_message(format!(
            "front {} inserted {} tets {}",
            it.front, it.inserted, it.tets
        ));
    };
    let result = mesher::mesh::mesh_with_progress(&surface, &params, &mut progress);
    bar.finish_and_clear();
    let (meshed, report) = match result {
        Ok(r) => r,
        Err(e) if is_refusal(&e) => return Ok(refuse(args, &e)),
        Err(e) => return Err(e).with_context(|| format!("meshing {}", args.surface.display())),
    };
    if args.validate {
        meshed
            .mesh
            .validate(false)
            .context("the mesh failed validation")?;
    }
    let (vm, sizes) = meshed.volume_and_sizes();
    // The file is written while the summary is measured (bunny00: 0.2 s and 0.4 s).
    let (written, (q_t, summary, band)) = rayon::join(
        || {
            args.output.as_ref().map(|out| {
                mesher::io::write_volume(out, &vm)
                    .with_context(|| format!("writing {}", out.display()))
            })
        },
        || {
            let ((q_t, summary), band) = rayon::join(
                || {
                    let q_t =
                        mesher::quality::target_quality(&surface.vertices, &surface.triangles);
                    let summary = mesher::quality::summarize(&vm, Some(q_t.q_t));
                    (q_t, summary)
                },
                || mesher::mesh::EdgeBand::of(&vm, &sizes),
            );
            (q_t, summary, band)
        },
    );
    written.transpose()?;
    if let Some(path) = &args.stats {
        let mut v = serde_json::to_value(&report)?;
        v["iterations"] = serde_json::to_value(&report.front.iterations)?;
        v["quality"] = serde_json::to_value(&summary)?;
        v["edges"] = serde_json::to_value(&band)?;
        let json = serde_json::to_string_pretty(&v)? + "\n";
        mesher::io::write_with(path, |w| std::io::Write::write_all(w, json.as_bytes()))
            .with_context(|| format!("writing {}", path.display()))?;
    }
    crate::note_reoriented(
        report.boundary.faces_reoriented,
        report.boundary.surface_triangles,
    );
    if let Some(phase) = &report.time_limit_hit {
        eprintln!("mesher: time limit passed after the {phase}; the later phases were skipped");
    }
    // A mesh without interior edges (a lone tet) has no band to tell.
    let in_band = if band.edges == 0 {
        "no interior edge".to_string()
    } else {
        format!("{:.1} % edges in [0.6, 1.67]", band.in_band_percent)
    };
    eprintln!(
        "mesher: {} vertices, {} tets, {} iterations{}; worst Q_K {:.2} (Q_t {:.2}), {:.1} % Q_K < 3, {in_band}; {:.3} s",
        report.vertices,
        report.tets,
        report.front.iterations.len(),
        if report.front.converged { "" } else { " (front not empty)" },
        summary.worst_q_k,
        q_t.q_t,
        summary.well_shaped_percent,
        report.time_total
    );
    Ok(ExitCode::SUCCESS)
}

/// Whether `e` refuses the input (a defect of the surface) rather than a failure of
/// the mesher.
fn is_refusal(e: &MeshError) -> bool {
    matches!(
        e,
        MeshError::Boundary(
            BoundaryError::Defective { .. }
                | BoundaryError::VertexOnEntity { .. }
                | BoundaryError::CoincidentVertices { .. }
                | BoundaryError::Kernel(
                    DelaunayError::NonFinite { .. }
                        | DelaunayError::OutOfRange { .. }
                        | DelaunayError::Degenerate { .. }
                )
        )
    )
}

/// Prints the refusal and gives its exit code.
fn refuse(args: &MeshArgs, e: &MeshError) -> ExitCode {
    eprintln!("mesher: refused: {}: {e}", args.surface.display());
    ExitCode::from(EXIT_REFUSED)
}

/// The library parameters from the command line.
fn params_from(args: &MeshArgs) -> Result<Params> {
    let mut params = Params {
        optimize: !args.no_optimize,
        ..Params::default()
    };
    params.optimize_options.max_passes = args.optimize_passes;
    params.optimize_options.bad_quality = args.optimize_above;
    params.front.max_iterations = args.max_iterations;
    params.gradation = args.gradation;
    params.time_limit = args.time_limit;
    params.time_limit_action = match args.time_limit_action {
        TimeLimitArg::Best => TimeLimitAction::Best,
        TimeLimitArg::Error => TimeLimitAction::Error,
    };
    params.front.delta = args.delta;
    params.front.delta_f = args.delta_f;
    params.front.delta_v = args.delta_v;
    params.front.layers = args.front_layers;
    params.front.merge_layers = args.merge_layers;
    params.front.q_accept = args.q_accept;
    params.front.absorb_q_k = args.absorb_q_k;
    params.front.delta_boundary = args.delta_boundary;
    params.front.point.length = args.point_length;
    params.front.seed_spacing = args.seed_spacing;
    params.front.filter_all_vertices = args.filter_all_vertices;
    params.front.point.mode = match args.length {
        Length::Endpoints => LengthMode::EndPoints,
        Length::Piecewise => LengthMode::Piecewise,
    };
    params.front.remedial = match args.remedial {
        RemedialArg::Front => Remedial::Front,
        RemedialArg::All => Remedial::All,
    };
    if let Some(h) = args.size {
        params.size = SizeSpec::Constant(h);
    } else if let Some(bg) = &args.size_map {
        let mesh = mesher::io::read_volume(bg)
            .with_context(|| format!("reading the size map {}", bg.display()))?;
        let sizes = match &args.size_sol {
            Some(sol) => {
                let text = std::fs::read_to_string(sol)
                    .with_context(|| format!("reading {}", sol.display()))?;
                mesher::io::medit::parse_sol(
                    &sol.display().to_string(),
                    &text,
                    mesh.vertices.len(),
                )?
            }
            None => mesh.vertex_sizes.clone().with_context(|| {
                format!("{} has no .sol beside it; give --size-sol", bg.display())
            })?,
        };
        params.size = SizeSpec::Background { mesh, sizes };
    }
    Ok(params)
}
