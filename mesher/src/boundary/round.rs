//! One recovery round of T(S,F) (paper §4.2): what is present locked, the missing
//! constrained edges recovered, then the missing faces, and what is still missing
//! returned for the next round's Steiner points.

use super::*;

/// Locks what is present, recovers the missing edges, then the missing faces; returns
/// the entities still missing.
pub(super) fn recover_all(
    rec: &mut Recovery,
    surface: &Surface,
    edges: &[(u32, u32, u32)],
    sv: &[VertexId],
    options: &BoundaryOptions,
    report: &mut BoundaryReport,
    round: usize,
) -> Result<Recovered, BoundaryError> {
    let m = |i: u32| sv[i as usize].0;
    let sweep = match all_faces_present(rec, surface, edges, sv) {
        Sweep::All(marks) => {
            return Ok(Recovered {
                stuck: Vec::new(),
                bad: Vec::new(),
                marks: Some(marks),
            })
        }
        Sweep::Some { found, clock } => Some((found, clock)),
        Sweep::NotFresh => None,
    };
    let mut is_surface = vec![false; rec.l.mesh.num_vertices()];
    for v in sv {
        is_surface[v.index()] = true;
    }
    let mut bad: Vec<Point> = Vec::new();
    let mut missing: Vec<(u32, u32, u32)> = Vec::new();
    let mesh_edges: Vec<(u32, u32)> = edges.iter().map(|&(a, b, _)| (m(a), m(b))).collect();
    // Locks kept from an incremental round tell what is present without a sweep;
    // faces are locked again only after the edges (as in a fresh round), so flips for
    // the edges may take some away: those are looked up again (see `faces_now`).
    // The kept sets are reused (a round's locks are most of the next one's).
    let Locks {
        edges: kept_edges,
        faces: mut kept_faces,
        ..
    } = std::mem::take(&mut rec.locks);
    let since = rec.l.stamps.clock;
    rec.locks.edges = kept_edges;
    // The sweep is of the mesh as it is: no change since (nothing recovered yet).
    let swept = sweep
        .as_ref()
        .filter(|s| s.1 == rec.l.stamps.clock)
        .map(|s| &s.0[..]);
    let present = edges_now(rec, &mesh_edges, |k| edges[k].2 as usize, swept);
    for (&(a, b, t), &here) in edges.iter().zip(&present) {
        match here {
            Here::Locked => {}
            Here::Present => lock_edge(rec, m(a), m(b)),
            Here::Missing => missing.push((a, b, t)),
        }
    }
    if round == 0 {
        report.missing_edges = missing.len();
    }

    // Repeated passes: recovering one segment can unblock another.
    let mut stuck_edges = Vec::new();
    // First flips and cones only, then with Steiner points for what is left.
    rec.allow_steiner = false;
    rec.flip_depth = options.flip_depth;
    for pass in 0..2 * MAX_PASSES {
        if missing.is_empty() {
            break;
        }
        if pass == MAX_PASSES {
            rec.allow_steiner = true;
        }
        stuck_edges.clear();
        for &(a, b, t) in &missing {
            match rec.segment_once_per_change(m(a), m(b), options.flip_budget) {
                Ok(()) => lock_edge(rec, m(a), m(b)),
                Err(Stuck::Through(v)) if is_surface.get(v as usize) == Some(&true) => {
                    return Err(on_entity(surface, sv, v, &[a, b]))
                }
                Err(Stuck::Through(v)) => {
                    bad.push(rec.l.p(v));
                    stuck_edges.push((a, b, t));
                }
                Err(Stuck::NoFlip) => stuck_edges.push((a, b, t)),
            }
        }
        let progress = stuck_edges.len() < missing.len();
        std::mem::swap(&mut missing, &mut stuck_edges);
        if !progress {
            if rec.allow_steiner {
                break;
            }
            rec.allow_steiner = true;
        }
    }
    // `missing` now holds what is still missing.
    let mut stuck: Vec<Entity> = missing
        .iter()
        .map(|&(a, b, t)| Entity::Edge(a, b, t))
        .collect();
    let mut faces: Vec<u32> = Vec::new();
    let mut missing_faces = 0;
    let mesh_tris: Vec<[u32; 3]> = surface.triangles.iter().map(|t| t.map(m)).collect();
    let found = faces_now(rec, &kept_faces, since, &mesh_tris);
    let looked_up = rec.l.stamps.clock;
    // Kept faces the edges' flips took away are dropped, the others stay.
    for (k, f) in mesh_tris.iter().enumerate() {
        if found[k] == Here::Missing {
            kept_faces.remove(&sorted_ids(*f));
        }
    }
    rec.locks.faces = kept_faces;
    for (k, f) in mesh_tris.iter().enumerate() {
        if found[k] == Here::Locked {
            continue;
        }
        if found[k] == Here::Present {
            rec.locks.faces.insert(sorted_ids(*f));
        } else {
            missing_faces += 1;
            if [(0, 1), (1, 2), (2, 0)]
                .iter()
                .all(|&(i, j)| rec.has_edge(f[i], f[j]))
            {
                faces.push(k as u32);
            }
        }
    }
    if round == 0 {
        report.missing_faces = missing_faces;
    }
    let mut pending = faces;
    let mut still = Vec::new();
    for _pass in 0..MAX_PASSES {
        if pending.is_empty() {
            break;
        }
        still.clear();
        for &k in &pending {
            let f = surface.triangles[k as usize].map(m);
            match rec.face_once_per_change(f, options.flip_budget) {
                Ok(()) => {
                    rec.locks.faces.insert(sorted_ids(f));
                }
                Err(Stuck::Through(v)) if is_surface.get(v as usize) == Some(&true) => {
                    return Err(on_entity(surface, sv, v, &surface.triangles[k as usize]))
                }
                Err(Stuck::Through(v)) => {
                    bad.push(rec.l.p(v));
                    still.push(k);
                }
                Err(Stuck::NoFlip) => still.push(k),
            }
        }
        let progress = still.len() < pending.len();
        std::mem::swap(&mut pending, &mut still);
        if !progress {
            break;
        }
    }
    // A face's recovery can make a stuck edge as a side effect: that edge is no longer
    // stuck (splitting it would put a point on the edge of a recovered face, which no
    // insertion can take). Its faces, skipped above, are found by the check below or
    // tried again by the next round.
    stuck.retain(|e| match *e {
        Entity::Edge(a, b, _) if rec.has_edge(m(a), m(b)) => {
            lock_edge(rec, m(a), m(b));
            false
        }
        _ => true,
    });
    stuck.extend(pending.iter().map(|&k| Entity::Face(k)));
    if stuck.is_empty() {
        // Safety net: every input triangle must be a face now.
        stuck.extend(
            faces_lost(rec, &mesh_tris, looked_up)
                .into_iter()
                .map(Entity::Face),
        );
    }
    // Faces skipped because an edge is stuck are covered by that edge's entry.
    Ok(Recovered {
        stuck,
        bad,
        marks: None,
    })
}

/// What a recovery round left.
pub(super) struct Recovered {
    /// The entities still missing.
    pub stuck: Vec<Entity>,
    /// Steiner points found exactly on an input entity (to drop).
    pub bad: Vec<Point>,
    /// The face marks when every triangle was a face at once ([`all_faces_present`]).
    pub marks: Option<FaceMarks>,
}
