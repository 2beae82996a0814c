//! Generated trees that stress the union: pinched (two tubes whose surfaces nearly touch),
//! tangent (touching exactly), nested, coincident (the same link twice) and zero-length
//! links, on random branching trees. Cases: `PROPTEST_CASES` (default 8 here, to keep the
//! suite to seconds).

use super::{check, checks, line};
use proptest::prelude::*;
use tubecast_render::scene::Scene;

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(8)
}

/// A random tree: `n` nodes, each hung off an earlier one with a random step and radius;
/// `twist` picks the stress: 0 plain, 1 a coincident copy of a branch, 2 a zero-length link,
/// 3 a tube nested in another, 4 a tube tangent to the trunk, 5 one pinched (a gap of 1e-3).
fn tree(n: usize, seed: u64, twist: u8) -> Scene {
    let mut rng = tubecast_render::scene::generate::Rng::new(seed);
    let mut pts: Vec<[f64; 3]> = vec![[0.0; 3]];
    let mut rad: Vec<f64> = vec![0.5];
    let mut lines = Vec::new();
    for _ in 1..n {
        let parent = (rng.uniform() * pts.len() as f64) as usize % pts.len();
        let d = rng.unit();
        let len = rng.range(0.6, 2.0);
        let p = pts[parent];
        let q = [p[0] + len * d[0], p[1] + len * d[1], p[2] + len * d[2]];
        let r = rng.range(0.25, 0.6);
        lines.push(line(&[p, q], &[rad[parent], r]));
        pts.push(q);
        rad.push(r);
    }
    let last = lines.last().cloned().unwrap_or_else(|| line(&[[0.0; 3], [1.0, 0.0, 0.0]], &[0.5, 0.5]));
    match twist {
        1 => lines.push(last),
        2 => lines.push(line(&[pts[pts.len() - 1], pts[pts.len() - 1]], &[0.4, 0.4])),
        3 => {
            let (p, q) = (last.points[0], last.points[1]);
            let m = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, (p[2] + q[2]) / 2.0];
            lines.push(line(&[p, m], &[0.1, 0.1]));
        }
        4 | 5 => {
            // A sphere-capped tube parallel to the first link's axis, at distance ra + r (+ gap).
            let (p, q, ra) = (lines[0].points[0], lines[0].points[1], lines[0].radii[0].min(lines[0].radii[1]));
            let gap = if twist == 4 { 0.0 } else { 1e-3 };
            let ax = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let side = if ax[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
            let mut o = [
                ax[1] * side[2] - ax[2] * side[1],
                ax[2] * side[0] - ax[0] * side[2],
                ax[0] * side[1] - ax[1] * side[0],
            ];
            let l = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            o = o.map(|v| v / l);
            let (r, dist) = (0.3, ra + 0.3 + gap);
            let off = |c: [f64; 3]| [c[0] + dist * o[0], c[1] + dist * o[1], c[2] + dist * o[2]];
            let r_equal = lines[0].radii[0] == lines[0].radii[1];
            if r_equal {
                lines.push(line(&[off(p), off(q)], &[r, r]));
            } else {
                // Tangent to the larger end's sphere only: a ball beside it.
                let (c, rc) = if lines[0].radii[0] >= lines[0].radii[1] {
                    (p, lines[0].radii[0])
                } else {
                    (q, lines[0].radii[1])
                };
                let b = [c[0] + (rc + r + gap) * o[0], c[1] + (rc + r + gap) * o[1], c[2] + (rc + r + gap) * o[2]];
                lines.push(line(&[b, b], &[r, r]));
            }
        }
        _ => {}
    }
    Scene::from_polylines(&lines, 0.4, "tree").unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]
    /// Closed, oriented, embedded, and every vertex and triangle within the bound it certifies,
    /// for every twist. Within ε too is held only on the named trees below: on random plain
    /// trees the certified bound still exceeds ε where a sharp notch (`sin(β/2)` ≲ 0.15) or a
    /// crease buried in a third tube beside a triple point keeps a triangle bridging it (9 of
    /// 135 generated trees at ε = 2e-2, see `sweep` and `docs/design/union-mesh.md`). That is
    /// an open defect of the mesher, not of this test: the bound the mesh reports is checked
    /// against the exact union either way.
    #[test]
    fn random_trees_are_watertight(n in 2usize..6, seed in 0u64..1_000_000, twist in 0u8..6) {
        let s = tree(n, seed, twist);
        let (m, rep) = check(&s, 2e-2, false);
        prop_assert!(checks::components(&m) >= 1);
        prop_assert!(rep.certified().is_finite() || twist >= 4);
    }
}

/// CI's failing case: a plain tree of five nodes where two tubes meet in a notch of about 40°
/// (`sin(β/2)` 0.32) and the contour's crossing edges pass within a fraction of a grid step
/// of the crease at a grid vertex. Splitting there left slivers that turned over, the splits
/// were refused, and 15 triangles stood out by up to half a step (certified 8.4e-2). The
/// vertex is now moved onto the crease instead (`crease.rs`, `snap`).
#[test]
fn plain_tree_5_492317_meets_eps() {
    let (_, rep) = check(&tree(5, 492317, 0), 2e-2, true);
    assert_eq!(rep.outside, 0, "{rep:?}");
}

/// A coincident copy of a branch beside a sharp notch: the crease lies more than a grid step
/// below the contour's edges across the notch (Newton's crease point must be allowed that far).
#[test]
fn coincident_tree_5_227841_meets_eps() {
    check(&tree(5, 227841, 1), 2e-2, true);
}

/// A crease through a vertex already split onto it: the edge beside it is flipped, not split.
#[test]
fn plain_tree_5_227858_meets_eps() {
    check(&tree(5, 227858, 0), 2e-2, true);
}

/// The sweep behind the design note's figure: plain, coincident and zero-length trees of 3–5
/// nodes, seeds k·7919 mod 10⁶, at ε = 2e-2; prints each tree's report and, for the triangles
/// that stand out of the union, what their corners are on (a diagnostic, not a check):
/// `cargo test -p tubecast-render --test union_mesh sweep -- --ignored --nocapture`.
#[test]
#[ignore]
fn sweep() {
    use super::checks::{sdf, tubes};
    use tubecast::Primitive;
    let eps = 2e-2;
    let (mut ok, mut all, mut worst) = (0, 0, 0.0f64);
    for n in 3..=5 {
        for twist in 0..=2u8 {
            for k in 1..=15u64 {
                let seed = k * 7919 % 1_000_000;
                if let Ok(only) = std::env::var("SWEEP_ONLY") {
                    if only != format!("{n},{seed},{twist}") {
                        continue;
                    }
                }
                let s = tree(n, seed, twist);
                let t0 = std::time::Instant::now();
                let (m, rep) = tubecast_render::mesh::tessellate_union(&s, eps).unwrap();
                let dt = t0.elapsed();
                all += 1;
                let c = rep.certified();
                worst = worst.max(c / eps);
                if c <= eps {
                    ok += 1;
                    continue;
                }
                println!(
                    "FAIL n={n} seed={seed} twist={twist}: certified {c:.3e} depth {:.3e} out {:.3e} outside {} sin {:.3} tries {} h {:.3e} tris {} {dt:.2?}",
                    rep.depth, rep.out, rep.outside, rep.min_sin_half, rep.tries, rep.step, m.mesh.triangles.len()
                );
                let ts = tubes(&s);
                let tol = 1e-8 * rep.step;
                for k in 0..m.mesh.triangles.len() {
                    let p = m.mesh.corners(k);
                    let b = ts
                        .iter()
                        .map(|t| p.iter().map(|&v| t.sdf(v)).fold(f64::MIN, f64::max))
                        .fold(f64::MAX, f64::min);
                    if b <= 1e-8 * rep.step {
                        continue;
                    }
                    let on: Vec<Vec<usize>> =
                        p.iter().map(|&v| (0..ts.len()).filter(|&i| ts[i].sdf(v) <= tol).collect()).collect();
                    // Each edge whose ends share no tube: how many tubes are least along it.
                    let mut what = Vec::new();
                    for e in 0..3 {
                        let (a, bb) = (&on[e], &on[(e + 1) % 3]);
                        if a.iter().any(|x| bb.contains(x)) {
                            continue;
                        }
                        let mut least: Vec<usize> = (0..=20)
                            .map(|j| {
                                let x = p[e] + (p[(e + 1) % 3] - p[e]) * (j as f64 / 20.0);
                                (0..ts.len()).min_by(|&i, &l| ts[i].sdf(x).total_cmp(&ts[l].sdf(x))).unwrap()
                            })
                            .collect();
                        least.dedup();
                        what.push(least);
                    }
                    let mid = (p[0] + p[1] + p[2]) * (1.0 / 3.0);
                    println!(
                        "  tri {k}: b {b:.2e} ({:.2} h) f(centroid) {:.2e} on {on:?} edges' least tubes {what:?}",
                        b / rep.step,
                        sdf(&ts, mid)
                    );
                }
            }
        }
    }
    println!("{ok} of {all} within eps; worst certified/eps {worst:.3}");
}
