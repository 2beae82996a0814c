//! OBB / AABB of a quadratic sphere sweep (Russig §3.2): conservative, tight, degenerate
//! frames, and the OBB/AABB volume ratio. `PROPTEST_CASES` raises the case counts.

use super::common::*;
use proptest::prelude::*;
use tubecast::{Obb, QuadTube, V3};

/// Fibonacci-sphere directions.
fn dirs(n: usize) -> Vec<[f64; 3]> {
    let ga = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            [s * (ga * i as f64).cos(), s * (ga * i as f64).sin(), z]
        })
        .collect()
}

/// Every sampled point of every sphere of the sweep is inside the box (slack: the box and
/// the local coordinates are each a few dot products of size-S numbers: ≤ 16εS).
fn check_conservative(b: &[[f64; 3]; 3], r: &[f64; 3], bx: &Obb<f64>) -> Result<(), TestCaseError> {
    let s = scale(b, r) + 1.0;
    let slack = 16.0 * f64::EPSILON * s;
    let ds = dirs(64);
    for k in 0..=200 {
        let (p, rr) = eval(b, r, k as f64 / 200.0);
        for u in &ds {
            let x = V3::new(p[0] + rr * u[0], p[1] + rr * u[1], p[2] + rr * u[2]);
            let l = bx.local(x);
            prop_assert!(l.x >= bx.lo.x - slack && l.x <= bx.hi.x + slack, "x {l:?} {bx:?}");
            prop_assert!(l.y >= bx.lo.y - slack && l.y <= bx.hi.y + slack, "y {l:?} {bx:?}");
            prop_assert!(l.z >= bx.lo.z - slack && l.z <= bx.hi.z + slack, "z {l:?} {bx:?}");
        }
    }
    Ok(())
}

/// Each face touches the tube: the support max_t(a·p(t) + r(t)) found independently (dense
/// samples + golden section to 1e-12 in t; the support is smooth with |d/dt| ≤ 4S, so its
/// error is ≤ 1e-11·S, plus the box's rounding 16εS) equals the face.
fn check_tight(b: &[[f64; 3]; 3], r: &[f64; 3], bx: &Obb<f64>) -> Result<(), TestCaseError> {
    let s = scale(b, r) + 1.0;
    let tol = 1e-11 * s + 16.0 * f64::EPSILON * s;
    for (k, a) in bx.axes.iter().enumerate() {
        for sign in [1.0, -1.0] {
            let sup = |t: f64| {
                let (p, rr) = eval(b, r, t);
                sign * ((p[0] - b[0][0]) * a.x + (p[1] - b[0][1]) * a.y + (p[2] - b[0][2]) * a.z) + rr
            };
            let n = 2000;
            let kb = (0..=n).max_by(|&i, &j| sup(i as f64 / n as f64).total_cmp(&sup(j as f64 / n as f64))).unwrap();
            let (mut lo, mut hi) = (((kb as f64 - 1.0) / n as f64).max(0.0), ((kb as f64 + 1.0) / n as f64).min(1.0));
            while hi - lo > 1e-12 {
                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                if sup(m1) < sup(m2) {
                    lo = m1
                } else {
                    hi = m2
                }
            }
            let best = sup(lo).max(sup(hi)).max(sup(kb as f64 / n as f64));
            let face = if sign > 0.0 { [bx.hi.x, bx.hi.y, bx.hi.z][k] } else { -[bx.lo.x, bx.lo.y, bx.lo.z][k] };
            prop_assert!((face - best).abs() <= tol, "axis {k} sign {sign}: face {face} vs support {best}");
        }
    }
    Ok(())
}

/// The identity-frame box (the tube's `Aabb`, before it is moved to world coordinates).
fn axis_aligned(t: &QuadTube<f64>) -> Obb<f64> {
    Obb::with_axes(t, [V3::new(1.0, 0.0, 0.0), V3::new(0.0, 1.0, 0.0), V3::new(0.0, 0.0, 1.0)])
}

fn orthonormal(bx: &Obb<f64>) -> bool {
    let a = bx.axes;
    let ok = |x: f64, y: f64| (x - y).abs() < 1e-12;
    (0..3).all(|i| ok(a[i].length(), 1.0))
        && ok(a[0].dot(a[1]), 0.0)
        && ok(a[0].dot(a[2]), 0.0)
        && ok(a[1].dot(a[2]), 0.0)
        && ok(a[0].cross(a[1]).dot(a[2]), 1.0)
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn obb_and_aabb_conservative_and_tight((b, r) in tube_strategy(0.0, 0.6), kind in 0u8..4) {
        let mut b = b;
        match kind {
            1 => b[1] = [0.3 * b[0][0] + 0.7 * b[2][0], 0.3 * b[0][1] + 0.7 * b[2][1], 0.3 * b[0][2] + 0.7 * b[2][2]], // collinear
            2 => b[2] = b[0],  // zero chord
            3 => { b[1] = b[0]; b[2] = b[0]; } // a sphere
            _ => {}
        }
        let t = tube(&b, &r);
        for bx in [Obb::fit(&t), axis_aligned(&t)] {
            prop_assert!(orthonormal(&bx), "{bx:?}");
            check_conservative(&b, &r, &bx)?;
            check_tight(&b, &r, &bx)?;
        }
    }
}

/// Reported figure: OBB volume / AABB volume over random segments (deterministic stream).
#[test]
fn volume_ratio_report() {
    use proptest::strategy::{Strategy, ValueTree};
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strat = tube_strategy(0.02, 0.3);
    let mut ratios = Vec::new();
    for _ in 0..2000 {
        let (b, r) = strat.new_tree(&mut runner).unwrap().current();
        let t = tube(&b, &r);
        let (o, a) = (Obb::fit(&t), axis_aligned(&t));
        // Both boxes contain the sweep, so both volumes are at least the tube's positive volume.
        assert!(o.volume() > 0.0 && a.volume() > 0.0);
        ratios.push(o.volume() / a.volume());
    }
    ratios.sort_by(f64::total_cmp);
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let med = ratios[ratios.len() / 2];
    eprintln!(
        "OBB/AABB volume: mean {mean:.3}, median {med:.3}, p10 {:.3}, p90 {:.3}, max {:.3}",
        ratios[200], ratios[1800], ratios[1999]
    );
    assert!(ratios.iter().all(|x| x.is_finite()));
}
