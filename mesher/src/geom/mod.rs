//! Geometry: the point type, exact predicates (sealed in [`predicates`]) and inexact
//! constructions, which are named as such.

pub mod chebyshev;
pub mod predicates;
pub(crate) mod search;

/// A point or vector of 3D space.
pub type Point = glam::DVec3;

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Point,
    /// Upper corner.
    pub max: Point,
}

impl Aabb {
    /// The box of a set of points; `None` when the set is empty.
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a Point>) -> Option<Aabb> {
        let mut it = points.into_iter();
        let first = *it.next()?;
        let mut b = Aabb {
            min: first,
            max: first,
        };
        for p in it {
            b.min = b.min.min(*p);
            b.max = b.max.max(*p);
        }
        Some(b)
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }
}
