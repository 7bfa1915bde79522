//! Generated corpus surfaces (no download): geodesic spheres of any size, a box with a
//! cylindrical through-hole, nested spheres (a hollow ball), a thin slab, two cubes
//! sharing an edge (non-manifold), the dirty tier's small defects (a single triangle,
//! a flat fan, a NaN coordinate, an empty file), and midpoint refinement of any surface.
//!
//! Every generator is deterministic: vertices are created in a fixed order and each
//! coordinate is computed from integer lattice indices in one canonical way, so a shared
//! vertex gets bitwise the same coordinates whichever face creates it.

use mesher::surface::generate as base;
use mesher::{Point, Surface};
use std::collections::HashMap;

/// The generator names accepted by `generated:NAME` sources.
pub const NAMES: &[&str] = &[
    "sphere-1k",
    "sphere-10k",
    "sphere-100k",
    "torus",
    "box-with-hole",
    "nested-spheres",
    "thin-slab",
    "two-cubes-edge",
    "single-triangle",
    "flat-fan",
    "nan-vertex",
    "empty-file",
];

/// Generators whose file is not an OFF rendering of a surface: the exact bytes.
pub fn raw_bytes(name: &str) -> Option<Vec<u8>> {
    match name {
        // Zero bytes: a download that failed, a file truncated by a crash.
        "empty-file" => Some(Vec::new()),
        _ => None,
    }
}

/// The surface of generator `name`, or `None` for an unknown name.
pub fn by_name(name: &str) -> Option<Surface> {
    Some(match name {
        // 20 n^2 triangles: 980, 10 580, 103 680.
        "sphere-1k" => geodesic_sphere(7, 1.0),
        "sphere-10k" => geodesic_sphere(23, 1.0),
        "sphere-100k" => geodesic_sphere(72, 1.0),
        // 2 * 64 * 20 = 2560 triangles, edges ~0.1 around the axis and the tube.
        "torus" => base::torus(64, 20, 1.0, 0.3),
        "box-with-hole" => box_with_hole(&HoleBox::default()),
        "nested-spheres" => nested_spheres(),
        // 1 x 1 x 0.02, squares of 0.02: 10 400 triangles.
        "thin-slab" => box_grid([1.0, 1.0, 0.02], [50, 50, 1]),
        "two-cubes-edge" => two_cubes_edge(),
        "single-triangle" => single_triangle(),
        "flat-fan" => flat_fan(),
        "nan-vertex" => nan_vertex(),
        // Rendered by `raw_bytes`; as a surface it is the empty one.
        "empty-file" => Surface::default(),
        _ => return None,
    })
}

/// A geodesic sphere of radius `radius`: each face of the icosahedron split into `n^2`
/// triangles (`20 n^2` in all), vertices projected on the sphere.
pub fn geodesic_sphere(n: usize, radius: f64) -> Surface {
    let n = n.max(1);
    let ico = base::icosphere(0);
    let mut index: HashMap<Vec<(u32, usize)>, u32> = HashMap::new();
    let mut vertices = Vec::new();
    // A lattice point as integer weights on icosahedron vertices, sorted by vertex id:
    // the same point from two faces gets the same key and the same arithmetic.
    let mut vid = |w: [(u32, usize); 3], v: &mut Vec<Point>| -> u32 {
        let mut key: Vec<(u32, usize)> = w.into_iter().filter(|&(_, k)| k > 0).collect();
        key.sort_unstable();
        *index.entry(key.clone()).or_insert_with(|| {
            let p = key.iter().fold(Point::ZERO, |acc, &(i, k)| {
                acc + ico.vertices[i as usize] * (k as f64 / n as f64)
            });
            v.push(p.normalize() * radius);
            v.len() as u32 - 1
        })
    };
    let mut triangles = Vec::with_capacity(20 * n * n);
    for &[a, b, c] in &ico.triangles {
        // Point (i, j): weight i on b, j on c, the rest on a.
        let mut p =
            |i: usize, j: usize, v: &mut Vec<Point>| vid([(a, n - i - j), (b, i), (c, j)], v);
        for i in 0..n {
            for j in 0..n - i {
                let (p0, p1, p2) = (
                    p(i, j, &mut vertices),
                    p(i + 1, j, &mut vertices),
                    p(i, j + 1, &mut vertices),
                );
                triangles.push([p0, p1, p2]);
                if i + j + 1 < n {
                    let p3 = p(i + 1, j + 1, &mut vertices);
                    triangles.push([p1, p3, p2]);
                }
            }
        }
    }
    Surface {
        vertices,
        triangles,
    }
}

/// Parameters of [`box_with_hole`].
#[derive(Clone, Copy, Debug)]
pub struct HoleBox {
    /// Half width of the square box (in x and y).
    pub half_width: f64,
    /// Radius of the hole (along z, through the centre).
    pub radius: f64,
    /// Height (z from 0).
    pub height: f64,
    /// Segments around the axis (a multiple of 8, so the square's corners are vertices).
    pub segments: usize,
    /// Rings between the hole and the square on the top and bottom faces.
    pub rings: usize,
    /// Layers of the outer walls and of the hole's wall.
    pub layers_outer: usize,
    /// Layers of the hole's wall.
    pub layers_inner: usize,
}

impl Default for HoleBox {
    /// A 2 x 2 x 1 box with a hole of radius 0.5: 2784 triangles.
    fn default() -> Self {
        HoleBox {
            half_width: 1.0,
            radius: 0.5,
            height: 1.0,
            segments: 48,
            rings: 4,
            layers_outer: 6,
            layers_inner: 15,
        }
    }
}

/// Vertex key of [`box_with_hole`]: ring (0 = hole, `rings` = square), segment, and the
/// height as a reduced fraction (so top and bottom rings are shared by all walls).
type HoleKey = (usize, usize, usize, usize);

/// A box with a cylindrical through-hole: a closed genus-1 surface, outward oriented.
pub fn box_with_hole(p: &HoleBox) -> Surface {
    let m = p.segments.div_ceil(8).max(1) * 8;
    let nr = p.rings.max(1);
    let mut index: HashMap<HoleKey, u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut vid = |j: usize, k: usize, l: usize, nl: usize, v: &mut Vec<Point>| -> u32 {
        let k = k % m;
        let key = match l {
            0 => (j, k, 0, 1),
            _ if l == nl => (j, k, 1, 1),
            _ => (j, k, l, nl),
        };
        *index.entry(key).or_insert_with(|| {
            let t = std::f64::consts::TAU * k as f64 / m as f64;
            let (s, c) = t.sin_cos();
            let inner = Point::new(c, s, 0.0) * p.radius;
            let outer = Point::new(c, s, 0.0) * (p.half_width / c.abs().max(s.abs()));
            let f = j as f64 / nr as f64;
            let xy = inner * (1.0 - f) + outer * f;
            v.push(Point::new(
                xy.x,
                xy.y,
                p.height * key.2 as f64 / key.3 as f64,
            ));
            v.len() as u32 - 1
        })
    };
    let mut tris = Vec::new();
    let mut quad = |q: [u32; 4], flip: bool| {
        let [a, b, c, d] = q;
        if flip {
            tris.extend_from_slice(&[[a, c, b], [a, d, c]]);
        } else {
            tris.extend_from_slice(&[[a, b, c], [a, c, d]]);
        }
    };
    for k in 0..m {
        for j in 0..nr {
            for (l, flip) in [(1, false), (0, true)] {
                let q = [
                    vid(j, k, l, 1, &mut vertices),
                    vid(j + 1, k, l, 1, &mut vertices),
                ];
                let r = [
                    vid(j + 1, k + 1, l, 1, &mut vertices),
                    vid(j, k + 1, l, 1, &mut vertices),
                ];
                quad([q[0], q[1], r[0], r[1]], flip);
            }
        }
        for (j, nl, flip) in [
            (nr, p.layers_outer.max(1), false),
            (0, p.layers_inner.max(1), true),
        ] {
            for l in 0..nl {
                let q = [
                    vid(j, k, l, nl, &mut vertices),
                    vid(j, k + 1, l, nl, &mut vertices),
                ];
                let r = [
                    vid(j, k + 1, l + 1, nl, &mut vertices),
                    vid(j, k, l + 1, nl, &mut vertices),
                ];
                quad([q[0], q[1], r[0], r[1]], flip);
            }
        }
    }
    Surface {
        vertices,
        triangles: tris,
    }
}

/// A hollow ball: the unit sphere (outward) around a sphere of radius 0.5 oriented
/// inward, edges of about the same length on both (2000 + 500 triangles).
pub fn nested_spheres() -> Surface {
    let mut s = geodesic_sphere(10, 1.0);
    let inner = reversed(geodesic_sphere(5, 0.5));
    append(&mut s, &inner);
    s
}

/// The box `[0, size]` with `counts[i]` squares along axis `i`, two triangles each,
/// outward oriented.
pub fn box_grid(size: [f64; 3], counts: [usize; 3]) -> Surface {
    let n = counts.map(|c| c.max(1));
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut vid = |c: [usize; 3], v: &mut Vec<Point>| -> u32 {
        *index.entry(c).or_insert_with(|| {
            let x = |i: usize| size[i] * c[i] as f64 / n[i] as f64;
            v.push(Point::new(x(0), x(1), x(2)));
            v.len() as u32 - 1
        })
    };
    let mut triangles = Vec::new();
    for axis in 0..3 {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n[axis]] {
            for i in 0..n[u] {
                for j in 0..n[w] {
                    let corner = |di: usize, dj: usize| {
                        let mut c = [0usize; 3];
                        c[axis] = side;
                        c[u] = i + di;
                        c[w] = j + dj;
                        c
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|c| vid(c, &mut vertices));
                    if side == n[axis] {
                        triangles.extend_from_slice(&[[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
                    } else {
                        triangles.extend_from_slice(&[[q[0], q[2], q[1]], [q[0], q[3], q[2]]]);
                    }
                }
            }
        }
    }
    Surface {
        vertices,
        triangles,
    }
}

/// Two unit cubes touching along one edge (x = 1, y = 1): after welding, that edge has
/// four faces, a non-manifold defect.
pub fn two_cubes_edge() -> Surface {
    let mut s = base::cube(2);
    let mut other = base::cube(2);
    for p in &mut other.vertices {
        *p += Point::new(1.0, 1.0, 0.0);
    }
    append(&mut s, &other);
    s
}

/// One triangle: an open surface (three boundary edges), nothing to mesh.
pub fn single_triangle() -> Surface {
    Surface {
        vertices: vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2]],
    }
}

/// A closed cube (12 triangles) whose vertex 5 has a NaN y coordinate, as a writer that
/// divided by zero leaves it.
pub fn nan_vertex() -> Surface {
    let mut s = box_grid([1.0, 1.0, 1.0], [1, 1, 1]);
    if let Some(p) = s.vertices.get_mut(5) {
        p.y = f64::NAN;
    }
    s
}

/// All vertices coplanar: a square fan and the same fan reversed, glued along the
/// boundary. Every edge has two faces, but the surface encloses no volume and its
/// diagonal edges carry four faces (non-manifold).
pub fn flat_fan() -> Surface {
    let s = box_grid([1.0, 1.0, 1.0], [2, 2, 1]);
    // The bottom face of a grid box, doubled: the z = 0 triangles and their reverses.
    let bottom: Vec<[u32; 3]> = s
        .triangles
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&i| s.vertices[i as usize].z == 0.0))
        .collect();
    let mut triangles = bottom.clone();
    triangles.extend(bottom.iter().map(|t| [t[0], t[2], t[1]]));
    Surface {
        vertices: s.vertices,
        triangles,
    }
}

/// `s` with every triangle's orientation reversed.
pub fn reversed(mut s: Surface) -> Surface {
    for t in &mut s.triangles {
        t.swap(1, 2);
    }
    s
}

/// Appends `other`'s vertices and triangles to `s` (no welding).
pub fn append(s: &mut Surface, other: &Surface) {
    let off = s.vertices.len() as u32;
    s.vertices.extend_from_slice(&other.vertices);
    s.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + off)));
}

/// Midpoint subdivision, once: each triangle into four, the new vertex of an edge at its
/// exact midpoint (planar: no projection). Triangle count times 4.
pub fn subdivide(s: &Surface) -> Surface {
    let mut vertices = s.vertices.clone();
    let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(s.triangles.len() * 3 / 2);
    let mut triangles = Vec::with_capacity(s.triangles.len() * 4);
    let mut midpoint = |a: u32, b: u32, v: &mut Vec<Point>| -> u32 {
        *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (p, q) = (v[a.min(b) as usize], v[a.max(b) as usize]);
            v.push((p + q) * 0.5);
            v.len() as u32 - 1
        })
    };
    for &[a, b, c] in &s.triangles {
        let ab = midpoint(a, b, &mut vertices);
        let bc = midpoint(b, c, &mut vertices);
        let ca = midpoint(c, a, &mut vertices);
        triangles.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    Surface {
        vertices,
        triangles,
    }
}

/// Subdivides `s` until it has at least `min_triangles` triangles (at most 12 levels);
/// returns the surface and the number of levels applied.
pub fn refine(s: &Surface, min_triangles: usize) -> (Surface, u32) {
    let mut out = s.clone();
    let mut levels = 0;
    while out.triangles.len() < min_triangles && levels < 12 && !out.triangles.is_empty() {
        out = subdivide(&out);
        levels += 1;
    }
    (out, levels)
}
