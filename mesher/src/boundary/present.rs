//! Which input edges and triangles are in the mesh during the recovery (paper §4.2):
//! one sweep over the tets for a fresh round, the locks and local look-ups for an
//! incremental one; the edges and faces found are locked.

use super::local::Local;
use super::recover::Recovery;
use crate::surface::{sorted_ids, Surface};
use crate::tetmesh::VertexId;
use crate::FastSet;

/// The tet faces that are input triangles ([`Local::triangle_faces`]), as of the
/// recovery clock then: [`super::finish`] reuses them while the clock has not moved.
pub(crate) struct FaceMarks {
    pub clock: u32,
    pub marks: Vec<[u32; 4]>,
}

/// What a fresh round's first sweep found ([`all_faces_present`]).
pub(super) enum Sweep {
    /// Not a fresh round (entities are locked already): no sweep.
    NotFresh,
    /// Every input triangle is a face: all locked, and the face marks.
    All(FaceMarks),
    /// Which triangles are faces, as of the recovery clock `clock` ([`edges_now`] reads
    /// the edges' presence from it while the clock has not moved).
    Some { found: Vec<bool>, clock: u32 },
}

/// When no entity is locked yet (a fresh round) and every input triangle is a face of
/// the mesh already (most clean inputs), their edges are edges of it too: every edge
/// and face is locked as present and the face marks are returned; otherwise, with
/// nothing changed, which triangles are faces. One sweep over the tets instead of
/// three (the edges' hash, the faces' look-up, the domain's marks): knot2 11 -> 5.5
/// ms; and where some are missing, the edges' presence without a sweep of their own.
pub(super) fn all_faces_present(
    rec: &mut Recovery,
    surface: &Surface,
    edges: &[(u32, u32, u32)],
    sv: &[VertexId],
) -> Sweep {
    if !(rec.locks.edges.is_empty() && rec.locks.faces.is_empty()) {
        return Sweep::NotFresh;
    }
    let m = |i: u32| sv[i as usize].0;
    let mesh_tris: Vec<[u32; 3]> = surface.triangles.iter().map(|t| t.map(m)).collect();
    let marks = rec.l.triangle_faces(&mesh_tris);
    let found = found_in(&marks, mesh_tris.len());
    if found.contains(&false) {
        return Sweep::Some {
            found,
            clock: rec.l.stamps.clock,
        };
    }
    for &(a, b, _) in edges {
        lock_edge(rec, m(a), m(b));
    }
    for f in &mesh_tris {
        rec.locks.faces.insert(sorted_ids(*f));
    }
    Sweep::All(FaceMarks {
        clock: rec.l.stamps.clock,
        marks,
    })
}

/// Whether an input edge or triangle is in the mesh ([`edges_now`], [`faces_now`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Here {
    /// Locked (kept by an incremental round): present, and nothing to lock.
    Locked,
    /// Present, not locked yet.
    Present,
    Missing,
}

impl From<bool> for Here {
    /// Present or missing (not known to be locked).
    fn from(present: bool) -> Here {
        if present {
            Here::Present
        } else {
            Here::Missing
        }
    }
}

/// Which edges (mesh vertex ids) are in the mesh: from the locks `kept` by an
/// incremental round (exactly the locked entities still present) and a local look-up
/// for the others. When there are none: from the fresh round's sweep `found` (whether
/// each triangle is a face, for the mesh as it is), an edge being present when its
/// triangle (`tri`, per edge) is, and else looked up; without it, one sweep over the
/// mesh.
pub(super) fn edges_now(
    rec: &mut Recovery,
    edges: &[(u32, u32)],
    tri: impl Fn(usize) -> usize,
    found: Option<&[bool]>,
) -> Vec<Here> {
    if rec.locks.edges.is_empty() {
        let Some(found) = found else {
            return rec
                .l
                .edges_present(edges)
                .into_iter()
                .map(Here::from)
                .collect();
        };
        let now: Vec<Here> = edges
            .iter()
            .enumerate()
            .map(|(k, &(a, b))| {
                let here = found.get(tri(k)) == Some(&true) || rec.has_edge(a, b);
                Here::from(here)
            })
            .collect();
        debug_assert!(
            now.iter()
                .zip(rec.l.edges_present(edges))
                .all(|(&h, e)| h == Here::from(e)),
            "the edges of the sweep's faces are not the mesh's"
        );
        return now;
    }
    edges
        .iter()
        .map(|&(a, b)| {
            if rec.locks.edge(a, b) {
                Here::Locked
            } else {
                Here::from(rec.has_edge(a, b))
            }
        })
        .collect()
}

/// Which triangles (mesh vertex ids) are faces of the mesh, as [`edges_now`]: a face
/// `kept` is still there if no change touched its vertices since the clock `since`.
/// (A fresh round's first sweep is not reused here: the edges' flips touch most of
/// the triangles, turbine 76 %, cheese 98 %, fandisk 42 %, and a look-up per touched
/// triangle costs more than this sweep.)
pub(super) fn faces_now(
    rec: &mut Recovery,
    kept: &FastSet<[u32; 3]>,
    since: u32,
    tris: &[[u32; 3]],
) -> Vec<Here> {
    if kept.is_empty() {
        return faces_found(&rec.l, tris)
            .into_iter()
            .map(Here::from)
            .collect();
    }
    tris.iter()
        .map(|&f| {
            if !rec.l.stamps.changed_since(&f, since) && kept.contains(&sorted_ids(f)) {
                Here::Locked
            } else {
                Here::from(rec.has_face(f[0], f[1], f[2]))
            }
        })
        .collect()
}

/// Which triangles (mesh vertex ids) are faces of the mesh.
fn faces_found(l: &Local, tris: &[[u32; 3]]) -> Vec<bool> {
    found_in(&l.triangle_faces(tris), tris.len())
}

/// Which of `n` triangles the face marks of [`Local::triangle_faces`] hold.
fn found_in(marks: &[[u32; 4]], n: usize) -> Vec<bool> {
    let mut found = vec![false; n];
    for &k in marks.iter().flatten() {
        if k != u32::MAX {
            found[k as usize] = true;
        }
    }
    found
}

/// The triangles (mesh vertex ids) that are not faces of the mesh, when every one was
/// either a face or stuck at the clock `looked_up` ([`faces_now`]): only those with a
/// vertex whose tets changed since are looked up again (one sweep over the mesh when
/// they are many).
pub(super) fn faces_lost(rec: &mut Recovery, tris: &[[u32; 3]], looked_up: u32) -> Vec<u32> {
    let changed: Vec<u32> = (0..tris.len() as u32)
        .filter(|&k| rec.l.stamps.changed_since(&tris[k as usize], looked_up))
        .collect();
    if changed.len() > tris.len() / 8 {
        let found = faces_found(&rec.l, tris);
        return (0..tris.len() as u32)
            .filter(|&k| !found[k as usize])
            .collect();
    }
    changed
        .into_iter()
        .filter(|&k| {
            let f = tris[k as usize];
            !rec.has_face(f[0], f[1], f[2])
        })
        .collect()
}

pub(super) fn lock_edge(rec: &mut Recovery, a: u32, b: u32) {
    rec.locks.edges.insert((a.min(b), a.max(b)));
}
