//! Bounding boxes: one axis-aligned [`Aabb`] for every primitive ([`crate::Primitive::aabb`])
//! and the oriented [`Obb`] where a tight one is defined ([`QuadTube::obb`],
//! [`RoundCone::obb`]).

use crate::kernel::link::RoundCone;
use crate::kernel::spline::QuadTube;
use crate::real::Real;
use crate::vec::V3;

pub use crate::kernel::obb::Obb;

/// An axis-aligned box `{x : min ≤ x ≤ max}` (component-wise). For lane types each lane is
/// one box.
///
/// Primitives' boxes ([`crate::Primitive::aabb`]) are formed from their defining data with a
/// few roundings to nearest, so they can be short of the exact box by a few ulps of the
/// coordinates: pad them for conservative culling (see `tests/kernels/primitive.rs` for the bound).
///
/// ```
/// use tubecast::{Aabb, Primitive, RoundCone, Sphere, V3};
/// let link = RoundCone::new(V3::new(0.0f64, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let ball = Sphere::new(V3::new(0.0, 3.0, 0.0), 0.5)?;
/// let all = Aabb::empty().union(link.aabb()).union(ball.aabb());
/// assert_eq!(all, Aabb::new(V3::new(-1.0, -1.0, -1.0), V3::new(4.5, 3.5, 1.0)));
/// assert!(all.contains(V3::new(2.0, 3.0, 0.0)));
/// assert_eq!(all.center(), V3::new(1.75, 1.25, 0.0));
/// assert_eq!(all.extent(), V3::new(5.5, 4.5, 2.0));
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<T> {
    /// Least corner.
    pub min: V3<T>,
    /// Greatest corner.
    pub max: V3<T>,
}

impl<T: Real> Aabb<T> {
    /// The box with corners `min` and `max`.
    #[inline(always)]
    pub fn new(min: V3<T>, max: V3<T>) -> Self {
        Self { min, max }
    }
    /// The empty box (`min = +∞`, `max = −∞`): the identity of [`Self::union`].
    #[inline(always)]
    pub fn empty() -> Self {
        let inf = T::infinity();
        Self { min: V3::new(inf, inf, inf), max: V3::new(-inf, -inf, -inf) }
    }
    /// The smallest box containing both.
    #[inline(always)]
    pub fn union(self, o: Self) -> Self {
        let (a, b) = (self.min, o.min);
        let (c, d) = (self.max, o.max);
        Self {
            min: V3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z)),
            max: V3::new(c.x.max(d.x), c.y.max(d.y), c.z.max(d.z)),
        }
    }
    /// Whether `p` lies in the box (boundary included), lane-wise.
    #[inline(always)]
    pub fn contains(&self, p: V3<T>) -> T::Mask {
        let (lo, hi) = (self.min, self.max);
        p.x.ge(lo.x) & p.y.ge(lo.y) & p.z.ge(lo.z) & p.x.le(hi.x) & p.y.le(hi.y) & p.z.le(hi.z)
    }
    /// The centre `(min + max)/2`.
    #[inline(always)]
    pub fn center(&self) -> V3<T> {
        (self.min + self.max) * T::cst(0.5)
    }
    /// The edge lengths `max − min`.
    #[inline(always)]
    pub fn extent(&self) -> V3<T> {
        self.max - self.min
    }
    /// Lane `i` as a scalar box.
    #[inline]
    pub fn lane(&self, i: usize) -> Aabb<T::Elem> {
        Aabb { min: self.min.lane(i), max: self.max.lane(i) }
    }
}

impl<T: Real> QuadTube<T> {
    /// Russig's oriented box of the segment ([`Obb::fit`]).
    #[inline(always)]
    pub fn obb(&self) -> Obb<T> {
        Obb::fit(self)
    }
}

impl<T: Real> RoundCone<T> {
    /// The oriented box of the link: [`Obb::fit`] of the straight segment with the same sweep
    /// (`x̂` along the axis), which is tight (every face touches one of the two spheres).
    #[inline(always)]
    pub fn obb(&self) -> Obb<T> {
        let h = T::cst(0.5);
        Obb::fit(&QuadTube {
            b: [self.a, (self.a + self.b) * h, self.b],
            r: [self.ra, (self.ra + self.rb) * h, self.rb],
        })
    }
}
