//! Ray–sphere interval.
//!
//! The origin is moved to the point of the line closest to the centre before the quadratic is
//! formed (the "Ray Tracing Gems" ch. 7 formulation), so the discriminant is computed from a
//! vector of length ≈ distance(line, centre) rather than from `|o − c|²`: far origins lose only
//! what representing `o` itself loses.

use crate::ray::{in_range, Interval, Ray};
use crate::real::Real;
use crate::vec::V3;

/// Interval of the ray's line with the ball `|x − c| ≤ r`, with unit outward normals.
///
/// `u_in`/`u_out` are set to `u` (the caller's curve parameter for this sphere, e.g. 0 or 1
/// for a link's end spheres). Lanes with `r ≤ 0` miss. Never NaN for finite input with `d ≠ 0`.
#[inline(always)]
pub fn intersect_sphere<T: Real>(ray: &Ray<T>, c: V3<T>, r: T, u: T) -> Interval<T> {
    let iv = sphere_line(ray, c, r, u);
    iv.masked(in_range(ray, iv.t_in, iv.t_out))
}

/// Like [`intersect_sphere`] but `hit` only says the line meets the ball (no range test):
/// the building block for unions of convex pieces, which must be formed before clipping.
#[inline(always)]
pub(crate) fn sphere_line<T: Real>(ray: &Ray<T>, c: V3<T>, r: T, u: T) -> Interval<T> {
    let d2 = ray.d.length2();
    let f = ray.o - c;
    // t of the closest point of the line to c.
    let tc = -f.dot(ray.d) / d2;
    // Perpendicular from c to the line (accurate: no |f|² − (f·d)² cancellation).
    let l = f + ray.d * tc;
    let disc = r * r - l.length2();
    let ok = disc.ge(T::zero()) & r.gt(T::zero());
    let h = (disc.max(T::zero()) / d2).sqrt();
    let t_in = tc - h;
    let t_out = tc + h;
    // Hit points relative to c: l ∓ h·d (no o + t·d − c cancellation).
    // Hit point − c = l ∓ h·d = l ∓ √disc·d̂. Formed with the unit direction so that nothing
    // overflows even when t itself does (radius ≫ |d|), and normalised explicitly: in f32 with
    // |o − c| ≫ r the rounding of l is not small against r.
    let dn = ray.d * (T::one() / d2.sqrt());
    let sq = disc.max(T::zero()).sqrt();
    let n_in = (l - dn * sq).normalize_or_zero();
    let n_out = (l + dn * sq).normalize_or_zero();
    Interval { t_in, t_out, n_in, n_out, u_in: u, u_out: u, hit: ok }.masked(ok)
}
