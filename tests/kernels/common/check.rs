//! The oracle check of one link-kernel result, with the error analysis of `tests/kernels/link/properties.rs`
//! (module docs there): shared by the link property tests and the extreme-scale tests.

use super::*;
use proptest::prelude::*;
use tubecast::{Interval, LinkShape, RoundCone, Scalar};

/// Distance error bound E for precision with unit roundoff `eps` (see the module docs):
/// `64·ε·(S + D)` plus the nearly-flat-stump term (derived at `tubecast_oracle::link_error_bound`,
/// shared with the fuzz check and the reports).
pub fn bound(c: &Case, eps: f64) -> f64 {
    tubecast_oracle::link_error_bound(&olink(&c.link), ov(c.ray.o), c.size, eps)
}

/// The tip term of a `t` tolerance near a pointed end (derived at
/// [`tubecast_oracle::link_tip_term`], shared with the differential fuzz check).
pub fn tip_term(l: &RoundCone<f64>, e: f64) -> f64 {
    tubecast_oracle::link_tip_term(&olink(l), e)
}

pub fn no_nan<T: Scalar>(iv: &Interval<T>) -> bool {
    let f = |x: T| !x.to_f64().is_nan();
    f(iv.entry.t)
        && f(iv.exit.t)
        && f(iv.entry.u)
        && f(iv.exit.u)
        && [iv.entry.n, iv.exit.n].iter().all(|n| f(n.x) && f(n.y) && f(n.z))
}

/// Check one kernel result (converted to f64) against the oracle. `eps`: kernel precision.
pub fn check_against_oracle(c: &Case, iv: Interval<f64>, eps: f64, what: &str) -> Result<(), TestCaseError> {
    prop_assert!(no_nan(&iv), "{what}: NaN in {iv:?}");
    let e = bound(c, eps);
    let e64 = bound(c, f64::EPSILON);
    let dl = c.ray.d.length();
    let (gap, _) = line_gap(&c.link, &c.ray);
    let oracle = line_interval(&c.link, &c.ray);
    // Range overlap of the oracle interval, with the t tolerance of a perpendicular hit.
    let t_tol = (e + e64) / dl;
    let must_hit = gap < -e && oracle.is_some_and(|o| o.t_out > c.ray.t_min + t_tol);
    let must_miss = gap > e || oracle.is_some_and(|o| o.t_out < c.ray.t_min - t_tol);
    if must_hit {
        prop_assert!(iv.hit, "{what}: false miss, gap {gap:e} (E {e:e}), oracle {oracle:?}");
    }
    if must_miss {
        prop_assert!(!iv.hit, "{what}: false hit, gap {gap:e} (E {e:e}), got {iv:?}");
    }
    if !iv.hit {
        return Ok(());
    }
    prop_assert!(iv.entry.t <= iv.exit.t);
    for (t, n, u, o_t, entering) in [
        (iv.entry.t, iv.entry.n, iv.entry.u, oracle.map(|o| o.t_in), true),
        (iv.exit.t, iv.exit.n, iv.exit.u, oracle.map(|o| o.t_out), false),
    ] {
        let x = c.ray.at(t);
        let (sd, us) = sweep_dist(&c.link, x);
        prop_assert!(
            sd.abs() <= e + e64,
            "{what}: hit point off the surface by {sd:e} > {:e} (entering {entering})",
            e + e64
        );
        // Normal: unit, and equal to the oracle gradient at the same point.
        prop_assert!((n.length() - 1.0).abs() <= 16.0 * eps, "{what}: |n| = {}", n.length());
        // Around the axis the cone's normal turns with the radius of its circle, r(u)·c.
        let cc = {
            let len = (c.link.b - c.link.a).length();
            let s = if len > 0.0 { ((c.link.ra - c.link.rb) / len).clamp(-1.0, 1.0) } else { 0.0 };
            ((1.0 - s) * (1.0 + s)).sqrt()
        };
        let cc = if c.link.shape() == LinkShape::Sphere { 1.0 } else { cc };
        let r_min = c.link.ra.min(c.link.rb).max(r_at(&c.link, us)) * cc;
        let ng = sweep_normal(&c.link, x);
        // At the tip of a zero-radius end the surface has no normal: nothing to compare.
        if r_min > 0.0 && ng.length() > 0.5 {
            // Near a seam (sphere tangent to cone) a point within E of the surface may be
            // reported by either piece; the two surfaces separate like a²/(2r) at arc distance
            // a from the seam, so both are within E for a ≤ √(2rE), where their normals differ
            // by a/r = √(2E/r).
            let ee = e + e64;
            let n_tol = 4.0 * ee / r_min + (2.0 * ee / r_min).sqrt() + 16.0 * eps;
            prop_assert!((n - ng).length() <= n_tol, "{what}: normal {n:?} vs oracle {ng:?} (tol {n_tol:e})");
        }
        // t against the oracle's t, through the incidence cosine at the oracle's hit.
        if let Some(ot) = o_t {
            let gamma = sweep_normal(&c.link, c.ray.at(ot)).dot(c.ray.d).abs() / dl;
            // No normal (and no conditioning statement) at the tip of a zero-radius end.
            if !gamma.is_finite() {
                continue;
            }
            let tol = (e + e64) / (gamma * dl) + tip_term(&c.link, e + e64) / dl + 1e-12 * ot.abs();
            prop_assert!((t - ot).abs() <= tol, "{what}: t {t} vs oracle {ot} (tol {tol:e}, γ {gamma:e})");
        }
        // Curve parameter (undefined for a link that is a single sphere).
        if c.link.shape() != LinkShape::Sphere {
            let v = c.link.b - c.link.a;
            let s = (c.link.ra - c.link.rb) / v.length();
            // Plus the seam term: within arc √(2·r·E) of a seam either piece's u may be reported.
            let lc2 = v.length() * (1.0 - s * s);
            let seam = (2.0 * c.link.ra.max(c.link.rb) * (e + e64)).sqrt() / lc2;
            let tol_u = 2.0 * (e + e64) / lc2 + seam + 16.0 * eps;
            prop_assert!((u - us).abs() <= tol_u, "{what}: u {u} vs oracle {us} (tol {tol_u:e})");
        }
    }
    Ok(())
}

pub fn iv64<T: Scalar>(iv: Interval<T>) -> Interval<f64> {
    iv.to_f64()
}
