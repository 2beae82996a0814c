//! Error-bounded simplification against the independent oracle (`tubecast-oracle`): at random
//! points near the tube, the oracle's `min_u |x − p(u)| − r(u)` of the original union and of
//! the simplified one differ by at most the bound `D ≤ ε` (so the solids are within ε both
//! ways: outside it is the exact distance, and each solid is its zero sublevel set).

use tubecast_oracle::link::{sweep_dist, Link};
use tubecast_oracle::rng::{splitmix, FloatRng};
use tubecast_oracle::Vec3;
use tubecast_render::scene::simplify::{merge_bound, simplify_chain};

fn field(nodes: &[([f64; 3], f64)], x: Vec3) -> f64 {
    let v = |p: [f64; 3]| Vec3::new(p[0], p[1], p[2]);
    nodes
        .windows(2)
        .map(|w| sweep_dist(&Link { a: v(w[0].0), ra: w[0].1, b: v(w[1].0), rb: w[1].1 }, x).0)
        .fold(f64::INFINITY, f64::min)
}

/// A wiggly tapering chain: gentle curvature with noise, scaled by `s`, shifted by `off`.
fn chain(seed: u64, n: usize, s: f64, off: f64) -> Vec<([f64; 3], f64)> {
    let mut rng = splitmix(seed);
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.15;
            let p = [
                off + s * (t + 0.02 * rng.range(-1.0, 1.0)),
                s * (0.6 * t.sin() + 0.02 * rng.range(-1.0, 1.0)),
                s * 0.3 * (0.5 * t).cos(),
            ];
            (p, s * (0.3 - 0.002 * i as f64 + 0.01 * rng.range(-1.0, 1.0)))
        })
        .collect()
}

#[test]
fn simplified_chains_stay_within_eps_of_the_original() {
    for (seed, s, off) in [(1u64, 1.0, 0.0), (2, 1e-4, 0.0), (3, 1e4, 0.0), (4, 1.0, 1e6)] {
        let nodes = chain(seed, 80, s, off);
        for rel in [1e-3, 1e-2, 5e-2] {
            let eps = rel * s;
            let (keep, d) = simplify_chain(&nodes, eps);
            assert!(d <= eps && keep.len() >= 2 && keep[0] == 0 && keep[keep.len() - 1] == nodes.len() - 1);
            let simple: Vec<_> = keep.iter().map(|&i| nodes[i]).collect();
            // Oracle rounding: sweep_dist's argmin is exact to ~1e-15 relative to the scene scale
            // (|off| + 15 s); 1e-12 of that covers both fields.
            let tol = d + 1e-12 * (off.abs() + 15.0 * s);
            let mut rng = splitmix(seed * 31);
            for _ in 0..400 {
                let k = (rng.uniform() * (nodes.len() - 1) as f64) as usize;
                let c = nodes[k].0;
                let u = rng.unit();
                let r = s * rng.range(0.0, 0.6);
                let x = Vec3::new(c[0] + u[0] * r, c[1] + u[1] * r, c[2] + u[2] * r);
                let (f, g) = (field(&nodes, x), field(&simple, x));
                assert!((f - g).abs() <= tol, "seed {seed} ε {eps}: fields {f} vs {g} differ by more than D = {d}");
            }
            if rel >= 1e-2 {
                assert!(keep.len() < nodes.len(), "ε {eps}: nothing merged");
            }
        }
    }
}

#[test]
fn the_bound_is_attained_by_a_bent_pair() {
    // Two links bent by h at the middle node: the merged link misses that ball by exactly h
    // (projection s = ½, same radius), and the field differs by h just outside it.
    let h = 0.05;
    let nodes = [([0.0, 0.0, 0.0], 0.2), ([1.0, h, 0.0], 0.2), ([2.0, 0.0, 0.0], 0.2)];
    let d = merge_bound(&nodes);
    assert!((d - h).abs() < 1e-12);
    let x = Vec3::new(1.0, h + 0.2 + 0.01, 0.0);
    let (f, g) = (field(&nodes, x), field(&[nodes[0], nodes[2]], x));
    assert!((g - f - h).abs() < 1e-9, "{f} {g}");
    assert_eq!(simplify_chain(&nodes, 0.9 * h).0, vec![0, 1, 2]);
    assert_eq!(simplify_chain(&nodes, 1.1 * h).0, vec![0, 2]);
}
