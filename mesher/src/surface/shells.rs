//! Shells of [`Surface::check`](crate::surface::Surface::check): connected components of
//! faces joined through shared edges, their size, signed volume, Euler characteristic
//! and genus, and how closed shells nest.
//!
//! Nesting uses exact ray parity (Jordan-Brouwer: a point not on a closed surface is
//! inside iff a ray from it crosses the surface an odd number of times). The ray is the
//! segment from a vertex `p` of the tested shell to a point `q` beyond the other shell's
//! bounding box; every crossing is decided with exact `orient3d` signs
//! ([`segment_crossing`]), and a ray that touches an edge, a vertex or lies in a face's
//! plane is discarded and another direction is tried (a fixed list of [`DIRECTIONS`]
//! directions, so the work is bounded). If `p` lies on the other shell (touching
//! shells, also reported as self-intersections) the next vertex is tried. Zero-area
//! faces are skipped: they have no interior for a ray to cross.
//!
//! With non-intersecting shells containment is a tree; each shell's parent is its
//! deepest container. Expected orientation alternates with depth: shells at even depth
//! bound material from outside (positive volume), at odd depth they bound cavities
//! (negative volume); a mismatch is reported as a warning, since the nesting already
//! tells the sides.

use super::bvh::{Box3, Bvh};
use super::intersect::{segment_crossing, Crossing};
use super::report::{CheckReport, Shell};
use super::topology::{find, EdgeTable, FaceStatus};
use super::Surface;
use crate::geom::Point;

/// Number of ray directions tried per query point.
const DIRECTIONS: usize = 12;
/// Number of vertices of a shell tried as query points.
const QUERY_VERTICES: usize = 4;

/// Face ids of each shell (by shell id).
pub(crate) struct ShellFaces {
    /// `start[s]..start[s + 1]` indexes `faces` for shell `s`.
    pub start: Vec<u32>,
    /// Face ids, increasing within a shell.
    pub faces: Vec<u32>,
}

impl ShellFaces {
    fn of(&self, s: usize) -> &[u32] {
        &self.faces[self.start[s] as usize..self.start[s + 1] as usize]
    }
}

/// Labels faces by connected component; returns the shell id per face (`u32::MAX` for
/// faces with invalid indices) and the face lists.
fn components(s: &Surface, st: &FaceStatus, et: &EdgeTable) -> (Vec<u32>, ShellFaces) {
    let nf = s.triangles.len();
    let mut parent: Vec<u32> = (0..nf as u32).collect();
    for &(a, b) in &et.groups {
        let first = et.half[a as usize].face;
        for h in &et.half[a as usize + 1..b as usize] {
            let x = find(&mut parent, first);
            let y = find(&mut parent, h.face);
            if x != y {
                parent[x.max(y) as usize] = x.min(y);
            }
        }
    }
    // Roots are the lowest face of each component, so numbering in face order is
    // numbering by lowest face.
    let mut label = vec![u32::MAX; nf];
    let mut count = 0u32;
    let mut sizes: Vec<u32> = Vec::new();
    for f in 0..nf {
        if !st.index_ok[f] {
            continue;
        }
        let r = find(&mut parent, f as u32) as usize;
        if label[r] == u32::MAX {
            label[r] = count;
            count += 1;
            sizes.push(0);
        }
        label[f] = label[r];
        sizes[label[f] as usize] += 1;
    }
    let mut start = vec![0u32; count as usize + 1];
    for (i, n) in sizes.iter().enumerate() {
        start[i + 1] = start[i] + n;
    }
    let mut fill = start.clone();
    let mut faces = vec![0u32; start[count as usize] as usize];
    for (f, &l) in label.iter().enumerate() {
        if l != u32::MAX {
            faces[fill[l as usize] as usize] = f as u32;
            fill[l as usize] += 1;
        }
    }
    (label, ShellFaces { start, faces })
}

/// Computes the shells, their nesting and orientation warnings into `r`.
pub(crate) fn shells(s: &Surface, st: &FaceStatus, et: &EdgeTable, r: &mut CheckReport) {
    let (label, sf) = components(s, st, et);
    let n = sf.start.len() - 1;
    let mut edges = vec![0usize; n];
    let mut closed = vec![true; n];
    for &(a, b) in &et.groups {
        let run = &et.half[a as usize..b as usize];
        let sh = label[run[0].face as usize] as usize;
        edges[sh] += 1;
        if run.len() != 2 || run[0].forward == run[1].forward {
            closed[sh] = false;
        }
    }
    let mut pinched = vec![false; n];
    let mut pinched_v = vec![false; s.vertices.len()];
    for p in &r.pinched_vertices {
        pinched_v[p.vertex.vertex as usize] = true;
    }
    for sh in 0..n {
        let faces = sf.of(sh);
        let mut verts: Vec<u32> = faces
            .iter()
            .flat_map(|&f| s.triangles[f as usize])
            .collect();
        verts.sort_unstable();
        verts.dedup();
        pinched[sh] = verts.iter().any(|&v| pinched_v[v as usize]);
        let chi = verts.len() as i64 - edges[sh] as i64 + faces.len() as i64;
        let genus = (closed[sh] && !pinched[sh] && chi <= 2 && chi % 2 == 0).then(|| (2 - chi) / 2);
        r.shells.push(Shell {
            id: sh,
            faces: faces.len(),
            vertices: verts.len(),
            edges: edges[sh],
            first_face: faces[0],
            closed: closed[sh],
            signed_volume: signed_volume(s, faces),
            euler_characteristic: chi,
            genus,
            bbox: bbox(s, &verts),
            parent: None,
            depth: None,
        });
    }
    nesting(s, st, &sf, r);
    r.face_shell = label;
}

/// Sum of the signed volumes of the tetrahedra (origin, face) over finite faces.
fn signed_volume(s: &Surface, faces: &[u32]) -> f64 {
    let mut v = 0.0;
    for &f in faces {
        let [a, b, c] = s.triangles[f as usize].map(|i| s.vertices[i as usize]);
        let t = a.dot(b.cross(c));
        if t.is_finite() {
            v += t;
        }
    }
    v / 6.0
}

/// Box of the finite vertices among `verts`, NaN if none.
fn bbox(s: &Surface, verts: &[u32]) -> [[f64; 3]; 2] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &v in verts {
        let p = s.vertices[v as usize];
        if p.is_finite() {
            for (k, x) in p.to_array().into_iter().enumerate() {
                lo[k] = lo[k].min(x);
                hi[k] = hi[k].max(x);
            }
        }
    }
    if lo[0] > hi[0] {
        return [[f64::NAN; 3]; 2];
    }
    [lo, hi]
}

/// Box `a` lies within box `b` (closed).
fn box_within(a: &[[f64; 3]; 2], b: &[[f64; 3]; 2]) -> bool {
    (0..3).all(|k| a[0][k] >= b[0][k] && a[1][k] <= b[1][k])
}

/// Fills `parent`/`depth` of closed shells and the orientation warnings.
fn nesting(s: &Surface, st: &FaceStatus, sf: &ShellFaces, r: &mut CheckReport) {
    let n = r.shells.len();
    // A shell takes part if closed with all its faces finite.
    let usable: Vec<bool> = (0..n)
        .map(|i| {
            r.shells[i].closed
                && !r.shells[i].bbox[0][0].is_nan()
                && sf.of(i).iter().all(|&f| {
                    let t = s.triangles[f as usize];
                    t.iter().all(|&v| s.vertices[v as usize].is_finite())
                })
        })
        .collect();
    let mut containers: Vec<Option<Vec<usize>>> = vec![None; n];
    // Candidate containers come from a tree of shell boxes, so many small side-by-side
    // bodies cost O(k log k) and not O(k^2).
    let boxes: Vec<(u32, Box3)> = (0..n)
        .filter(|&b| usable[b])
        .map(|b| {
            let [min, max] = r.shells[b].bbox;
            (b as u32, Box3 { min, max })
        })
        .collect();
    let tree = Bvh::build(boxes);
    let mut cand: Vec<usize> = Vec::new();
    for a in (0..n).filter(|&a| usable[a]) {
        let mut inside = Some(Vec::new());
        let [min, max] = r.shells[a].bbox;
        cand.clear();
        tree.query_after(0, &Box3 { min, max }, |b| cand.push(b as usize));
        cand.sort_unstable();
        for &b in cand.iter().filter(|&&b| b != a) {
            if !box_within(&r.shells[a].bbox, &r.shells[b].bbox) {
                continue;
            }
            match shell_inside(s, st, sf.of(a), sf.of(b), &r.shells[b].bbox) {
                Some(true) => {
                    if let Some(v) = inside.as_mut() {
                        v.push(b);
                    }
                }
                Some(false) => {}
                None => inside = None,
            }
        }
        containers[a] = inside;
    }
    for a in 0..n {
        let Some(cs) = &containers[a] else { continue };
        let depth_of = |b: usize| containers[b].as_ref().map_or(0, |v| v.len());
        r.shells[a].depth = Some(cs.len());
        r.shells[a].parent = cs
            .iter()
            .copied()
            .max_by_key(|&b| (depth_of(b), usize::MAX - b));
    }
    orientation_warnings(r);
}

/// Warns about closed shells whose signed volume does not have the sign their depth
/// calls for.
fn orientation_warnings(r: &mut CheckReport) {
    for sh in r.shells.iter() {
        let Some(d) = sh.depth else { continue };
        let (want, what) = if d % 2 == 0 {
            (1.0, "positive (outer boundary of a body)")
        } else {
            (-1.0, "negative (boundary of a cavity)")
        };
        if sh.signed_volume * want <= 0.0 {
            r.warnings.push(format!(
                "shell {} at nesting depth {d} has signed volume {:.6e}, expected {what}: its faces are oriented the other way",
                sh.id, sh.signed_volume
            ));
        }
    }
}

/// Whether shell `a` (faces) lies inside closed shell `b`; `None` if undecided.
fn shell_inside(
    s: &Surface,
    st: &FaceStatus,
    a: &[u32],
    b: &[u32],
    bbox_b: &[[f64; 3]; 2],
) -> Option<bool> {
    let mut tried: Vec<u32> = Vec::with_capacity(QUERY_VERTICES);
    for &f in a {
        for &v in &s.triangles[f as usize] {
            if tried.len() >= QUERY_VERTICES {
                return None;
            }
            if tried.contains(&v) {
                continue;
            }
            tried.push(v);
            if let Some(ans) = point_inside(s, st, s.vertices[v as usize], b, bbox_b) {
                return Some(ans);
            }
        }
    }
    None
}

/// Ray parity of `p` against the closed shell with faces `b`; `None` when `p` is on
/// the shell or every direction was degenerate.
pub(crate) fn point_inside(
    s: &Surface,
    st: &FaceStatus,
    p: Point,
    b: &[u32],
    bbox_b: &[[f64; 3]; 2],
) -> Option<bool> {
    let lo = Point::from_array(bbox_b[0]);
    let hi = Point::from_array(bbox_b[1]);
    if !p.is_finite() || (0..3).any(|k| p[k] < lo[k] || p[k] > hi[k]) {
        return Some(false);
    }
    let reach = 2.0 * ((hi - lo).length() + 1.0);
    'dirs: for k in 0..DIRECTIONS {
        let q = p + direction(k) * reach;
        if (0..3).all(|i| q[i] >= lo[i] && q[i] <= hi[i]) {
            continue;
        }
        let (qlo, qhi) = (p.min(q), p.max(q));
        let mut odd = false;
        for &f in b {
            if !st.geom_ok[f as usize] {
                continue;
            }
            let t = s.triangles[f as usize].map(|v| s.vertices[v as usize]);
            let tlo = t[0].min(t[1]).min(t[2]);
            let thi = t[0].max(t[1]).max(t[2]);
            if (0..3).any(|i| tlo[i] > qhi[i] || thi[i] < qlo[i]) {
                continue;
            }
            match segment_crossing(p, q, &t) {
                Crossing::Miss => {}
                Crossing::Proper => odd = !odd,
                Crossing::AtStart => return None,
                Crossing::Degenerate => continue 'dirs,
            }
        }
        return Some(odd);
    }
    None
}

/// The `k`-th ray direction: points spread on the sphere by the golden angle, with
/// irrational-looking components so rays rarely hit edges of axis-aligned models.
fn direction(k: usize) -> Point {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let z = 1.0 - (2.0 * k as f64 + 1.0) / DIRECTIONS as f64;
    let r = (1.0 - z * z).sqrt();
    let th = golden * k as f64 + 0.123_456_789;
    Point::new(r * th.cos(), r * th.sin(), z + 0.017_320_508)
}
