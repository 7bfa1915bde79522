//! Insertion order: Hilbert curve keys and the biased randomized insertion order (BRIO)
//! of Amenta, Choi and Rote ("Incremental constructions con BRIO", SoCG 2003).
//!
//! Points are shuffled with a seeded generator, split into rounds whose sizes grow
//! geometrically, and each round is sorted along a 3D Hilbert curve (key by Skilling's
//! transpose algorithm, "Programming the Hilbert curve", AIP Conf. Proc. 707, 2004).
//! Consecutive points are then close in space, so the walk of the kernel is short and
//! the cavity is still in cache, while the expected complexity stays that of a random
//! order.

use crate::geom::{Aabb, Point};
use rayon::prelude::*;

/// Bits per coordinate of the Hilbert key (3 x 21 = 63 bits).
const HILBERT_BITS: u32 = 21;

/// Ratio between the sizes of consecutive BRIO rounds.
pub const BRIO_RATIO: usize = 8;

/// Rounds smaller than this are merged into the first one.
pub const BRIO_MIN_ROUND: usize = 1024;

/// A small deterministic generator (splitmix64), so runs are reproducible.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)`: the top 53 of the next 64 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform integer in `0..n` (n > 0), by multiply-shift.
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
}

/// Fisher-Yates shuffle of `v` with the generator seeded by `seed`.
pub fn shuffle<T>(v: &mut [T], seed: u64) {
    let mut rng = SplitMix64::new(seed);
    for i in (1..v.len()).rev() {
        let j = rng.below(i + 1);
        v.swap(i, j);
    }
}

/// Hilbert index of a point with integer coordinates below `2^HILBERT_BITS`: the key of
/// Skilling's algorithm, one level (three bits) at a time through [`HILBERT_TABLE`]
/// (four times faster than the bit-parallel form, whose steps all depend on each other).
pub fn hilbert_key(coords: [u32; 3]) -> u64 {
    let mut state = 0usize;
    let mut key = 0u64;
    for b in (0..HILBERT_BITS).rev() {
        let octant =
            ((coords[0] >> b) & 1) << 2 | ((coords[1] >> b) & 1) << 1 | ((coords[2] >> b) & 1);
        let e = HILBERT_TABLE[state][octant as usize];
        key = key << 3 | (e & 7) as u64;
        state = (e >> 3) as usize;
    }
    key
}

/// States of [`HILBERT_TABLE`]: the signed permutation of the axes that Skilling's
/// transform applies to the lower levels (6 permutations, 3 inversion bits) and the
/// parity of the Gray code's running correction.
const HILBERT_STATES: usize = 96;

/// The three-bit permutations of the axes, in the order of the state index.
const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// Per state and octant (bit 2: x, bit 1: y, bit 0: z) of a level: the key's three
/// bits at that level, plus eight times the state for the level below.
const HILBERT_TABLE: [[u16; 8]; HILBERT_STATES] = hilbert_table();

/// Builds [`HILBERT_TABLE`] by running one level of Skilling's "AxesToTranspose"
/// ("Programming the Hilbert curve", 2004) symbolically: in state `(perm, flip,
/// parity)`, the current `x[j]` at this level is the input bit of axis `perm[j]`
/// inverted if bit `j` of `flip` is set. Then for each axis `i`, a set bit of `x[i]`
/// inverts the lower bits of `x[0]` and a clear one exchanges the lower bits of `x[0]`
/// and `x[i]`. The Gray code follows, and `parity` (the XOR of the Gray-coded `x[2]`
/// over the levels above) inverts all three bits.
const fn hilbert_table() -> [[u16; 8]; HILBERT_STATES] {
    let mut table = [[0u16; 8]; HILBERT_STATES];
    let mut s = 0;
    while s < HILBERT_STATES {
        let (p, flip, parity) = (s / 16, (s / 2) % 8, s % 2);
        let mut o = 0;
        while o < 8 {
            let mut perm = PERMUTATIONS[p];
            let mut inv = [flip & 1, (flip >> 1) & 1, (flip >> 2) & 1];
            let mut x = [0usize; 3];
            let mut j = 0;
            while j < 3 {
                x[j] = ((o >> (2 - perm[j])) & 1) ^ inv[j];
                j += 1;
            }
            let mut i = 0;
            while i < 3 {
                if x[i] == 1 {
                    inv[0] ^= 1;
                } else {
                    let (tp, ti) = (perm[0], inv[0]);
                    perm[0] = perm[i];
                    inv[0] = inv[i];
                    perm[i] = tp;
                    inv[i] = ti;
                }
                i += 1;
            }
            let g = [x[0], x[0] ^ x[1], x[0] ^ x[1] ^ x[2]];
            let digit = (g[0] ^ parity) << 2 | (g[1] ^ parity) << 1 | (g[2] ^ parity);
            let mut q = 0;
            while PERMUTATIONS[q][0] != perm[0] || PERMUTATIONS[q][1] != perm[1] {
                q += 1;
            }
            let next = q * 16 + (inv[0] | inv[1] << 1 | inv[2] << 2) * 2 + (parity ^ g[2]);
            table[s][o] = (digit | next << 3) as u16;
            o += 1;
        }
        s += 1;
    }
    table
}

/// Hilbert keys of `points` inside their bounding box (non-finite points get key 0).
pub fn hilbert_keys(points: &[Point]) -> Vec<u64> {
    hilbert_keys_in(points, finite_bounds(points))
}

/// The box of the finite points.
fn finite_bounds(points: &[Point]) -> Option<Aabb> {
    Aabb::of_points(points.iter().filter(|p| p.is_finite()))
}

/// [`hilbert_keys`] on the grid over the box `bb` (which should hold the finite
/// points; those outside are clamped to it), so that a subset of a point set gets the
/// keys the whole set gives it (a cast saturates: coordinates below the box get 0);
/// all zero without a box.
pub fn hilbert_keys_in(points: &[Point], bb: Option<Aabb>) -> Vec<u64> {
    let Some(bb) = bb else {
        return vec![0; points.len()];
    };
    let ext = (bb.max - bb.min).max_element();
    let scale = if ext > 0.0 {
        ((1u64 << HILBERT_BITS) - 1) as f64 / ext
    } else {
        0.0
    };
    let q = |v: f64, lo: f64| (((v - lo) * scale) as u32).min((1 << HILBERT_BITS) - 1);
    // Pure per point, so the threads change nothing in the result.
    points
        .par_iter()
        .with_min_len(4096)
        .map(|p| {
            if p.is_finite() {
                hilbert_key([q(p.x, bb.min.x), q(p.y, bb.min.y), q(p.z, bb.min.z)])
            } else {
                0
            }
        })
        .collect()
}

/// Indices of `points` in Hilbert order (ties by index, deterministic).
pub fn hilbert_order(points: &[Point]) -> Vec<u32> {
    hilbert_order_by(points, |_| 0)
}

/// Indices of `points` sorted by `major(i)`, then along the Hilbert curve (ties by
/// index: the order is total, so the parallel sort is deterministic).
pub fn hilbert_order_by(points: &[Point], major: impl Fn(usize) -> u8 + Sync) -> Vec<u32> {
    hilbert_order_by_in(points, finite_bounds(points), major)
}

/// [`hilbert_order_by`] with the keys of [`hilbert_keys_in`] over the box `bb`: the
/// order of a subset is then the order its points have in the whole set (ties by
/// index).
pub fn hilbert_order_by_in(
    points: &[Point],
    bb: Option<Aabb>,
    major: impl Fn(usize) -> u8 + Sync,
) -> Vec<u32> {
    let keys = hilbert_keys_in(points, bb);
    // The sort keys inline (not looked up through the index): a sequential sort.
    let mut items: Vec<(u8, u64, u32)> = keys
        .into_iter()
        .enumerate()
        .map(|(i, k)| (major(i), k, i as u32))
        .collect();
    items.par_sort_unstable();
    items.into_iter().map(|x| x.2).collect()
}

/// Indices of `points` in BRIO order: seeded shuffle, rounds growing by [`BRIO_RATIO`],
/// each round sorted along the Hilbert curve.
pub fn brio_order(points: &[Point], seed: u64) -> Vec<u32> {
    let keys = hilbert_keys(points);
    let n = points.len();
    let mut idx: Vec<(u64, u32)> = keys.into_iter().zip(0..n as u32).collect();
    shuffle(&mut idx, seed);
    let mut end = n;
    loop {
        let start = if end / BRIO_RATIO < BRIO_MIN_ROUND {
            0
        } else {
            end / BRIO_RATIO
        };
        idx[start..end].par_sort_unstable();
        if start == 0 {
            break;
        }
        end = start;
    }
    idx.into_iter().map(|x| x.1).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_subset_ordered_over_the_whole_box_keeps_its_order_in_the_whole() {
        let mut rng = SplitMix64::new(7);
        let mut u = || rng.unit();
        let pts: Vec<Point> = (0..500).map(|_| Point::new(u(), u(), u())).collect();
        let whole = hilbert_order_by(&pts, |i| (i % 3) as u8);
        let keep = |i: usize| !i.is_multiple_of(7);
        let subset: Vec<usize> = (0..pts.len()).filter(|&i| keep(i)).collect();
        let sub_pts: Vec<Point> = subset.iter().map(|&i| pts[i]).collect();
        let bb = Aabb::of_points(pts.iter());
        let ordered: Vec<usize> = hilbert_order_by_in(&sub_pts, bb, |k| (subset[k] % 3) as u8)
            .into_iter()
            .map(|k| subset[k as usize])
            .collect();
        let expected: Vec<usize> = whole
            .into_iter()
            .map(|i| i as usize)
            .filter(|&i| keep(i))
            .collect();
        assert_eq!(ordered, expected);
    }

    #[test]
    fn hilbert_keys_are_a_bijection_on_a_small_grid() {
        // On a 2^21 grid the key is a bijection; check that neighbouring keys of an 8^3
        // sub-grid (scaled to the top bits) are distinct and adjacent cells.
        let s = 1u32 << (HILBERT_BITS - 3);
        let mut cells: Vec<(u64, [u32; 3])> = Vec::new();
        for x in 0..8 {
            for y in 0..8 {
                for z in 0..8 {
                    cells.push((hilbert_key([x * s, y * s, z * s]), [x, y, z]));
                }
            }
        }
        cells.sort();
        for w in cells.windows(2) {
            assert_ne!(w[0].0, w[1].0);
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(d, 1, "consecutive Hilbert cells must be face neighbours");
        }
    }

    /// Skilling's bit-parallel transform, the oracle of the table.
    fn skilling_key(coords: [u32; 3]) -> u64 {
        let mut x = coords;
        let m = 1u32 << (HILBERT_BITS - 1);
        let mut q = m;
        while q > 1 {
            let p = q - 1;
            for i in 0..3 {
                if x[i] & q != 0 {
                    x[0] ^= p;
                } else {
                    let t = (x[0] ^ x[i]) & p;
                    x[0] ^= t;
                    x[i] ^= t;
                }
            }
            q >>= 1;
        }
        x[1] ^= x[0];
        x[2] ^= x[1];
        let mut t = 0;
        q = m;
        while q > 1 {
            if x[2] & q != 0 {
                t ^= q - 1;
            }
            q >>= 1;
        }
        for c in &mut x {
            *c ^= t;
        }
        (spread3(x[0]) << 2) | (spread3(x[1]) << 1) | spread3(x[2])
    }

    /// The low [`HILBERT_BITS`] bits of `v`, bit b moved to bit 3b.
    fn spread3(v: u32) -> u64 {
        let mut x = v as u64 & ((1 << HILBERT_BITS) - 1);
        x = (x | x << 32) & 0x001f_0000_0000_ffff;
        x = (x | x << 16) & 0x001f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        x = (x | x << 2) & 0x1249_2492_4924_9249;
        x
    }

    #[test]
    fn the_table_gives_skillings_keys() {
        let mut rng = SplitMix64::new(3);
        for _ in 0..200_000 {
            let r = rng.next_u64();
            let c = [0, 21, 42].map(|s| ((r >> s) & ((1 << HILBERT_BITS) - 1)) as u32);
            assert_eq!(hilbert_key(c), skilling_key(c), "{c:?}");
        }
    }

    #[test]
    fn spread_moves_bit_b_to_bit_3b() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..10_000 {
            let v = rng.next_u64() as u32;
            let mut want = 0u64;
            for b in 0..HILBERT_BITS {
                want |= (((v >> b) & 1) as u64) << (3 * b);
            }
            assert_eq!(spread3(v), want, "{v:#x}");
        }
    }

    #[test]
    fn brio_is_a_permutation() {
        let mut rng = SplitMix64::new(1);
        let pts: Vec<Point> = (0..5000)
            .map(|_| {
                Point::new(
                    rng.next_u64() as f64,
                    rng.next_u64() as f64,
                    rng.next_u64() as f64,
                )
            })
            .collect();
        let mut o = brio_order(&pts, 7);
        o.sort_unstable();
        assert!(o.iter().enumerate().all(|(i, &v)| i as u32 == v));
    }
}
