//! Bounding volume hierarchy over axis-aligned boxes, used to find the candidate pairs
//! of the self-intersection check and the triangles near a tet (`quality::room`).
//!
//! A binary tree built top-down by splitting the items at the median of their box
//! centres along the longest axis of the centres' extent (a median split keeps the depth
//! at `ceil(log2(n / LEAF))`, so the explicit traversal stack is bounded). Boxes are
//! the exact min/max of the input coordinates, so the closed-box overlap test never
//! misses a pair of intersecting triangles.

/// A closed axis-aligned box as `[min, max]` per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Box3 {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Box3 {
    /// The empty box (neutral for [`Box3::union`]).
    pub const EMPTY: Box3 = Box3 {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    /// Smallest box holding both.
    #[inline]
    pub fn union(&self, o: &Box3) -> Box3 {
        Box3 {
            min: [0, 1, 2].map(|k| self.min[k].min(o.min[k])),
            max: [0, 1, 2].map(|k| self.max[k].max(o.max[k])),
        }
    }

    /// The closed boxes share a point.
    #[inline]
    pub fn overlaps(&self, o: &Box3) -> bool {
        (0..3).all(|k| self.min[k] <= o.max[k] && o.min[k] <= self.max[k])
    }

    /// Centre along axis `k`.
    #[inline]
    fn centre(&self, k: usize) -> f64 {
        0.5 * (self.min[k] + self.max[k])
    }
}

/// Items per leaf.
const LEAF: usize = 4;

/// A node covers the contiguous items `start..end` (in leaf order).
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Box3,
    start: u32,
    end: u32,
    /// Index of the right child (the left child is the next node); 0 for a leaf.
    right: u32,
}

/// The hierarchy over a set of boxes identified by `u32` ids.
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    items: Vec<(u32, Box3)>,
    depth: usize,
}

impl Bvh {
    /// Builds the tree over `(id, box)` pairs. Boxes must have finite coordinates.
    pub fn build(mut items: Vec<(u32, Box3)>) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * items.len() / LEAF + 1),
            items: Vec::with_capacity(items.len()),
            depth: 0,
        };
        if !items.is_empty() {
            bvh.build_node(&mut items, 1);
        }
        bvh
    }

    /// Appends the node for `items` and its subtree; returns its index.
    fn build_node(&mut self, items: &mut [(u32, Box3)], depth: usize) -> usize {
        self.depth = self.depth.max(depth);
        let bounds = items.iter().fold(Box3::EMPTY, |acc, (_, b)| acc.union(b));
        let idx = self.nodes.len();
        let start = self.items.len() as u32;
        let end = start + items.len() as u32;
        if items.len() <= LEAF {
            self.nodes.push(Node {
                bounds,
                start,
                end,
                right: 0,
            });
            self.items.extend_from_slice(items);
            return idx;
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (_, b) in items.iter() {
            for k in 0..3 {
                lo[k] = lo[k].min(b.centre(k));
                hi[k] = hi[k].max(b.centre(k));
            }
        }
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |a, b| a.1.centre(axis).total_cmp(&b.1.centre(axis)));
        self.nodes.push(Node {
            bounds,
            start,
            end,
            right: 0,
        });
        let (left, right) = items.split_at_mut(mid);
        self.build_node(left, depth + 1);
        let r = self.build_node(right, depth + 1);
        self.nodes[idx].right = r as u32;
        idx
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// The item at position `pos` of the leaf order: its id and box.
    pub fn item(&self, pos: usize) -> (u32, Box3) {
        self.items[pos]
    }

    /// Calls `visit(id)` for every item whose box overlaps `q`, in no particular order.
    pub fn query(&self, q: &Box3, visit: impl FnMut(u32)) {
        self.query_after(0, q, visit);
    }

    /// Calls `visit(id)` for every item at leaf-order position `>= from` whose box
    /// overlaps `q`. Querying each item's own box with `from = pos + 1` enumerates every
    /// overlapping pair once, and queries in leaf order touch nearby nodes in turn.
    pub fn query_after(&self, from: usize, q: &Box3, mut visit: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let from = from as u32;
        // A right child is pushed at most once per level: the stack never exceeds depth.
        let mut stack: Vec<u32> = Vec::with_capacity(self.depth + 1);
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if node.end <= from || !node.bounds.overlaps(q) {
                continue;
            }
            if node.right == 0 {
                let s = node.start.max(from) as usize;
                for (id, b) in &self.items[s..node.end as usize] {
                    if b.overlaps(q) {
                        visit(*id);
                    }
                }
            } else {
                stack.push(node.right);
                stack.push(n + 1);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn query_matches_brute_force() {
        let boxes: Vec<(u32, Box3)> = (0..200u32)
            .map(|i| {
                let x = ((i * 37) % 101) as f64;
                let y = ((i * 53) % 97) as f64;
                let z = ((i * 17) % 89) as f64;
                let b = Box3 {
                    min: [x, y, z],
                    max: [x + 5.0, y + 7.0, z + 3.0],
                };
                (i, b)
            })
            .collect();
        let bvh = Bvh::build(boxes.clone());
        for (i, b) in &boxes {
            let mut got = Vec::new();
            bvh.query(b, |j| got.push(j));
            got.sort_unstable();
            let want: Vec<u32> = boxes
                .iter()
                .filter(|(_, c)| c.overlaps(b))
                .map(|(j, _)| *j)
                .collect();
            assert_eq!(got, want, "box {i}");
        }
    }
}
