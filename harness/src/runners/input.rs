//! The input surface as the runners hand it to peers: its shells (connected components)
//! with their nesting from [`mesher::Surface::check`], the bodies to mesh (an outer shell
//! and the shells directly inside it, which are holes), points inside the holes (TetGen),
//! and a double-precision JSON file for the Python peers.

use super::RunError;
use mesher::{Point, Surface};
use serde::Serialize;
use std::path::Path;

/// One closed shell of the input.
#[derive(Clone, Debug, PartialEq)]
pub struct Shell {
    /// Its faces (indices into the surface's triangles), increasing.
    pub faces: Vec<u32>,
    /// How many shells contain it (0 = outermost).
    pub depth: usize,
    /// The shell directly containing it.
    pub parent: Option<usize>,
    /// Signed enclosed volume (positive when its faces point outwards).
    pub signed_volume: f64,
}

/// Reads a surface file (vertices welded as `mesher::io::read_surface` does).
pub fn load(path: &Path) -> Result<Surface, RunError> {
    mesher::io::read_surface(path)
        .map(|r| r.surface)
        .map_err(|e| RunError::Io(format!("reading the input surface: {e}")))
}

/// The shells of a clean surface with their nesting, or why not (defects, open shells).
pub fn shells(surface: &Surface) -> Result<Vec<Shell>, String> {
    let report = surface.check();
    if !report.is_clean() {
        return Err(format!(
            "input surface has {} defects",
            report.num_defects()
        ));
    }
    let comp = face_components(surface);
    let mut faces: Vec<Vec<u32>> = vec![Vec::new(); report.shells.len()];
    let by_first: std::collections::HashMap<u32, usize> = report
        .shells
        .iter()
        .enumerate()
        .map(|(i, s)| (s.first_face, i))
        .collect();
    // A component's label is its lowest face, which is the shell's first face.
    for (f, &c) in comp.iter().enumerate() {
        let i = *by_first
            .get(&c)
            .ok_or_else(|| format!("face {f}: component {c} is not a shell of the report"))?;
        faces[i].push(f as u32);
    }
    let mut out = Vec::with_capacity(faces.len());
    for (s, f) in report.shells.iter().zip(faces) {
        let depth = s
            .depth
            .ok_or_else(|| format!("shell {}: nesting unknown", s.id))?;
        let parent = match s.parent {
            Some(p) => Some(
                report
                    .shells
                    .iter()
                    .position(|t| t.id == p)
                    .ok_or("bad parent")?,
            ),
            None => None,
        };
        out.push(Shell {
            faces: f,
            depth,
            parent,
            signed_volume: s.signed_volume,
        });
    }
    Ok(out)
}

/// For each face, the lowest face of its edge-connected component.
fn face_components(surface: &Surface) -> Vec<u32> {
    let n = surface.triangles.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let mut edges: Vec<([u32; 2], u32)> = Vec::with_capacity(3 * n);
    for (f, t) in surface.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.push(([a.min(b), a.max(b)], f as u32));
        }
    }
    edges.sort_unstable();
    for w in edges.windows(2) {
        if w[0].0 == w[1].0 {
            let (a, b) = (find(&mut parent, w[0].1), find(&mut parent, w[1].1));
            // Keep the lower face as the root, so the root is the component's lowest face.
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi as usize] = lo;
        }
    }
    (0..n as u32).map(|f| find(&mut parent, f)).collect()
}

/// The bodies to mesh: each shell at even depth, followed by its direct children (odd
/// depth), which bound holes.
pub fn volumes(shells: &[Shell]) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    for (i, s) in shells.iter().enumerate() {
        if s.depth % 2 == 0 {
            let mut v = vec![i];
            v.extend((0..shells.len()).filter(|&j| shells[j].parent == Some(i)));
            out.push(v);
        }
    }
    out
}

/// One point inside each hole (shells at odd depth): just inside the shell's largest
/// face, offset by 1e-3 of that face's size. Approximate: a point so close to the face
/// lands in the hole unless another shell passes within that distance.
pub fn hole_points(surface: &Surface, shells: &[Shell]) -> Vec<Point> {
    let mut out = Vec::new();
    for s in shells.iter().filter(|s| s.depth % 2 == 1) {
        let best = s.faces.iter().copied().max_by(|&f, &g| {
            let (a, b) = (
                face_area_normal(surface, f).0,
                face_area_normal(surface, g).0,
            );
            a.total_cmp(&b)
        });
        let Some(f) = best else { continue };
        let (area, n) = face_area_normal(surface, f);
        let [a, b, c] = surface.triangles[f as usize].map(|i| surface.vertices[i as usize]);
        let inward = if s.signed_volume > 0.0 { -n } else { n };
        out.push((a + b + c) / 3.0 + inward * (1e-3 * area.sqrt()));
    }
    out
}

/// Area and unit normal (by vertex order) of face `f`.
fn face_area_normal(surface: &Surface, f: u32) -> (f64, Point) {
    let [a, b, c] = surface.triangles[f as usize].map(|i| surface.vertices[i as usize]);
    let cr = (b - a).cross(c - a);
    let len = cr.length();
    let n = if len > 0.0 { cr / len } else { Point::ZERO };
    (0.5 * len, n)
}

/// Mean length of the unique edges of the surface (0 for an empty surface).
pub fn mean_edge_length(surface: &Surface) -> f64 {
    let edges = mesher::quality::unique_triangle_edges(&surface.triangles);
    let v = &surface.vertices;
    let sum: f64 = edges
        .iter()
        .map(|&[a, b]| v[a as usize].distance(v[b as usize]))
        .sum();
    if edges.is_empty() {
        0.0
    } else {
        sum / edges.len() as f64
    }
}

#[derive(Serialize)]
struct DomainJson<'a> {
    vertices: Vec<[f64; 3]>,
    triangles: &'a [[u32; 3]],
    shells: Vec<&'a [u32]>,
    volumes: Vec<Vec<usize>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    background: Option<&'a super::sizes::Background>,
}

/// Writes the surface with its shells and bodies as JSON (coordinates round-trip exactly
/// as doubles) for `scripts/gmsh_tet.py` and `scripts/ftetwild.py`. Without shells (a
/// dirty surface) all faces form one shell and one body. `background`: the size field
/// of the sized configurations (key `background`: `vertices`, `tets`, `values`).
pub fn write_domain_json(
    path: &Path,
    surface: &Surface,
    shells: Option<&[Shell]>,
    background: Option<&super::sizes::Background>,
) -> Result<(), RunError> {
    let all: Vec<u32> = (0..surface.triangles.len() as u32).collect();
    let (shell_faces, vols) = match shells {
        Some(s) => (s.iter().map(|s| s.faces.as_slice()).collect(), volumes(s)),
        None => (vec![all.as_slice()], vec![vec![0]]),
    };
    let dom = DomainJson {
        vertices: surface.vertices.iter().map(|p| p.to_array()).collect(),
        triangles: &surface.triangles,
        shells: shell_faces,
        volumes: vols,
        background,
    };
    let text = serde_json::to_string(&dom).map_err(|e| RunError::Io(e.to_string()))?;
    std::fs::write(path, text).map_err(|e| RunError::Io(format!("{}: {e}", path.display())))
}
