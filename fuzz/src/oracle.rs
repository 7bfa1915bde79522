//! Decoders from the fuzzer's bytes to mesher inputs, and the checks run on each.
//!
//! Every function here panics only when a property of the mesher is violated (the
//! fuzzer reports the panic as a finding); errors the mesher returns are typed results
//! and fine. The same file is compiled into `mesher/tests/fuzz_regress.rs`, which
//! replays the committed inputs under `mesher/tests/regress/<target>/`.

use mesher::delaunay::{triangulate, DelaunayError, DelaunayOptions, Inserted, Kernel};
use mesher::geom::Point;
use mesher::io::{parse_surface, SurfaceFormat};
use mesher::surface::generate::{cube, icosphere};
use mesher::{Params, Surface};
use std::collections::BTreeMap;

/// Largest surface (vertices or triangles) whose check is run after parsing.
const MAX_CHECKED: usize = 4096;
/// Most points of one Delaunay input.
const MAX_POINTS: usize = 256;
/// Points per insertion batch, after which the mesh is validated.
const BATCH: usize = 16;

/// A parser on arbitrary bytes: an error or a surface; a small surface is then checked
/// (topology, self-intersections) and written back, which must not panic either.
pub fn parse(format: SurfaceFormat, data: &[u8]) {
    let Ok(read) = parse_surface("fuzz", data, format) else {
        return;
    };
    let s = read.surface;
    for t in &s.triangles {
        assert!(
            t.iter().all(|&v| (v as usize) < s.vertices.len()),
            "triangle {t:?} out of range"
        );
    }
    if s.vertices.len() <= MAX_CHECKED && s.triangles.len() <= MAX_CHECKED {
        let report = s.check();
        let _ = report.to_string();
    }
}

/// Little-endian reader over the fuzzer's bytes; reads past the end give zeros.
struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    fn i8(&mut self) -> i8 {
        self.u8() as i8
    }

    fn i16(&mut self) -> i16 {
        i16::from_le_bytes([self.u8(), self.u8()])
    }

    fn f64(&mut self) -> f64 {
        let mut b = [0u8; 8];
        for x in &mut b {
            *x = self.u8();
        }
        f64::from_le_bytes(b)
    }

    fn left(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }
}

/// The 30 integer points at distance exactly 3 from the origin (permutations and signs
/// of (1, 2, 2) and (0, 0, 3)): a cospherical set.
fn cospherical(k: u8) -> Point {
    let mut pts = Vec::with_capacity(30);
    for s in 0..8u8 {
        let sg = |bit: u8| if s & bit == 0 { 1.0 } else { -1.0 };
        let (a, b, c) = (sg(1), 2.0 * sg(2), 2.0 * sg(4));
        pts.push(Point::new(a, b, c));
        pts.push(Point::new(b, a, c));
        pts.push(Point::new(b, c, a));
    }
    for axis in 0..3 {
        for sign in [3.0, -3.0] {
            let mut p = [0.0; 3];
            p[axis] = sign;
            pts.push(Point::new(p[0], p[1], p[2]));
        }
    }
    pts[k as usize % pts.len()]
}

/// A point set from bytes. Header: mode (bits 0-1: kind of coordinates, small integer
/// grid / 16-bit grid / raw f64 / cospherical; bit 2: all but the last point in z = 0),
/// a power-of-two scale exponent and an offset (0, 1, 1e3, 1e6, 1e12 on x).
pub fn points(data: &[u8]) -> Vec<Point> {
    let mut b = Bytes { data, pos: 0 };
    let mode = b.u8();
    let scale = 2f64.powi(i32::from(b.i8()) / 2);
    let offset = [0.0, 1.0, 1e3, 1e6, 1e12][b.u8() as usize % 5];
    let mut pts = Vec::new();
    while b.left() > 0 && pts.len() < MAX_POINTS {
        let p = match mode & 3 {
            0 => Point::new(
                f64::from(b.i8() % 4),
                f64::from(b.i8() % 4),
                f64::from(b.i8() % 4),
            ),
            1 => Point::new(f64::from(b.i16()), f64::from(b.i16()), f64::from(b.i16())),
            2 => Point::new(b.f64(), b.f64(), b.f64()),
            _ => cospherical(b.u8()),
        };
        let mut p = p * scale;
        p.x += offset;
        pts.push(p);
    }
    if mode & 4 != 0 {
        let n = pts.len().saturating_sub(1);
        for p in &mut pts[..n] {
            p.z = 0.0;
        }
    }
    pts
}

/// Whether the kernel must accept `p`: finite and within its coordinate range.
fn in_range(p: Point) -> bool {
    p.is_finite() && p.abs().max_element() <= mesher::delaunay::MAX_COORDINATE
}

/// The Delaunay kernel: the first half of the points by `triangulate`, the rest
/// inserted one by one in batches, `validate(true)` after each batch; every point ends
/// on a vertex with its exact coordinates.
pub fn delaunay(data: &[u8]) {
    let pts = points(data);
    let half = pts.len() / 2;
    let tri = match triangulate(&pts[..half], &DelaunayOptions::default()) {
        Ok(t) => t,
        Err(DelaunayError::NonFinite { index, .. } | DelaunayError::OutOfRange { index, .. }) => {
            assert!(!in_range(pts[index]), "{:?} refused", pts[index]);
            return;
        }
        Err(_) => return,
    };
    let mut mesh = tri.mesh;
    mesh.validate(true)
        .expect("triangulate gave an invalid mesh");
    for (p, v) in pts.iter().zip(&tri.vertex_of_input) {
        assert_eq!(mesh.point(*v), *p, "input point lost");
    }
    let mut kernel = Kernel::new();
    for batch in pts[half..].chunks(BATCH) {
        for &p in batch {
            match kernel.insert(&mut mesh, p) {
                Ok(Inserted::New(v) | Inserted::Duplicate(v)) => {
                    assert_eq!(mesh.point(v), p, "inserted point lost");
                }
                Err(DelaunayError::NonFinite { .. } | DelaunayError::OutOfRange { .. }) => {
                    assert!(!in_range(p), "{p:?} refused");
                }
                Err(e) => panic!("insert {p:?}: {e}"),
            }
        }
        mesh.validate(true).expect("invalid after a batch");
    }
}

/// A small closed surface from bytes. Header: base shape (icosphere level 0 or 1, cube
/// with 1 or 2 squares per side), perturbation amplitude, power-of-two scale exponent,
/// offset; then three signed bytes per vertex (its perturbation), then triangles whose
/// orientation is flipped (at most four).
pub fn surface(data: &[u8]) -> Surface {
    let mut b = Bytes { data, pos: 0 };
    let mut s = match b.u8() % 4 {
        0 => icosphere(0),
        1 => icosphere(1),
        2 => cube(1),
        _ => cube(2),
    };
    let amp = f64::from(b.u8()) / 255.0 * 0.2;
    let scale = 2f64.powi(i32::from(b.i8() % 64));
    let offset = [0.0, 1.0, 1e3, 1e6][b.u8() as usize % 4];
    for p in &mut s.vertices {
        let d = Point::new(f64::from(b.i8()), f64::from(b.i8()), f64::from(b.i8()));
        *p = (*p + d * (amp / 128.0)) * scale + Point::splat(offset);
    }
    let n = s.triangles.len();
    for _ in 0..4 {
        if b.left() == 0 {
            break;
        }
        let t = &mut s.triangles[b.u8() as usize % n];
        t.swap(1, 2);
    }
    s
}

/// The whole mesher on [`surface`]: a typed error, or a valid mesh of positive tets
/// with the enclosed volume whose boundary is the input triangles (when no split point
/// is left on the boundary).
pub fn mesh(data: &[u8]) {
    let s = surface(data);
    let Ok((m, r)) = mesher::mesh(&s, &Params::default()) else {
        return;
    };
    m.mesh.validate(false).expect("the mesh is invalid");
    let vm = m.to_volume_mesh();
    let volume = vm.volume();
    let enclosed = r.boundary.enclosed_volume;
    assert!(
        ((volume - enclosed) / enclosed).abs() < 1e-9,
        "volume {volume} vs enclosed {enclosed}"
    );
    if m.boundary_steiner.is_empty() {
        let mut count: BTreeMap<[u32; 3], u32> = BTreeMap::new();
        for t in &vm.tets {
            for f in [
                [t[1], t[2], t[3]],
                [t[0], t[3], t[2]],
                [t[0], t[1], t[3]],
                [t[0], t[2], t[1]],
            ] {
                let mut k = f;
                k.sort_unstable();
                *count.entry(k).or_default() += 1;
            }
        }
        let mut boundary: Vec<[u32; 3]> = count
            .into_iter()
            .filter(|&(_, c)| c == 1)
            .map(|(k, _)| k)
            .collect();
        let mut input: Vec<[u32; 3]> = s
            .triangles
            .iter()
            .map(|t| {
                let mut k = *t;
                k.sort_unstable();
                k
            })
            .collect();
        input.sort_unstable();
        boundary.sort_unstable();
        assert_eq!(boundary, input, "the boundary is not the input");
    }
}
