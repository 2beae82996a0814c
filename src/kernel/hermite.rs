//! Cubic Hermite segment → two quadratic Bézier sub-segments (Russig §3.2).
//!
//! For a segment between nodes `i`, `j` with values `nᵢ`, `nⱼ` and derivatives `tᵢ`, `tⱼ`
//! (positions and radii alike), the sub-segments' control points are
//! `a₁ = nᵢ`, `a₂ = nᵢ + c₁tᵢ`, `b₂ = nⱼ − c₂tⱼ`, `b₃ = nⱼ`, `a₃ = b₁ = (a₂ + b₂)/2` with
//! `c₁ = c₂ = 1/3` (the Hermite → cubic Bézier basis change). The junction is C¹: both
//! sub-segments have derivative `b₂ − a₂` there (in their own parameters). The pair is a
//! **model**, not a reparametrisation of the cubic: the sweep differs from the cubic Hermite
//! sweep (`tests/spline_hermite.rs` measures by how much); it is exact for straight segments
//! whose node derivatives are the chord (`tᵢ = tⱼ = nⱼ − nᵢ`).

use crate::error::GeometryError;
use crate::kernel::spline::QuadTube;
use crate::real::{Real, Scalar};
use crate::vec::V3;

/// A cubic Hermite segment: positions, position derivatives (tangents), radii and radius
/// derivatives at both nodes; the parameter runs over `[0, 1]`.
///
/// ```
/// use tubecast::{HermiteSegment, V3};
/// let (p0, p1) = (V3::new(0.0f64, 0.0, 0.0), V3::new(3.0, 0.0, 0.0));
/// let seg = HermiteSegment::new(p0, p1 - p0, 0.5, 0.0, p1, p1 - p0, 0.5, 0.0);
/// let [a, b] = seg.split()?; // two quadratic sphere-swept segments, joined at t = ½
/// assert_eq!(a.b[2], b.b[0]);
/// assert_eq!(a.point(1.0), seg.point(0.5)); // straight, chord tangents: exact
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HermiteSegment<T> {
    /// Start position.
    pub p0: V3<T>,
    /// Start tangent `p'(0)`.
    pub m0: V3<T>,
    /// End position.
    pub p1: V3<T>,
    /// End tangent `p'(1)`.
    pub m1: V3<T>,
    /// Start radius.
    pub r0: T,
    /// Start radius derivative `r'(0)`.
    pub dr0: T,
    /// End radius.
    pub r1: T,
    /// End radius derivative `r'(1)`.
    pub dr1: T,
}

/// The two sub-segments' control data: `(positions, radii)` of the first and of the second.
pub type QuadControls<T> = (([V3<T>; 3], [T; 3]), ([V3<T>; 3], [T; 3]));

impl<T: Real> HermiteSegment<T> {
    /// Hermite basis weights `[h00, h10, h01, h11]` at `t`.
    #[inline(always)]
    fn basis(t: T) -> [T; 4] {
        let (two, three) = (T::cst(2.0), T::cst(3.0));
        let t2 = t * t;
        let t3 = t2 * t;
        [two * t3 - three * t2 + T::one(), t3 - two * t2 + t, three * t2 - two * t3, t3 - t2]
    }
    /// Cubic position `p(t)`.
    #[inline(always)]
    pub fn point(&self, t: T) -> V3<T> {
        let [a, b, c, d] = Self::basis(t);
        self.p0 * a + self.m0 * b + self.p1 * c + self.m1 * d
    }
    /// Cubic radius `r(t)`.
    #[inline(always)]
    pub fn radius(&self, t: T) -> T {
        let [a, b, c, d] = Self::basis(t);
        self.r0 * a + self.dr0 * b + self.r1 * c + self.dr1 * d
    }
    /// Russig's split control points (`c₁ = c₂ = 1/3`), unvalidated.
    #[inline(always)]
    pub fn quad_controls(&self) -> QuadControls<T> {
        let third = T::cst(1.0 / 3.0);
        let half = T::cst(0.5);
        let a2 = self.p0 + self.m0 * third;
        let b2 = self.p1 - self.m1 * third;
        let mid = (a2 + b2) * half;
        let ra2 = self.r0 + self.dr0 * third;
        let rb2 = self.r1 - self.dr1 * third;
        let rmid = (ra2 + rb2) * half;
        (([self.p0, a2, mid], [self.r0, ra2, rmid]), ([mid, b2, self.p1], [rmid, rb2, self.r1]))
    }
}

impl<T: Scalar> HermiteSegment<T> {
    /// A segment from node data (no validation here; [`Self::split`] validates the result).
    #[allow(clippy::too_many_arguments)]
    pub fn new(p0: V3<T>, m0: V3<T>, r0: T, dr0: T, p1: V3<T>, m1: V3<T>, r1: T, dr1: T) -> Self {
        Self { p0, m0, p1, m1, r0, dr0, r1, dr1 }
    }
    /// The two validated quadratic sub-segments. Errors as [`QuadTube::new`] (non-finite
    /// data, a sub-segment radius negative somewhere, zero radius).
    pub fn split(&self) -> Result<[QuadTube<T>; 2], GeometryError> {
        let ((pa, ra), (pb, rb)) = self.quad_controls();
        Ok([QuadTube::new(pa, ra)?, QuadTube::new(pb, rb)?])
    }
}
