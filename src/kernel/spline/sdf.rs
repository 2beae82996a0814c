//! The spline segment's distance-like function, [`quadratic_tube`].

use super::QuadTube;
use crate::math::minimise::golden_section_min;
use crate::math::roots::{poly_breakpoints, poly_mul, Bracket};
use crate::real::Scalar;
use crate::vec::V3;

/// Distance-like function of the sweep: `φ(x) = min_t (|x − p(t)| − r(t))` over `t ∈ [0, 1]`,
/// by exact 1-D minimisation. Outside the tube and on its surface this **is** the exact
/// distance to the sweep (the distance to a union of balls is the least distance to one of
/// them); inside it is `−max_t (r(t) − |x − p(t)|)`, negative, zero on the surface and at most
/// the depth in magnitude.
///
/// The critical points of `|x − p| − r` satisfy `(x − p)·p' = −r'|x − p|`, so they are roots of
/// the degree-6 polynomial `((x − p)·p')² − r'²|x − p|²`; all of them in `[0, 1]` are isolated
/// by the derivative cascade with safeguarded Newton, each is polished by a golden-section
/// search between its neighbours, and `φ` is the least value seen (ends included).
pub fn quadratic_tube<T: Scalar>(x: V3<T>, tube: &QuadTube<T>) -> T {
    let two = T::cst(2.0);
    let [b0, b1, b2] = tube.b;
    // Relative to b₀ (precision), in units of a power of two near the extent (exact scaling;
    // the polynomial below has products of up to six coordinates, and |x − p| squares them,
    // which would underflow for a tube 1e-304 small — fuzz finding
    // regression-tiny-sdf-underflow: the SDF said −r at a surface point — or overflow far out).
    let xr = x - b0;
    let mut e = xr.max_abs();
    for i in 0..3 {
        e = e.max((tube.b[i] - b0).max_abs()).max(tube.r[i].abs());
    }
    let kmax = if T::EPS.to_f64() < 1e-10 { 1000 } else { 120 };
    let k = if e > T::zero() && e.is_finite() { (e.to_f64().log2().floor() as i32).clamp(-kmax, kmax) } else { 0 };
    let (sc, unsc) = (T::from_f64(2f64.powi(-k)), T::from_f64(2f64.powi(k)));
    let (b0, b1, b2) = (V3::zero(), (b1 - b0) * sc, (b2 - b0) * sc);
    let xr = xr * sc;
    let tube = &QuadTube { b: [b0, b1, b2], r: [tube.r[0] * sc, tube.r[1] * sc, tube.r[2] * sc] };
    // p = A t² + B t, D = x − p.
    let a = b0 - b1 * two + b2;
    let b = (b1 - b0) * two;
    let d = [xr, -b, -a];
    let dp = [b, a * two];
    let [r0, r1, r2] = tube.r;
    let rp = [(r1 - r0) * two, (r0 - r1 * two + r2) * two];
    // D·p' (cubic), |D|² (quartic).
    let mut dpp = [T::zero(); 4];
    for i in 0..3 {
        for j in 0..2 {
            dpp[i + j] += d[i].dot(dp[j]);
        }
    }
    let mut dd = [T::zero(); 5];
    for i in 0..3 {
        for j in 0..3 {
            dd[i + j] += d[i].dot(d[j]);
        }
    }
    let s1: [T; 7] = poly_mul(&dpp, &dpp);
    let rp2: [T; 3] = poly_mul(&rp, &rp);
    let s2: [T; 7] = poly_mul(&rp2, &dd);
    let mut q = [T::zero(); 7];
    for i in 0..7 {
        q[i] = s1[i] - s2[i];
    }
    let (bp, n) = poly_breakpoints(&q, T::zero(), T::one(), Bracket::Newton);
    let phi = |t: T| (xr - (a * (t * t) + b * t)).length() - tube.radius(t);
    let mut best = T::infinity();
    for &t in &bp[..n] {
        best = best.min(phi(t));
    }
    // The polynomial's roots can be off where its coefficients cancel (a thin tube far from
    // b₀: |x − p| ≪ |x − b₀|), though φ itself is evaluated to ~ε|x − b₀|. Between the
    // neighbours of a computed root φ has one critical point, so a golden-section search
    // there polishes it (every value it sees is a value of φ: the minimum can only improve).
    for i in 1..n - 1 {
        best = golden_section_min(phi, bp[i - 1], bp[i + 1], T::epsilon() * T::cst(4.0), 100, best);
    }
    best * unsc
}
