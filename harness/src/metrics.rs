//! Metrics of one output mesh against its input surface, all through `mesher::quality`
//! (this module only assembles inputs for it: orientation, face sets, sizes).
//!
//! - Input: `Q_t` (`target_quality`), the fraction of faces whose best reachable `Q_K`
//!   exceeds 3 (`face_best_q_k`), the same two with each face's tet kept inside the
//!   domain (`target_quality_in_domain`: thin parts), the enclosed volume (shells signed by nesting depth),
//!   and the size `h(P) = (shortest + longest edge at P) / 2` at every input vertex
//!   (NOTES.md §3).
//! - Output: [`QualitySummary`] against `Q_t`; normalised edge lengths with the size at
//!   each output vertex interpolated in the paper's control space (§5.3.1: the sizes
//!   of the input vertices on our boundary mesh T(S,F), `mesher::sizing::Background`),
//!   the size of the nearest input vertex where T(S,F) cannot be built (a dirty
//!   surface); the share of interior edges in `[0.6, 1.67]` (`quality::edge_band`);
//!   validity (inverted tets, faces in more than two tets, input triangles kept exactly,
//!   volume ratio).
//! - Orientation: when most tets have negative signed volume (fTetWild writes them so),
//!   every tet is flipped before measuring, and the record says so.

use crate::records::Validity;
use mesher::boundary::{boundary_mesh, BoundaryOptions};
use mesher::quality::{self, EdgeBand, EdgeLengthStats, QualitySummary};
use mesher::sizing::{Background, SizeField};
use mesher::surface::report::CheckReport;
use mesher::{Point, Surface, VolumeMesh};
use std::collections::HashMap;
use std::sync::Arc;

/// What the metrics need from the input surface, computed once per model.
#[derive(Clone, Debug)]
pub struct InputMeasures {
    /// Target quality (paper §8).
    pub q_t: f64,
    /// Fraction of faces with `face_best_q_k > 3`.
    pub hard_face_fraction: f64,
    /// `Q_t` in the domain (`target_quality_in_domain`: each face's best tet kept
    /// inside the domain; None when the surface is not clean and closed).
    pub q_t_domain: Option<f64>,
    /// Fraction of faces whose best tet inside the domain has `Q_K > 3`.
    pub hard_domain_fraction: Option<f64>,
    /// Volume enclosed by the surface (None when its shells are not clean and closed).
    pub enclosed_volume: Option<f64>,
    /// Size `h(P)` per input vertex.
    pub sizes: Vec<f64>,
    /// The control space: `sizes` on our boundary mesh T(S,F), interpolated inside
    /// (None when the surface is not clean and closed, or its boundary mesh fails).
    pub background: Option<Arc<Background>>,
}

/// Everything measured on one output mesh.
#[derive(Clone, Debug)]
pub struct OutputMeasures {
    /// Output vertices.
    pub vertices: usize,
    /// Output tets.
    pub tets: usize,
    /// Quality summary (after orientation normalisation).
    pub quality: QualitySummary,
    /// Normalised edge lengths against the input-derived sizes.
    pub edge_lengths: EdgeLengthStats,
    /// The interior edges (off the output's boundary) in the band `[0.6, 1.67]`.
    pub edge_band: EdgeBand,
    /// Validity checks.
    pub validity: Validity,
    /// True when every tet was flipped because most were negatively oriented.
    pub orientation_flipped: bool,
}

/// Measures the input surface.
pub fn measure_input(surface: &Surface) -> InputMeasures {
    let (v, t) = (&surface.vertices, &surface.triangles);
    let q_t = quality::target_quality(v, t).q_t;
    let hard = t
        .iter()
        .filter(|f| {
            let [a, b, c] = f.map(|i| v[i as usize]);
            quality::face_best_q_k(a, b, c) > quality::WELL_SHAPED_Q_K
        })
        .count();
    let hard_face_fraction = if t.is_empty() {
        0.0
    } else {
        hard as f64 / t.len() as f64
    };
    // One check serves the enclosed volume and the domain's side of each face.
    let report = surface.check();
    let room = quality::target_quality_in_domain(surface, &report);
    InputMeasures {
        q_t,
        hard_face_fraction,
        q_t_domain: room.map(|r| r.q_t),
        hard_domain_fraction: room
            .filter(|_| !t.is_empty())
            .map(|r| r.hard_faces as f64 / t.len() as f64),
        enclosed_volume: enclosed_volume(&report),
        sizes: vertex_sizes(surface),
        background: report.is_clean().then(|| control_space(surface)).flatten(),
    }
}

/// The paper's control space on our boundary mesh T(S,F) of `surface` (checked clean
/// by the caller): what `mesher mesh` interpolates its sizes in.
fn control_space(surface: &Surface) -> Option<Arc<Background>> {
    let options = BoundaryOptions {
        check_input: false,
        ..BoundaryOptions::default()
    };
    let (bm, _) = boundary_mesh(surface, &options).ok()?;
    Background::from_boundary(&bm, surface).ok().map(Arc::new)
}

/// The size at each of `points`: interpolated in the control space when there is one,
/// else the size of the nearest input vertex.
pub fn output_sizes(input: &InputMeasures, surface: &Surface, points: &[Point]) -> Vec<f64> {
    match &input.background {
        Some(bg) => {
            let mut hint = 0u32;
            points.iter().map(|p| bg.size(*p, &mut hint)).collect()
        }
        None => nearest_sizes(surface, &input.sizes, points),
    }
}

/// Enclosed volume: |shell volume| added at even nesting depth, subtracted at odd depth.
fn enclosed_volume(report: &CheckReport) -> Option<f64> {
    if !report.is_clean() {
        return None;
    }
    let mut total = 0.0;
    for s in &report.shells {
        let sign = if s.depth? % 2 == 0 { 1.0 } else { -1.0 };
        total += sign * s.signed_volume.abs();
    }
    Some(total)
}

/// `h(P) = (l_min + l_max) / 2` over the surface edges at each vertex (NaN for a vertex
/// on no edge).
pub fn vertex_sizes(surface: &Surface) -> Vec<f64> {
    let n = surface.vertices.len();
    let (mut lo, mut hi) = (vec![f64::INFINITY; n], vec![f64::NEG_INFINITY; n]);
    for [a, b] in quality::unique_triangle_edges(&surface.triangles) {
        let (a, b) = (a as usize, b as usize);
        if a >= n || b >= n {
            continue;
        }
        let d = surface.vertices[a].distance(surface.vertices[b]);
        for i in [a, b] {
            lo[i] = lo[i].min(d);
            hi[i] = hi[i].max(d);
        }
    }
    lo.iter()
        .zip(&hi)
        .map(|(&l, &h)| {
            if l.is_finite() {
                0.5 * (l + h)
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// Measures an output mesh. `check_boundary`: whether to test that every input triangle
/// is a tet face with exactly the input coordinates (peers that keep the boundary).
pub fn measure_output(
    input: &InputMeasures,
    surface: &Surface,
    mut mesh: VolumeMesh,
    check_boundary: bool,
) -> Result<OutputMeasures, String> {
    let nv = mesh.vertices.len();
    if let Some(t) = mesh
        .tets
        .iter()
        .find(|t| t.iter().any(|&i| i as usize >= nv))
    {
        return Err(format!(
            "tet {t:?} refers to a vertex out of range ({nv} vertices)"
        ));
    }
    let orientation_flipped = normalise_orientation(&mut mesh);
    let quality = quality::summarize(&mesh, Some(input.q_t));
    let sizes = output_sizes(input, surface, &mesh.vertices);
    // The unique edges once: for the lengths, then without the boundary's for the band.
    let edges = quality::unique_tet_edges(&mesh.tets);
    let edge_lengths = quality::edge_length_stats(&mesh.vertices, &edges, &sizes);
    let faces = face_counts(&mesh.tets);
    let boundary: Vec<[u32; 3]> = faces
        .iter()
        .filter(|(_, &n)| n == 1)
        .map(|(f, _)| *f)
        .collect();
    let edge_band = quality::edge_band(
        &mesh.vertices,
        &quality::edges_off_surface(edges, &boundary),
        &sizes,
    );
    let non_manifold_faces = faces.values().filter(|&&c| c > 2).count();
    let boundary_kept = check_boundary.then(|| boundary_kept(surface, &mesh, &faces));
    let volume: f64 = (0..mesh.tets.len())
        .map(|t| quality::signed_volume(&mesh.tet_points(t)))
        .sum();
    let volume_ratio = input
        .enclosed_volume
        .filter(|v| *v > 0.0)
        .map(|v| volume / v);
    let validity = Validity {
        inverted: quality.inverted as usize,
        non_manifold_faces,
        boundary_kept,
        volume_ratio,
        hausdorff: None,
    };
    Ok(OutputMeasures {
        vertices: nv,
        tets: mesh.tets.len(),
        quality,
        edge_lengths,
        edge_band,
        validity,
        orientation_flipped,
    })
}

/// The boundary of a tet mesh: every face used by exactly one tet, as a surface over the
/// vertices it uses, oriented as the tets are (for the Hausdorff distance of peers that move the boundary; interior
/// vertices are dropped so that vertex sampling sees only the boundary).
pub fn boundary_surface(mesh: &VolumeMesh) -> Surface {
    let counts = face_counts(&mesh.tets);
    // Faces of tet (0,1,2,3), outward when it is positively oriented.
    const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let mut faces = Vec::new();
    for t in &mesh.tets {
        for f in FACES {
            let face = f.map(|i| t[i]);
            let mut key = face;
            key.sort_unstable();
            if counts.get(&key) == Some(&1) {
                faces.push(face);
            }
        }
    }
    let mut new_id = vec![u32::MAX; mesh.vertices.len()];
    let mut vertices = Vec::new();
    for f in &mut faces {
        for v in f.iter_mut() {
            let slot = &mut new_id[*v as usize];
            if *slot == u32::MAX {
                *slot = vertices.len() as u32;
                vertices.push(mesh.vertices[*v as usize]);
            }
            *v = *slot;
        }
    }
    Surface {
        vertices,
        triangles: faces,
    }
}

/// Flips every tet (swaps its last two vertices) when more tets are negatively than
/// positively oriented; returns whether it did.
pub fn normalise_orientation(mesh: &mut VolumeMesh) -> bool {
    let (mut neg, mut pos) = (0usize, 0usize);
    for t in 0..mesh.tets.len() {
        let v = quality::signed_volume(&mesh.tet_points(t));
        if v < 0.0 {
            neg += 1;
        } else if v > 0.0 {
            pos += 1;
        }
    }
    if neg <= pos {
        return false;
    }
    for t in &mut mesh.tets {
        t.swap(2, 3);
    }
    true
}

/// How many tets use each face (sorted vertex triple).
fn face_counts(tets: &[[u32; 4]]) -> HashMap<[u32; 3], u32> {
    let mut m = HashMap::with_capacity(tets.len() * 2);
    for t in tets {
        for skip in 0..4 {
            let mut f = [0u32; 3];
            let mut k = 0;
            for (i, &v) in t.iter().enumerate() {
                if i != skip {
                    f[k] = v;
                    k += 1;
                }
            }
            f.sort_unstable();
            *m.entry(f).or_insert(0) += 1;
        }
    }
    m
}

/// Every input triangle is a face of some tet whose vertices have bitwise the input
/// coordinates.
fn boundary_kept(surface: &Surface, mesh: &VolumeMesh, faces: &HashMap<[u32; 3], u32>) -> bool {
    let key = |p: &Point| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let by_coords: HashMap<[u64; 3], u32> = mesh
        .vertices
        .iter()
        .enumerate()
        .map(|(i, p)| (key(p), i as u32))
        .collect();
    surface.triangles.iter().all(|t| {
        let mut f = [0u32; 3];
        for k in 0..3 {
            match surface
                .vertices
                .get(t[k] as usize)
                .and_then(|p| by_coords.get(&key(p)))
            {
                Some(&i) => f[k] = i,
                None => return false,
            }
        }
        f.sort_unstable();
        faces.contains_key(&f)
    })
}

/// The size at each query point: the size of the nearest input vertex (uniform grid).
pub fn nearest_sizes(surface: &Surface, sizes: &[f64], queries: &[Point]) -> Vec<f64> {
    match Grid::new(&surface.vertices) {
        Some(g) => queries
            .iter()
            .map(|q| {
                g.nearest(&surface.vertices, *q)
                    .map_or(f64::NAN, |i| sizes[i])
            })
            .collect(),
        None => vec![f64::NAN; queries.len()],
    }
}

/// A uniform grid over points (about 2 points per cell) for nearest-point queries.
struct Grid {
    lo: Point,
    cell: f64,
    dims: [usize; 3],
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Grid {
    fn new(points: &[Point]) -> Option<Grid> {
        let finite: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].is_finite())
            .collect();
        if finite.is_empty() {
            return None;
        }
        let (mut lo, mut hi) = (points[finite[0]], points[finite[0]]);
        for &i in &finite {
            (lo, hi) = (lo.min(points[i]), hi.max(points[i]));
        }
        let ext = (hi - lo).max(Point::splat(1e-300));
        let vol = ext.x * ext.y * ext.z;
        let cell = ((vol * 2.0 / finite.len() as f64).cbrt()).max(ext.max_element() / 256.0);
        let dims = [0, 1, 2].map(|k| ((ext[k] / cell) as usize + 1).min(1024));
        let mut g = Grid {
            lo,
            cell,
            dims,
            start: vec![0; dims[0] * dims[1] * dims[2] + 1],
            items: vec![0; finite.len()],
        };
        for &i in &finite {
            let c = g.index(g.cell_of(points[i]));
            g.start[c + 1] += 1;
        }
        for c in 1..g.start.len() {
            g.start[c] += g.start[c - 1];
        }
        let mut fill = g.start.clone();
        for &i in &finite {
            let c = g.index(g.cell_of(points[i]));
            g.items[fill[c]] = i;
            fill[c] += 1;
        }
        Some(g)
    }

    fn cell_of(&self, p: Point) -> [usize; 3] {
        [0, 1, 2].map(|k| {
            let c = ((p[k] - self.lo[k]) / self.cell).floor();
            (c.max(0.0) as usize).min(self.dims[k] - 1)
        })
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Nearest point: search shells of cells of growing radius until the best distance
    /// is within the searched radius.
    fn nearest(&self, points: &[Point], q: Point) -> Option<usize> {
        if !q.is_finite() {
            return None;
        }
        let c = self.cell_of(q);
        let max_r = *self.dims.iter().max()?;
        let mut best: Option<(f64, usize)> = None;
        for r in 0..=max_r {
            self.visit_shell(c, r, |i| {
                let d = points[i].distance_squared(q);
                if best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, i));
                }
            });
            if let Some((d, _)) = best {
                if d.sqrt() <= r as f64 * self.cell {
                    break;
                }
            }
        }
        best.map(|(_, i)| i)
    }

    /// Visits the points of the cells at Chebyshev distance exactly `r` from `c`.
    fn visit_shell(&self, c: [usize; 3], r: usize, mut f: impl FnMut(usize)) {
        let r = r as isize;
        let range = |k: usize| {
            let lo = (c[k] as isize - r).max(0);
            let hi = (c[k] as isize + r).min(self.dims[k] as isize - 1);
            lo..=hi
        };
        for z in range(2) {
            for y in range(1) {
                for x in range(0) {
                    let d = (x - c[0] as isize)
                        .abs()
                        .max((y - c[1] as isize).abs())
                        .max((z - c[2] as isize).abs());
                    if d != r {
                        continue;
                    }
                    let i = self.index([x as usize, y as usize, z as usize]);
                    self.items[self.start[i]..self.start[i + 1]]
                        .iter()
                        .for_each(|&p| f(p));
                }
            }
        }
    }
}
