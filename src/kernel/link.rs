//! The link: a round cone, i.e. the convex hull of two spheres (= sphere ∪ tangent-cone stump
//! ∪ sphere, = the sphere sweep `S(p(u), r(u))` with `p`, `r` linear in `u ∈ [0, 1]`).
//!
//! Two formulations, both public, so the reports can chart them against each other:
//!
//! * **faithful** — Han et al. 2019: apex, unit-cone transform, quadratic, slab `[z_cap, 1]`,
//!   plus the two spheres; a textbook cylinder when the radii are exactly equal. With the
//!   transform precomputed ([`HanLink`](crate::baseline::HanLink), Han Table 1 option d) or built per call
//!   ([`RoundCone::intersect_han_on_the_fly`], option c). A baseline: it lives in
//!   [`crate::baseline`].
//! * **stable** — [`RoundCone`] ([`Primitive`](crate::Primitive)): no apex. The cone is written with its half-angle,
//!   `sin θ = (r₁ − r₂)/L`, in coordinates centred on the link's midpoint, and the ray origin is
//!   first moved to the point of the line closest to that midpoint. The quadratic's
//!   coefficients are built from cross products (`|d × â|²`, `(o × â)·(d × â)`, …), so
//!   axis-parallel rays, equal radii and far origins lose no digits that the input did not
//!   already lose.
//!
//! Because the hull is convex and equals the union of its three pieces, the ray interval is
//! the earliest entry and the latest exit over the pieces.

mod stable;
pub use stable::PendingInterval;

use crate::error::GeometryError;
use crate::ray::{Interval, Ray};
use crate::real::{Real, Scalar};
use crate::vec::V3;

/// A round cone (link) between spheres `(a, ra)` and `(b, rb)`. The curve parameter `u` runs
/// from 0 at `a` to 1 at `b`.
///
/// Build scalar links with [`RoundCone::new`] (validated); lane links with
/// [`RoundCone::from_lanes`] from validated scalar links. Ray queries, the box and the
/// distance come from [`Primitive`](crate::Primitive): the **stable** formulation (no apex: the cone by its
/// half-angle in coordinates centred on the link, the ray origin moved to the point of the
/// line closest to it; derivation in `src/kernel/link.rs`). [`HanLink`](crate::baseline::HanLink) is the faithful one, a
/// baseline.
///
/// ```
/// use tubecast::{Primitive, Ray, RoundCone, V3};
/// let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let iv = link.intersect(&Ray::new(V3::new(0.0, 0.0, -5.0), V3::new(0.0, 0.0, 1.0)));
/// assert_eq!((iv.entry.t, iv.exit.t, iv.entry.u), (4.0, 6.0, 0.0)); // through the centre of sphere a
/// assert!(link.sdf(V3::new(2.0, 0.0, 0.0)) < 0.0);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundCone<T> {
    /// First centre.
    pub a: V3<T>,
    /// First radius.
    pub ra: T,
    /// Second centre.
    pub b: V3<T>,
    /// Second radius.
    pub rb: T,
}

/// What a link degenerates to, by the classification the kernels use.
///
/// ```
/// use tubecast::{LinkShape, RoundCone, V3};
/// let o = V3::new(0.0, 0.0, 0.0);
/// let x = V3::new(1.0, 0.0, 0.0);
/// assert_eq!(RoundCone::new(o, 0.5, x, 0.5)?.shape(), LinkShape::Cylinder);
/// assert_eq!(RoundCone::new(o, 0.5, x, 0.2)?.shape(), LinkShape::Cone);
/// assert_eq!(RoundCone::new(o, 2.0, x, 0.5)?.shape(), LinkShape::Sphere);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkShape {
    /// Distinct radii with `|ra − rb| < L`: a tangent cone stump between two spheres.
    Cone,
    /// Equal radii and `L > 0`: a cylinder between two spheres.
    Cylinder,
    /// `|ra − rb| ≥ L` (one sphere inside the other, or zero length): the larger sphere.
    Sphere,
}

impl<T: Scalar> RoundCone<T> {
    /// A validated link. Errors: non-finite coordinates or radii, a negative radius, or both
    /// radii zero (no volume). One sphere inside the other and zero length are valid: the
    /// link is the larger sphere ([`LinkShape::Sphere`]).
    pub fn new(a: V3<T>, ra: T, b: V3<T>, rb: T) -> Result<Self, GeometryError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(GeometryError::NonFinite { what: "link centre" });
        }
        if !ra.is_finite() || !rb.is_finite() {
            return Err(GeometryError::NonFinite { what: "link radius" });
        }
        if ra < T::zero() || rb < T::zero() {
            return Err(GeometryError::NegativeRadius);
        }
        if ra == T::zero() && rb == T::zero() {
            return Err(GeometryError::ZeroRadius);
        }
        // Kernels square radii and form differences of squares: a non-zero radius whose square
        // is within a factor 1/ε of underflow loses its digits in subnormal arithmetic.
        let tiny = |r: T| r > T::zero() && r * r < T::MIN_POSITIVE / T::EPS;
        if tiny(ra) || tiny(rb) {
            return Err(GeometryError::TooSmall { what: "link radius (its square underflows)" });
        }
        // Squared length must not overflow, or every kernel sees L = ∞.
        let e = (b - a).max_abs().max(ra).max(rb);
        if !(e * e * T::cst(4.0)).is_finite() {
            return Err(GeometryError::NonFinite { what: "link extent (overflows when squared)" });
        }
        Ok(Self { a, ra, b, rb })
    }
    /// How the kernels classify this link.
    pub fn shape(&self) -> LinkShape {
        let l = (self.b - self.a).length();
        let dr = (self.ra - self.rb).abs();
        if dr >= l {
            LinkShape::Sphere
        } else if dr == T::zero() {
            LinkShape::Cylinder
        } else {
            LinkShape::Cone
        }
    }
    /// Convert the precision.
    pub fn cast<U: Scalar>(&self) -> RoundCone<U> {
        RoundCone {
            a: self.a.cast(),
            ra: U::from_f64(self.ra.to_f64()),
            b: self.b.cast(),
            rb: U::from_f64(self.rb.to_f64()),
        }
    }
}

impl<T: Real> RoundCone<T> {
    /// Lanes from validated scalar links (one per lane).
    pub fn from_lanes(f: impl Fn(usize) -> RoundCone<T::Elem>) -> Self {
        Self {
            a: V3::from_fn(|i| f(i).a),
            ra: T::from_fn(|i| f(i).ra),
            b: V3::from_fn(|i| f(i).b),
            rb: T::from_fn(|i| f(i).rb),
        }
    }
    /// Every lane the same link.
    pub fn broadcast(l: RoundCone<T::Elem>) -> Self {
        Self { a: V3::broadcast(l.a), ra: T::splat(l.ra), b: V3::broadcast(l.b), rb: T::splat(l.rb) }
    }

    /// The tangent-cone stump alone (no end spheres), stable form.
    #[inline(always)]
    pub fn intersect_stump_stable(&self, ray: &Ray<T>) -> Interval<T> {
        self.stable_line(ray, false).clip(ray)
    }
}
