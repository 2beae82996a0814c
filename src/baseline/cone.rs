//! The faithful pieces of Han et al. 2019 on their own, for comparisons and benchmarks: the
//! tangent cone of two spheres (§3.2.2), the unit-cone transform and the ray–stump slab test
//! (§4.1) with the transform precomputed (Table 1 option d) or built per call (option c), and
//! the textbook cylinder. [`HanLink`](super::HanLink) composes them into the round cone.
//!
//! ```
//! use tubecast::baseline::cone::{intersect_stump_precomputed, TangentCone, UnitConeTransform};
//! use tubecast::{Ray, V3};
//! let cone = TangentCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5);
//! assert!(cone.is_cone && cone.swapped); // apex behind the smaller sphere
//! let xf = UnitConeTransform::new(&cone);
//! let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
//! let iv = intersect_stump_precomputed(&ray, &cone, &xf);
//! assert!(iv.hit && iv.entry.u > 0.0 && iv.entry.u < 1.0); // on the cone side
//! ```
//!
//! The construction puts the apex behind the **smaller** sphere: spheres are reordered so that
//! `r_small ≤ r_large` (the paper assumes `r1 < r2`); [`TangentCone::swapped`] says whether
//! that happened, so curve parameters still run from the caller's first to second sphere.
//!
//! Erratum in the paper's eq. (3): with columns `(w/p₂)·v̂ₓ, (w/p₂)·v̂ᵧ, Ĉ, A` the larger cap lands
//! at `Z = z₂`, not at `Z = 1` as the text says; we scale the whole frame by `z₂`
//! (`M⁻¹ = [z₂w/p₂·v̂ₓ, z₂w/p₂·v̂ᵧ, z₂Ĉ, A]`) so that the slab is `[z₁/z₂, 1]` as stated.
//!
//! The apex sits at distance `p₁ = L·r₁/(r₂ − r₁)` behind the small sphere and goes to infinity
//! as `r₁ → r₂`: this formulation loses digits for near-equal radii (the stability report
//! charts it). Equal radii are a cylinder, handled by [`intersect_cylinder_naive`].

use crate::math::frame::orthonormal_basis;
use crate::math::quadric::{quadric_in_slab, slab};
use crate::ray::{Crossing, Interval, Ray};
use crate::real::Real;
use crate::vec::V3;

/// The tangent cone of two spheres, per Han §3.2.2 (smaller sphere first).
///
/// ```
/// use tubecast::baseline::cone::TangentCone;
/// use tubecast::V3;
/// let c = TangentCone::new(V3::new(0.0f64, 0.0, 0.0), 0.5, V3::new(4.0, 0.0, 0.0), 1.0);
/// assert!(c.is_cone && !c.swapped);
/// assert_eq!((c.p1, c.p2), (4.0, 8.0)); // p₁ = L·r₁/(r₂ − r₁)
/// assert_eq!(c.apex, V3::new(-4.0, 0.0, 0.0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct TangentCone<T: Real> {
    /// Apex `A` (undefined where `is_cone` is false).
    pub apex: V3<T>,
    /// Unit axis `Ĉ`, from the smaller towards the larger sphere.
    pub axis: V3<T>,
    /// Distance apex → smaller sphere's centre (`p₁`).
    pub p1: T,
    /// Distance apex → larger sphere's centre (`p₂`).
    pub p2: T,
    /// Clip plane of the small cap, as distance from the apex along `Ĉ` (`z₁`).
    pub z1: T,
    /// Clip plane of the large cap (`z₂`).
    pub z2: T,
    /// Cone radius at distance `p₂` from the apex (`w = p₂r₂/x₂`).
    pub w: T,
    /// Lanes whose spheres were given larger-first and were swapped.
    pub swapped: T::Mask,
    /// Lanes where a proper cone exists (`0 < r_large − r_small < L`).
    pub is_cone: T::Mask,
    /// Lanes with equal radii and `L > 0`: a cylinder, apex at infinity.
    pub is_cylinder: T::Mask,
}

impl<T: Real> TangentCone<T> {
    /// Build the tangent cone of spheres `(c1, r1)` and `(c2, r2)`.
    ///
    /// Covers `r1 < r2`, `r1 > r2` (swapped), `r1 = r2` (cylinder lanes), one sphere inside the
    /// other or zero length (neither cone nor cylinder: the link is the larger sphere), and a
    /// zero radius at one end (apex at that centre). Never produces NaN for finite input.
    #[inline(always)]
    pub fn new(c1: V3<T>, r1: T, c2: V3<T>, r2: T) -> Self {
        let swapped = r1.gt(r2);
        let (ps, rs) = (V3::select(swapped, c2, c1), T::select(swapped, r2, r1));
        let (pl, rl) = (V3::select(swapped, c1, c2), T::select(swapped, r1, r2));
        let v = pl - ps;
        let len = v.length();
        let dr = rl - rs;
        let is_cone = dr.gt(T::zero()) & dr.lt(len);
        let is_cylinder = dr.eq(T::zero()) & len.gt(T::zero());
        let one = T::one();
        let len_s = T::select(len.gt(T::zero()), len, one);
        let axis = v * (one / len_s);
        let dr_s = T::select(is_cone, dr, one);
        let rl_s = T::select(is_cone, rl, one);
        // p₁ = L·r₁/(r₂ − r₁), p₂ = L + p₁.
        let p1 = len_s * rs / dr_s;
        let p2 = len_s + p1;
        let apex = ps - axis * p1;
        // z₁ = p₁ − r₁²/p₁ (z₁ = 0 for a zero small radius: the apex is the tip).
        let p1_s = T::select(p1.gt(T::zero()), p1, one);
        let z1 = T::select(p1.gt(T::zero()), p1 - rs * rs / p1_s, T::zero());
        let p2_s = T::select(is_cone, p2, T::cst(2.0));
        let z2 = p2_s - rl_s * rl_s / p2_s;
        // x₂ = √(p₂² − r₂²) > 0 because r₂ < p₂ whenever r₂ − r₁ < L.
        let x2 = ((p2_s - rl_s) * (p2_s + rl_s)).sqrt();
        let x2_s = T::select(x2.gt(T::zero()), x2, one);
        let w = p2_s * rl_s / x2_s;
        Self { apex, axis, p1, p2: p2_s, z1, z2, w, swapped, is_cone, is_cylinder }
    }
}

/// The unit-cone transform of Han §4.1, precomputed (Han Table 1 option d).
///
/// World point `x` maps to `R·(x − A)` with rows `R = [v̂ₓ/(z₂·w/p₂), v̂ᵧ/(z₂·w/p₂), Ĉ/z₂]`; the
/// cone becomes `X² + Y² = Z²` and the stump the slab `Z ∈ [z_cap, 1]`.
///
/// ```
/// use tubecast::baseline::cone::{TangentCone, UnitConeTransform};
/// use tubecast::V3;
/// let c = TangentCone::new(V3::new(0.0f64, 0.0, 0.0), 0.5, V3::new(4.0, 0.0, 0.0), 1.0);
/// let m = UnitConeTransform::new(&c);
/// assert_eq!(m.point(c.apex), V3::new(0.0, 0.0, 0.0));
/// let big_cap = m.point(c.apex + c.axis * c.z2); // centre of the large cap circle
/// assert!((big_cap.z - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct UnitConeTransform<T: Real> {
    /// Rows of the linear part.
    pub rows: [V3<T>; 3],
    /// The apex (translation).
    pub apex: V3<T>,
    /// `z₁/z₂`.
    pub z_cap: T,
}

impl<T: Real> UnitConeTransform<T> {
    /// Precompute the transform of a tangent cone (lanes that are not cones get an
    /// arbitrary, finite transform; their results are masked out).
    #[inline(always)]
    pub fn new(c: &TangentCone<T>) -> Self {
        let (vx, vy) = orthonormal_basis(c.axis);
        let z2 = T::select(c.is_cone, c.z2, T::one());
        let s = T::one() / (z2 * c.w / c.p2);
        let iz = T::one() / z2;
        Self { rows: [vx * s, vy * s, c.axis * iz], apex: c.apex, z_cap: c.z1 * iz }
    }
    /// World → unit coordinates of a point.
    #[inline(always)]
    pub fn point(&self, x: V3<T>) -> V3<T> {
        let y = x - self.apex;
        V3::new(self.rows[0].dot(y), self.rows[1].dot(y), self.rows[2].dot(y))
    }
    /// World → unit coordinates of a direction.
    #[inline(always)]
    pub fn dir(&self, d: V3<T>) -> V3<T> {
        V3::new(self.rows[0].dot(d), self.rows[1].dot(d), self.rows[2].dot(d))
    }
    /// Unit-space normal → world normal (`Rᵀ·n`, normalised).
    #[inline(always)]
    pub fn normal_to_world(&self, n: V3<T>) -> V3<T> {
        let w = (self.rows[0] * n.x + self.rows[1] * n.y + self.rows[2] * n.z).normalize_or_zero();
        // Under/overflow of the transform (lengths spanning more than the exponent range) can
        // leave nothing: fall back to the axis direction so the normal stays unit length.
        let axis = self.rows[2].normalize_or_zero();
        let fallback = V3::select(n.z.gt(T::zero()), axis, -axis);
        let fallback = V3::select(fallback.length2().gt(T::zero()), fallback, V3::new(T::zero(), T::zero(), T::one()));
        V3::select(w.length2().gt(T::zero()), w, fallback)
    }
}

/// Ray–cone-stump interval in the unit-cone frame (Han §4.1), with a precomputed transform
/// (Han Table 1 option d). Only the stump (cone side and two flat caps) — see
/// [`HanLink`](crate::baseline::HanLink) for the round cone. `u` is the parameter along the stump from the
/// caller's first sphere (0) to its second (1), measured by the axial position of the hit.
#[inline(always)]
pub fn intersect_stump_precomputed<T: Real>(
    ray: &Ray<T>,
    cone: &TangentCone<T>,
    m: &UnitConeTransform<T>,
) -> Interval<T> {
    stump_line(ray, cone, m).clip(ray)
}

/// The stump's line interval, no range test (see [`crate::kernel::sphere`]).
#[inline(always)]
pub(crate) fn stump_line<T: Real>(ray: &Ray<T>, cone: &TangentCone<T>, m: &UnitConeTransform<T>) -> Interval<T> {
    let o = m.point(ray.o);
    let d = m.dir(ray.d);
    let a = d.x * d.x + d.y * d.y - d.z * d.z;
    let b = o.x * d.x + o.y * d.y - o.z * d.z;
    let c = o.x * o.x + o.y * o.y - o.z * o.z;
    let (lo, hi) = slab(o.z, d.z, m.z_cap, T::one());
    let hits = quadric_in_slab(a, b, c, lo, hi);
    let (t0, t1) = (hits.t0, hits.t1);
    // Normals in the unit frame: cone side ∇(X²+Y²−Z²) ∝ (X, Y, −Z); caps ±Ẑ.
    let cap_n = |t: T| {
        let z = o.z + d.z * t;
        let up = (z - m.z_cap).abs().gt((z - T::one()).abs());
        V3::new(T::zero(), T::zero(), T::select(up, T::one(), -T::one()))
    };
    let side_n = |t: T| {
        let p = o + d * t;
        // At the apex (a zero-radius end) the cone has no normal; the tip points along −Ẑ.
        let at_apex = p.length2().eq(T::zero());
        V3::new(p.x, p.y, T::select(at_apex, -T::one(), -p.z))
    };
    let n_in = m.normal_to_world(V3::select(hits.root0, side_n(t0), cap_n(t0)));
    let n_out = m.normal_to_world(V3::select(hits.root1, side_n(t1), cap_n(t1)));
    let zu = |t: T| {
        let z = o.z + d.z * t;
        let u = ((z - m.z_cap) / (T::one() - m.z_cap)).clamp(T::zero(), T::one());
        T::select(cone.swapped, T::one() - u, u)
    };
    let hit = hits.ok & cone.is_cone;
    Interval::new(Crossing { t: t0, n: n_in, u: zu(t0) }, Crossing { t: t1, n: n_out, u: zu(t1) }, hit).masked(hit)
}

/// Ray–cone-stump interval computing the tangent cone and its transform per call
/// (Han Table 1 option c).
#[inline(always)]
pub fn intersect_stump_on_the_fly<T: Real>(ray: &Ray<T>, c1: V3<T>, r1: T, c2: V3<T>, r2: T) -> Interval<T> {
    let cone = TangentCone::new(c1, r1, c2, r2);
    let m = UnitConeTransform::new(&cone);
    intersect_stump_precomputed(ray, &cone, &m)
}

/// Textbook ray–cylinder interval (radius `r`, axis `c1 → c2`, flat caps), as renderers use for
/// equal-radius links: formed directly from `o − c1` without re-centring.
#[inline(always)]
pub fn intersect_cylinder_naive<T: Real>(ray: &Ray<T>, c1: V3<T>, c2: V3<T>, r: T) -> Interval<T> {
    cylinder_line(ray, c1, c2, r).clip(ray)
}

/// The cylinder's line interval, no range test.
#[inline(always)]
pub(crate) fn cylinder_line<T: Real>(ray: &Ray<T>, c1: V3<T>, c2: V3<T>, r: T) -> Interval<T> {
    let v = c2 - c1;
    let len = v.length();
    let len_ok = len.gt(T::zero());
    let axis = v * (T::one() / T::select(len_ok, len, T::one()));
    let f = ray.o - c1;
    let zd = ray.d.dot(axis);
    let zo = f.dot(axis);
    let a = ray.d.length2() - zd * zd;
    let b = f.dot(ray.d) - zo * zd;
    let c = f.length2() - zo * zo - r * r;
    let (lo, hi) = slab(zo, zd, T::zero(), len);
    let hits = quadric_in_slab(a, b, c, lo, hi);
    let (t0, t1) = (hits.t0, hits.t1);
    let n_at = |t: T, q: T::Mask| {
        let p = f + ray.d * t;
        let z = p.dot(axis);
        let side = (p - axis * z).normalize_or_zero();
        // (On the axis only by rounding: any perpendicular keeps the normal unit length.)
        let side = V3::select(side.length2().gt(T::zero()), side, orthonormal_basis(axis).0);
        let cap = axis * T::select(z.gt(len * T::cst(0.5)), T::one(), -T::one());
        V3::select(q, side, cap)
    };
    let u_at = |t: T| ((zo + zd * t) / T::select(len_ok, len, T::one())).clamp(T::zero(), T::one());
    let hit = hits.ok & len_ok & r.gt(T::zero());
    let (n_in, n_out) = (n_at(t0, hits.root0), n_at(t1, hits.root1));
    Interval::new(Crossing { t: t0, n: n_in, u: u_at(t0) }, Crossing { t: t1, n: n_out, u: u_at(t1) }, hit).masked(hit)
}
