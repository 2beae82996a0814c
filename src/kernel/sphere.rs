//! Ray–sphere interval.
//!
//! The origin is moved to the point of the line closest to the centre before the quadratic is
//! formed (the "Ray Tracing Gems" ch. 7 formulation), so the discriminant is computed from a
//! vector of length ≈ distance(line, centre) rather than from `|o − c|²`: far origins lose only
//! what representing `o` itself loses.

use crate::math::quadric::{sphere_chord, Chord};
use crate::ray::{Crossing, Interval, Ray};
use crate::real::Real;
use crate::vec::V3;

/// Interval of the ray's **line** with the ball `|x − c| ≤ r`, with unit outward normals
/// ([`crate::Sphere`] clips it to the ray): `hit` only says the line meets the ball, the
/// building block for unions of convex pieces, which must be formed before clipping.
///
/// `u_in`/`u_out` are set to `u` (the caller's curve parameter for this sphere, e.g. 0 or 1
/// for a link's end spheres). Lanes with `r ≤ 0` miss. Never NaN for finite input with `d ≠ 0`.
#[inline(always)]
pub(crate) fn sphere_line<T: Real>(ray: &Ray<T>, c: V3<T>, r: T, u: T) -> Interval<T> {
    // Unit direction: the closest-point parameter and the half chord are formed in units of
    // length (τ), so nothing over/underflows because |d| is far from 1; t = τ/|d|.
    let dl = ray.d.length();
    let dn = ray.d * (T::one() / dl);
    let Chord { tc, h, l, ok } = sphere_chord(ray.o, dn, c, r);
    let inv_dl = T::one() / dl;
    let t_in = (tc - h) * inv_dl;
    let t_out = (tc + h) * inv_dl;
    // Hit point − c = l ∓ h·d̂, normalised explicitly: in f32 with |o − c| ≫ r the rounding
    // of l is not small against r.
    let n_in = (l - dn * h).normalize_or_zero();
    let n_out = (l + dn * h).normalize_or_zero();
    Interval::new(Crossing { t: t_in, n: n_in, u }, Crossing { t: t_out, n: n_out, u }, ok).masked(ok)
}
