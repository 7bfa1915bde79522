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

/// Hilbert index of a point with integer coordinates below `2^HILBERT_BITS`.
pub fn hilbert_key(coords: [u32; 3]) -> u64 {
    let mut x = coords;
    let m = 1u32 << (HILBERT_BITS - 1);
    // Inverse undo of the excess work (Skilling's AxesToTranspose).
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
    // Gray encode.
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
    // Interleave the transposed form, most significant bit first: bit b of x[0] goes
    // to bit 3b + 2 of the key, of x[1] to 3b + 1, of x[2] to 3b.
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

/// Hilbert keys of `points` inside their bounding box (non-finite points get key 0).
pub fn hilbert_keys(points: &[Point]) -> Vec<u64> {
    let finite = points.iter().filter(|p| p.is_finite());
    let Some(bb) = Aabb::of_points(finite) else {
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
    let keys = hilbert_keys(points);
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
