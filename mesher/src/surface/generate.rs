//! Deterministic generated surfaces for tests, benchmarks and the corpus: an icosphere,
//! a torus and a subdivided cube, all closed, manifold and outward oriented.

use super::Surface;
use crate::geom::Point;
use std::collections::HashMap;

/// The unit icosphere: an icosahedron subdivided `level` times (20 * 4^level
/// triangles), vertices projected on the sphere.
pub fn icosphere(level: u32) -> Surface {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<Point> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Point::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level.min(10) {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(triangles.len() * 4);
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<Point>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        for &[a, b, c] in &triangles {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    Surface {
        vertices,
        triangles,
    }
}

/// A torus around the z axis with `nu` segments around the axis and `nv` around the
/// tube, radii `major` and `minor`.
pub fn torus(nu: usize, nv: usize, major: f64, minor: f64) -> Surface {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let mut vertices = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = i as f64 / nu as f64 * std::f64::consts::TAU;
        for j in 0..nv {
            let v = j as f64 / nv as f64 * std::f64::consts::TAU;
            let r = major + minor * v.cos();
            vertices.push(Point::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Surface {
        vertices,
        triangles,
    }
}

/// A hollow body: the shell `outer` around `inner` scaled by `scale` about the origin
/// and reversed (facing the cavity), so that the domain is the space between them.
pub fn hollow(outer: &Surface, inner: &Surface, scale: f64) -> Surface {
    let n = outer.vertices.len() as u32;
    let mut s = outer.clone();
    s.vertices.extend(inner.vertices.iter().map(|p| *p * scale));
    s.triangles.extend(
        inner
            .triangles
            .iter()
            .map(|t| [t[0] + n, t[2] + n, t[1] + n]),
    );
    s
}

/// The cube `[0, 1]^3` with each face split into `n x n` squares of two triangles.
pub fn cube(n: usize) -> Surface {
    let n = n.max(1);
    let mut vertices = Vec::new();
    let mut index: HashMap<(usize, usize, usize), u32> = HashMap::new();
    let mut vid = |c: (usize, usize, usize), v: &mut Vec<Point>| -> u32 {
        *index.entry(c).or_insert_with(|| {
            let s = n as f64;
            v.push(Point::new(c.0 as f64 / s, c.1 as f64 / s, c.2 as f64 / s));
            v.len() as u32 - 1
        })
    };
    let mut triangles = Vec::new();
    // Each face: an axis, a side, and two in-plane axes ordered for an outward normal.
    for axis in 0..3 {
        for side in [0, n] {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: usize, dj: usize| {
                        let mut c = [0usize; 3];
                        c[axis] = side;
                        c[u] = i + di;
                        c[w] = j + dj;
                        (c[0], c[1], c[2])
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    let q: Vec<u32> = q.iter().map(|&c| vid(c, &mut vertices)).collect();
                    if side == n {
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    } else {
                        triangles.push([q[0], q[2], q[1]]);
                        triangles.push([q[0], q[3], q[2]]);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_volume(s: &Surface) -> f64 {
        s.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| s.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn generated_surfaces_are_outward_and_sized() {
        let s = icosphere(3);
        assert_eq!(s.triangles.len(), 20 * 64);
        assert_eq!(s.vertices.len(), 10 * 64 + 2);
        let v = signed_volume(&s);
        assert!(v > 4.0 && v < 4.19, "{v}");
        let c = cube(3);
        assert!((signed_volume(&c) - 1.0).abs() < 1e-12);
        assert_eq!(c.vertices.len(), 6 * 9 + 2);
        let t = torus(24, 12, 1.0, 0.3);
        let exact = 2.0 * std::f64::consts::PI.powi(2) * 0.09;
        let v = signed_volume(&t);
        // Inscribed polygons lose about 5.6 % at this resolution.
        assert!(
            v < exact && (v - exact).abs() / exact < 0.08,
            "{v} vs {exact}"
        );
    }
}
