//! The whole mesher (paper §2): boundary mesh T(S,F) (§4), control space (§5.3.1),
//! field points by the advancing front (§5), then optimisation (§6).
//!
//! [`mesh`] takes a closed surface and [`Params`] and returns the [`Meshed`] domain
//! (tets, regions, sizes) and a [`Report`] with the front's convergence series.

use crate::boundary::{boundary_mesh, BoundaryError, BoundaryOptions, BoundaryReport};
use crate::delaunay::Constraints;
use crate::front::{advance, FieldMesh, FrontError, FrontParams, FrontReport, Iteration};
use crate::limit::{Deadline, TimeLimitAction};
use crate::optimize::{optimize, Domain, OptimizeOptions, OptimizeReport};
use crate::sizing::{Background, SizeField, SizingError};
use crate::surface::Surface;
use crate::tetmesh::{TetMesh, VertexId, FACE_VERTICES};
use crate::volume::VolumeMesh;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Where the sizes come from.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum SizeSpec {
    /// The paper's control space on T(S,F) (§5.3.1).
    #[default]
    Boundary,
    /// One size everywhere.
    Constant(f64),
    /// A user background mesh with one size per vertex (§7).
    Background {
        /// The background mesh.
        mesh: VolumeMesh,
        /// Size per vertex of `mesh`.
        sizes: Vec<f64>,
    },
}

/// Parameters of [`mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// The boundary mesh.
    pub boundary: BoundaryOptions,
    /// The front.
    pub front: FrontParams,
    /// The size map.
    pub size: SizeSpec,
    /// Gradation control of the boundary-derived sizes ([`SizeSpec::Boundary`]): at
    /// most this growth of the size per unit length along T(S,F)'s edges; `None`, the
    /// paper's sizes as they are.
    pub gradation: Option<f64>,
    /// Run the optimisation (paper §6).
    pub optimize: bool,
    /// Its parameters.
    pub optimize_options: OptimizeOptions,
    /// Wall-clock limit in seconds, checked between the phases.
    pub time_limit: Option<f64>,
    /// What happens past the limit: the best valid mesh so far, or an error.
    pub time_limit_action: TimeLimitAction,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            boundary: BoundaryOptions::default(),
            front: FrontParams::default(),
            size: SizeSpec::default(),
            gradation: None,
            optimize: true,
            optimize_options: OptimizeOptions::default(),
            time_limit: None,
            time_limit_action: TimeLimitAction::default(),
        }
    }
}

/// Why no mesh was made.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The boundary mesh failed.
    #[error(transparent)]
    Boundary(#[from] BoundaryError),
    /// The size map is unusable.
    #[error(transparent)]
    Sizing(#[from] SizingError),
    /// The front failed.
    #[error(transparent)]
    Front(#[from] FrontError),
    /// The time limit passed (with [`TimeLimitAction::Error`]).
    #[error("time limit of {limit} s passed after the {phase} ({elapsed:.3} s)")]
    TimeLimit {
        /// The limit, seconds.
        limit: f64,
        /// Seconds elapsed when it was checked.
        elapsed: f64,
        /// The last phase done.
        phase: String,
    },
}

/// Counters and timings of one run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Report {
    /// The boundary mesh.
    pub boundary: BoundaryReport,
    /// The front, with its per-iteration series.
    pub front: FrontReport,
    /// Vertices of the domain mesh.
    pub vertices: usize,
    /// Tets of the domain mesh.
    pub tets: usize,
    /// Seconds: boundary mesh.
    pub time_boundary: f64,
    /// Seconds: control space.
    pub time_sizing: f64,
    /// Seconds: front.
    pub time_front: f64,
    /// The optimisation, when it ran: histograms before and after, per-pass counts.
    pub optimize: Option<OptimizeReport>,
    /// Seconds: optimisation.
    pub time_optimize: f64,
    /// Seconds: all.
    pub time_total: f64,
    /// The time limit passed after this phase and the later ones were skipped.
    pub time_limit_hit: Option<String>,
}

/// The meshed domain.
#[derive(Clone, Debug)]
pub struct Meshed {
    /// The whole box mesh (outside tets have region 0).
    pub mesh: TetMesh,
    /// Region per tet slot.
    pub region: Vec<u32>,
    /// Size at every vertex.
    pub h: Vec<f64>,
    /// Mesh vertex of each input vertex.
    pub surface_vertex: Vec<VertexId>,
    /// Steiner points left on input edges (mesh vertices).
    pub boundary_steiner: Vec<VertexId>,
    /// The boundary faces: the input triangles, or their pieces where an edge is split.
    pub faces: Vec<[VertexId; 3]>,
}

/// Meshes the domain bounded by `surface`.
pub fn mesh(surface: &Surface, params: &Params) -> Result<(Meshed, Report), MeshError> {
    mesh_with_progress(surface, params, &mut |_| {})
}

/// [`mesh`], calling `progress` after every front iteration.
pub fn mesh_with_progress(
    surface: &Surface,
    params: &Params,
    progress: &mut dyn FnMut(&Iteration),
) -> Result<(Meshed, Report), MeshError> {
    let t0 = Instant::now();
    let deadline = Deadline::new(t0, params.time_limit, params.time_limit_action);
    let mut time_limit_hit = None;
    let (bm, boundary) = boundary_mesh(surface, &params.boundary)?;
    let time_boundary = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let field: Box<dyn SizeField> = match &params.size {
        SizeSpec::Boundary => match params.gradation {
            None => Box::new(Background::from_boundary(&bm, surface)?),
            Some(g) => Box::new(Background::from_boundary_graded(&bm, surface, g)?),
        },
        SizeSpec::Constant(h) => Box::new(crate::sizing::constant(*h)?),
        SizeSpec::Background { mesh, sizes } => {
            Box::new(Background::from_volume(mesh, sizes.clone())?)
        }
    };
    let mut fm = field_mesh(bm.mesh, &bm.region, &bm.constrained, field.as_ref());
    let time_sizing = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let front = if deadline.go_on("boundary mesh", &mut time_limit_hit)? {
        advance(&mut fm, field.as_ref(), &params.front, progress)?
    } else {
        FrontReport::default()
    };
    let time_front = t2.elapsed().as_secs_f64();
    let mut meshed = Meshed {
        mesh: fm.mesh,
        region: fm.cons.region,
        h: fm.h,
        surface_vertex: bm.surface_vertex,
        boundary_steiner: bm.boundary_steiner,
        faces: bm.faces,
    };
    let t3 = Instant::now();
    let optimize = (params.optimize && deadline.go_on("front", &mut time_limit_hit)?)
        .then(|| optimize_meshed(&mut meshed, &bm.box_corners, field.as_ref(), params));
    let time_optimize = t3.elapsed().as_secs_f64();
    let tets = meshed.domain_tets().count();
    let report = Report {
        boundary,
        front,
        vertices: meshed.to_volume_mesh().vertices.len(),
        tets,
        time_boundary,
        time_sizing,
        time_front,
        optimize,
        time_optimize,
        time_total: t0.elapsed().as_secs_f64(),
        time_limit_hit,
    };
    Ok((meshed, report))
}

/// Vertices per parallel chunk of the size lookups after the optimisation.
const SIZE_CHUNK: usize = 4096;

/// Optimises the meshed domain in place (boundary vertices and faces fixed); the free
/// vertices, moved or inserted, get their size from the field again.
fn optimize_meshed(
    meshed: &mut Meshed,
    corners: &[VertexId],
    field: &dyn SizeField,
    params: &Params,
) -> OptimizeReport {
    let mut fixed = vec![false; meshed.mesh.num_vertices()];
    for v in meshed
        .surface_vertex
        .iter()
        .chain(&meshed.boundary_steiner)
        .chain(corners)
    {
        fixed[v.index()] = true;
    }
    let mut domain = Domain {
        constrained: meshed.faces.iter().map(|f| f.map(|v| v.0)).collect(),
        mesh: std::mem::take(&mut meshed.mesh),
        region: std::mem::take(&mut meshed.region),
        fixed,
    };
    let report = optimize(&mut domain, &params.optimize_options);
    meshed.mesh = domain.mesh;
    meshed.region = domain.region;
    // Every free vertex gets the size at where it is now (the smoothing moved many),
    // so that the reported edge lengths are those of the output, as the harness
    // measures them.
    // In parallel, by chunks of consecutive vertices (inserted near one another), each
    // chunk's walks from where its previous one ended.
    let points = meshed.mesh.points();
    meshed.h.resize(points.len(), f64::NAN);
    meshed
        .h
        .par_chunks_mut(SIZE_CHUNK)
        .zip(points.par_chunks(SIZE_CHUNK))
        .enumerate()
        .for_each(|(k, (h, p))| {
            let mut hint = 0u32;
            for (i, (h, p)) in h.iter_mut().zip(p).enumerate() {
                if !domain
                    .fixed
                    .get(k * SIZE_CHUNK + i)
                    .copied()
                    .unwrap_or(false)
                {
                    *h = field.size(*p, &mut hint);
                }
            }
        });
    report
}

/// The front's mesh from T(S,F): constraint masks from the constrained faces, sizes at
/// the vertices from the field.
fn field_mesh(
    mesh: TetMesh,
    region: &[u32],
    constrained: &std::collections::HashMap<[u32; 3], u32>,
    field: &dyn SizeField,
) -> FieldMesh {
    let n = mesh.num_slots();
    let mut cons = Constraints {
        face_mask: vec![0; n],
        region: region.to_vec(),
    };
    cons.resize(n);
    for t in mesh.tets() {
        let v = mesh.raw_tet(t.0);
        let adj = mesh.raw_adj(t.0);
        for (i, f) in FACE_VERTICES.iter().enumerate() {
            // The domain's regions are flood-filled up to the constrained faces, so a
            // face with the same region on both sides is not one: no lookup.
            if cons.region[t.index()] == cons.region[(adj[i] >> 2) as usize] {
                continue;
            }
            let mut key = [v[f[0]], v[f[1]], v[f[2]]];
            key.sort_unstable();
            if constrained.contains_key(&key) {
                cons.face_mask[t.index()] |= 1 << i;
            }
        }
    }
    let mut hint = 0u32;
    let (h, hints) = mesh
        .points()
        .iter()
        .map(|&p| (field.size(p, &mut hint), hint))
        .unzip();
    FieldMesh {
        mesh,
        cons,
        h,
        hint: hints,
    }
}

pub use crate::quality::band::EdgeBand;

impl Meshed {
    /// Finite tets with a non-zero region, in slot order.
    pub fn domain_tets(&self) -> impl Iterator<Item = crate::tetmesh::TetId> + '_ {
        self.mesh
            .finite_tets()
            .filter(|t| self.region[t.index()] != 0)
    }

    /// The domain as an exchange mesh: the input vertices first, in input order, then the
    /// other vertices in mesh order; tets with their region; the input triangles.
    pub fn to_volume_mesh(&self) -> VolumeMesh {
        let (vm, _) = self.volume_and_sizes();
        vm
    }

    /// [`Self::to_volume_mesh`] and the size at each of its vertices.
    pub fn volume_and_sizes(&self) -> (VolumeMesh, Vec<f64>) {
        let mut first = self.surface_vertex.clone();
        first.extend_from_slice(&self.boundary_steiner);
        let (vm, origin) =
            crate::volume::export_domain(&self.mesh, &self.region, &first, &self.faces);
        let sizes = origin.iter().map(|v| self.h[v.index()]).collect();
        (vm, sizes)
    }

    /// Normalised lengths of the interior edges with respect to the vertex sizes.
    pub fn edge_band(&self) -> EdgeBand {
        let (vm, sizes) = self.volume_and_sizes();
        EdgeBand::of(&vm, &sizes)
    }
}
