//! The result of [`Surface::check`](crate::surface::Surface::check): every defect found
//! in an input surface, the shells (connected components) with their nesting, and a
//! human-readable [`Display`](std::fmt::Display) that lists each defect with ids and
//! coordinates (at most [`SHOWN`] per kind, followed by the total count).
//!
//! Defects make [`CheckReport::is_clean`] false. Warnings (shell orientation that does
//! not match the nesting) do not: the nesting alone tells which side is inside.

use serde::Serialize;
use std::fmt;

/// How many items of each kind the human report lists.
pub const SHOWN: usize = 20;

/// A vertex id with its coordinates.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VertexRef {
    /// Vertex index.
    pub vertex: u32,
    /// Its coordinates (`[NaN; 3]` if the index is out of range).
    pub coords: [f64; 3],
}

/// A face id with its vertex ids and (when they exist) coordinates.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FaceRef {
    /// Face index.
    pub face: u32,
    /// Its vertex ids.
    pub vertices: [u32; 3],
    /// Its corner coordinates (NaN for out-of-range ids).
    pub coords: [[f64; 3]; 3],
}

/// An edge with the faces using it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EdgeRef {
    /// The two vertex ids, smaller first.
    pub vertices: [u32; 2],
    /// Their coordinates.
    pub coords: [[f64; 3]; 2],
    /// The faces using the edge, in increasing order.
    pub faces: Vec<u32>,
}

/// A vertex whose incident faces form several fans.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PinchedVertex {
    /// The vertex.
    pub vertex: VertexRef,
    /// Number of edge-connected fans of faces around it (at least 2).
    pub fans: usize,
}

/// A group of faces on the same three vertex ids.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DuplicateFaces {
    /// The faces, in increasing order (at least 2).
    pub faces: Vec<FaceRef>,
}

/// Two faces that intersect improperly.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IntersectingPair {
    /// Lower face id.
    pub a: FaceRef,
    /// Higher face id.
    pub b: FaceRef,
}

/// Result of the self-intersection test.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SelfIntersections {
    /// Number of intersecting face pairs found.
    pub count: usize,
    /// The lowest pairs (by `(a, b)` face ids), at most [`MAX_PAIRS`] of them.
    pub pairs: Vec<IntersectingPair>,
    /// Candidate pairs (box overlaps) tested exactly.
    pub candidates: u64,
    /// The test stopped after [`PAIR_BUDGET`] candidates: `count` is a lower bound and
    /// `pairs` are not necessarily the lowest.
    pub truncated: bool,
}

/// Most intersecting pairs kept in a report.
pub const MAX_PAIRS: usize = 1000;
/// Most candidate pairs tested before giving up (bounds the work on pathological input
/// such as thousands of stacked copies of one face).
pub const PAIR_BUDGET: u64 = 500_000_000;

/// One connected component (faces joined through shared edges).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Shell {
    /// Shell index (shells are numbered by their lowest face).
    pub id: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of distinct vertices.
    pub vertices: usize,
    /// Number of distinct edges.
    pub edges: usize,
    /// Lowest face id of the shell.
    pub first_face: u32,
    /// Every edge has exactly two faces, used in opposite directions, and no vertex is
    /// pinched: a closed oriented 2-manifold.
    pub closed: bool,
    /// Sum of the signed volumes of the tetrahedra (origin, face): positive when the
    /// faces are oriented outwards (counter-clockwise seen from outside). Inexact.
    pub signed_volume: f64,
    /// `V - E + F`.
    pub euler_characteristic: i64,
    /// `(2 - χ) / 2` for closed shells.
    pub genus: Option<i64>,
    /// Bounding box `[min, max]` (NaN when the shell has no finite vertex).
    pub bbox: [[f64; 3]; 2],
    /// For closed shells: the closed shell that directly contains this one, if any.
    pub parent: Option<usize>,
    /// For closed shells: how many closed shells contain this one (0 = outermost).
    /// `None` when unknown (open shell, or containment undecidable).
    pub depth: Option<usize>,
}

/// Everything [`Surface::check`](crate::surface::Surface::check) found.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CheckReport {
    /// Number of vertices of the surface.
    pub num_vertices: usize,
    /// Number of triangles of the surface.
    pub num_triangles: usize,
    /// Vertices with a NaN or infinite coordinate.
    pub non_finite_vertices: Vec<VertexRef>,
    /// Faces with a vertex id `>= num_vertices`.
    pub out_of_range_faces: Vec<FaceRef>,
    /// Faces with a repeated vertex id.
    pub degenerate_faces: Vec<FaceRef>,
    /// Faces with three distinct but exactly collinear vertices.
    pub zero_area_faces: Vec<FaceRef>,
    /// Groups of faces on the same vertex set.
    pub duplicate_faces: Vec<DuplicateFaces>,
    /// Edges with a single face.
    pub open_edges: Vec<EdgeRef>,
    /// Edges with more than two faces.
    pub non_manifold_edges: Vec<EdgeRef>,
    /// Edges with two faces that use it in the same direction.
    pub inconsistent_edges: Vec<EdgeRef>,
    /// Vertices whose faces form several fans.
    pub pinched_vertices: Vec<PinchedVertex>,
    /// Improperly intersecting faces.
    pub self_intersections: SelfIntersections,
    /// Connected components.
    pub shells: Vec<Shell>,
    /// Shell id of each face (`u32::MAX` for a face with an invalid index).
    #[serde(skip)]
    pub face_shell: Vec<u32>,
    /// Vertices used by no face (not a defect).
    pub unreferenced_vertices: usize,
    /// Non-fatal remarks (shell orientation against nesting).
    pub warnings: Vec<String>,
}

impl CheckReport {
    /// No defect of any kind (warnings allowed).
    pub fn is_clean(&self) -> bool {
        self.num_defects() == 0
    }

    /// Total number of defects of all kinds.
    pub fn num_defects(&self) -> usize {
        self.non_finite_vertices.len()
            + self.out_of_range_faces.len()
            + self.degenerate_faces.len()
            + self.zero_area_faces.len()
            + self.duplicate_faces.len()
            + self.open_edges.len()
            + self.non_manifold_edges.len()
            + self.inconsistent_edges.len()
            + self.pinched_vertices.len()
            + self.self_intersections.count
    }

    /// Number of closed shells contained in no other one (separate bodies).
    pub fn num_bodies(&self) -> usize {
        self.shells
            .iter()
            .filter(|s| s.closed && s.depth == Some(0))
            .count()
    }
}

struct P([f64; 3]);

impl fmt::Display for P {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {}, {})", self.0[0], self.0[1], self.0[2])
    }
}

impl fmt::Display for VertexRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "vertex {} at {}", self.vertex, P(self.coords))
    }
}

impl fmt::Display for FaceRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c] = self.vertices;
        write!(
            f,
            "face {} [{a} {b} {c}] {} {} {}",
            self.face,
            P(self.coords[0]),
            P(self.coords[1]),
            P(self.coords[2])
        )
    }
}

impl fmt::Display for EdgeRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "edge {}-{} {} {} faces {:?}",
            self.vertices[0],
            self.vertices[1],
            P(self.coords[0]),
            P(self.coords[1]),
            self.faces
        )
    }
}

/// Writes a titled list: the count, then at most [`SHOWN`] items.
fn list<T>(
    f: &mut fmt::Formatter<'_>,
    title: &str,
    items: &[T],
    show: impl Fn(&mut fmt::Formatter<'_>, &T) -> fmt::Result,
) -> fmt::Result {
    if items.is_empty() {
        return Ok(());
    }
    writeln!(f, "{title}: {}", items.len())?;
    for it in items.iter().take(SHOWN) {
        write!(f, "  ")?;
        show(f, it)?;
        writeln!(f)?;
    }
    if items.len() > SHOWN {
        writeln!(f, "  ... and {} more", items.len() - SHOWN)?;
    }
    Ok(())
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "surface: {} vertices, {} triangles, {} shells",
            self.num_vertices,
            self.num_triangles,
            self.shells.len()
        )?;
        if self.is_clean() {
            writeln!(f, "clean: no defect found")?;
        } else {
            writeln!(f, "NOT clean: {} defects", self.num_defects())?;
        }
        list(
            f,
            "non-finite vertices",
            &self.non_finite_vertices,
            |f, v| write!(f, "{v}"),
        )?;
        list(f, "out-of-range faces", &self.out_of_range_faces, |f, x| {
            write!(f, "{x}")
        })?;
        list(
            f,
            "faces with a repeated vertex",
            &self.degenerate_faces,
            |f, x| write!(f, "{x}"),
        )?;
        list(f, "zero-area faces", &self.zero_area_faces, |f, x| {
            write!(f, "{x}")
        })?;
        list(f, "duplicate faces", &self.duplicate_faces, |f, d| {
            let ids: Vec<u32> = d.faces.iter().map(|x| x.face).collect();
            match d.faces.first() {
                Some(first) => write!(f, "faces {ids:?} same as {first}"),
                None => Ok(()),
            }
        })?;
        list(f, "open edges", &self.open_edges, |f, e| write!(f, "{e}"))?;
        list(f, "non-manifold edges", &self.non_manifold_edges, |f, e| {
            write!(f, "{e}")
        })?;
        list(
            f,
            "inconsistently oriented edges",
            &self.inconsistent_edges,
            |f, e| write!(f, "{e}"),
        )?;
        list(f, "pinched vertices", &self.pinched_vertices, |f, p| {
            write!(f, "{} ({} fans)", p.vertex, p.fans)
        })?;
        self.fmt_intersections(f)?;
        self.fmt_shells(f)?;
        if self.unreferenced_vertices > 0 {
            writeln!(f, "unreferenced vertices: {}", self.unreferenced_vertices)?;
        }
        list(f, "warnings", &self.warnings, |f, w| write!(f, "{w}"))
    }
}

impl CheckReport {
    fn fmt_intersections(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let si = &self.self_intersections;
        if si.truncated {
            writeln!(
                f,
                "self-intersection test TRUNCATED after {} candidate pairs",
                si.candidates
            )?;
        }
        if si.count == 0 {
            return Ok(());
        }
        writeln!(f, "self-intersecting face pairs: {}", si.count)?;
        for p in si.pairs.iter().take(SHOWN) {
            writeln!(f, "  {}\n    x {}", p.a, p.b)?;
        }
        if si.count > SHOWN {
            writeln!(f, "  ... and {} more", si.count - SHOWN)?;
        }
        Ok(())
    }

    fn fmt_shells(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for s in self.shells.iter().take(SHOWN) {
            write!(
                f,
                "shell {}: {} faces, {} vertices, {}, volume {:.6e}",
                s.id,
                s.faces,
                s.vertices,
                if s.closed { "closed" } else { "not closed" },
                s.signed_volume
            )?;
            if let Some(g) = s.genus {
                write!(f, ", genus {g}")?;
            }
            match (s.depth, s.parent) {
                (Some(d), Some(p)) => write!(f, ", inside shell {p} (depth {d})")?,
                (Some(_), None) => write!(f, ", outermost")?,
                _ => {}
            }
            writeln!(f)?;
        }
        if self.shells.len() > SHOWN {
            writeln!(f, "... and {} more shells", self.shells.len() - SHOWN)?;
        }
        Ok(())
    }
}
