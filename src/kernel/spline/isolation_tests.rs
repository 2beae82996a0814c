//! `isolate.rs` against the old cascades (`cascade.rs`): the Polynomial solver's answers on
//! every generator region, `f32`, `f64` and lanes.

use super::QuadTube;
use crate::ray::Ray;
use crate::real::{Real, Scalar};
use crate::vec::V3;
use crate::{Solver, WideF32x8, WideF64x4};
use tubecast_oracle::{quad_crossing_offset, thin_case, ThinCase, Vec3, THIN_FAMILIES};

/// The case scaled by `2^k` (exact), in precision `T`.
fn make<T: Scalar>(c: &ThinCase, k: i32) -> Option<(QuadTube<T>, Ray<T>)> {
    let s = 2f64.powi(k);
    let v = |p: Vec3, s: f64| V3::new(T::from_f64(p.x * s), T::from_f64(p.y * s), T::from_f64(p.z * s));
    let tube = QuadTube::new(c.tube.b.map(|p| v(p, s)), c.tube.r.map(|x| T::from_f64(x * s))).ok()?;
    Some((tube, Ray::new(v(c.ray.o, s), v(c.ray.d, s))))
}

/// Band `E` along the ray (ray-parameter units) of a case scaled by `2^k`: `E/|d|`, scale-free.
fn dt(eps: f64, c: &ThinCase) -> f64 {
    (1024.0 * eps * c.extent + 8.0 * eps * c.origin_dist) / c.ray.d.length()
}

/// Whether `(ti, to)` lies in the band `E` (ray units `d`) of the exact tube of `c`, as
/// `tests/spline_conditioning.rs` judges (scaling by `2^k` leaves the ray parameter unchanged).
fn in_band(c: &ThinCase, d: f64, ti: f64, to: f64) -> bool {
    let e = d * c.ray.d.length();
    let Some(infl) = quad_crossing_offset(&c.tube, &c.ray, e) else { return false };
    let (bi, bo) = quad_crossing_offset(&c.tube, &c.ray, -e).unwrap_or((f64::INFINITY, -f64::INFINITY));
    ti >= infl.0 - d && to <= infl.1 + d && ti <= bi + d && to >= bo - d && ti <= to + 2.0 * d
}

/// Every region: `ThinFamily` × `L/r = 1…10⁵` × scales `2^±40` (`2^±20` in `f32`) and 1. The new candidates must
/// not change an answer: the same hit or miss, and where the interval differs at all, the new
/// one inside the band `E` of the exact tube (the property the old one is tested for; the
/// entry of a grazing line is ill-conditioned by the angle, so two answers in the band can be
/// farther apart than `E`). Returns (bit-equal, differing, differing by more than `E`).
fn sweep<T: Scalar>(seeds: u64) -> (usize, usize, usize) {
    let eps = T::EPS.to_f64();
    let (mut same, mut differ, mut far) = (0, 0, 0);
    // 2^±40 in f64, 2^±20 in f32 (whose extent check caps the far cases' squares).
    let scale = if eps < 1e-10 { 40 } else { 20 };
    for family in THIN_FAMILIES {
        for ratio in [1.0, 1e1, 1e2, 1e3, 1e4, 1e5] {
            for seed in 0..seeds {
                let c = thin_case(seed, ratio, family);
                let d = dt(eps, &c);
                for k in [-scale, 0, scale] {
                    // Unscaled cases are valid; a scaled one may exceed the extent check.
                    let Some((tube, ray)) = make::<T>(&c, k) else {
                        assert!(k != 0, "invalid case {c:?}");
                        continue;
                    };
                    let new = tube.line_interval_with(&ray, Solver::Polynomial);
                    let old = tube.line_interval_cascade(&ray);
                    let what = format!("{family:?} L/r={ratio:e} seed {seed} 2^{k}: new {new:?} old {old:?}");
                    assert_eq!(new.hit, old.hit, "{what}");
                    if new == old {
                        same += 1;
                        continue;
                    }
                    differ += 1;
                    let (ni, no, oi, oo) =
                        (new.t_in.to_f64(), new.t_out.to_f64(), old.t_in.to_f64(), old.t_out.to_f64());
                    far += usize::from((ni - oi).abs() > d || (no - oo).abs() > d);
                    // Outside the band only where the old answer had the same entry and exit (the
                    // scaled DirRatio cases in f32, beyond the conditioning test's region).
                    let kept = ni == oi && no == oo;
                    assert!(!new.hit || kept || in_band(&c, d, ni, no), "{what}: outside the band");
                }
            }
        }
    }
    (same, differ, far)
}

#[test]
fn bernstein_candidates_give_the_cascades_answers_f64() {
    let (same, differ, far) = sweep::<f64>(40);
    println!("f64: {same} bit-equal, {differ} differ ({far} by more than E), all in the band");
    // 10 families × 6 ratios × 40 seeds × 3 scales (a scaled case may be invalid: few).
    assert!(same + differ > 7000, "{}", same + differ);
}

#[test]
fn bernstein_candidates_give_the_cascades_answers_f32() {
    let (same, differ, far) = sweep::<f32>(40);
    println!("f32: {same} bit-equal, {differ} differ ({far} by more than E), all in the band");
    assert!(same + differ > 7000, "{}", same + differ);
}

/// Lanes: each lane equals its scalar call bit for bit (different cases per lane, so lanes
/// with different candidate counts share a pack).
fn lanes<T: Real>()
where
    T::Elem: Scalar,
{
    let w = T::LANES;
    let cases: Vec<ThinCase> = THIN_FAMILIES
        .iter()
        .flat_map(|&f| [1.0, 1e2, 1e4, 1e5].into_iter().flat_map(move |r| (0..8).map(move |s| thin_case(s, r, f))))
        .collect();
    let mut hits = 0;
    for pack in cases.chunks_exact(w) {
        let scalars: Vec<_> = pack.iter().map(|c| make::<T::Elem>(c, 0).expect("valid case")).collect();
        let tube = QuadTube::<T>::from_lanes(|i| scalars[i].0);
        let ray = Ray::<T>::from_fn(|i| scalars[i].1);
        let iv = tube.line_interval_with(&ray, Solver::Polynomial);
        for (i, (t, r)) in scalars.iter().enumerate() {
            let s = t.line_interval_with(r, Solver::Polynomial);
            assert_eq!(iv.lane(i), s, "lane {i} of {:?}", pack[i]);
            hits += usize::from(s.hit);
        }
    }
    assert!(hits > cases.len() / 4, "{hits} hits of {}", cases.len());
}

#[test]
fn bernstein_candidates_lanes_equal_scalars() {
    lanes::<WideF32x8>();
    lanes::<WideF64x4>();
}
