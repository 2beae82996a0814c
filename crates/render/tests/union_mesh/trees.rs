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
    /// Closed, oriented, embedded, every vertex and triangle within the bound it certifies
    /// (true distance to the union), and within ε, for every twist. Tangent tubes (twist 4)
    /// touch from outside: the exterior reaches the tangency, so the witnesses stay about the
    /// sagitta away; pinched ones (twist 5) leave a gap. Only tubes overlapping at a narrow
    /// angle (`narrow_crease_is_honest_and_reported`) may miss ε.
    #[test]
    fn random_trees_are_watertight(n in 2usize..6, seed in 0u64..1_000_000, twist in 0u8..6) {
        let s = tree(n, seed, twist);
        let (m, rep) = check(&s, 2e-2, true);
        prop_assert!(checks::components(&m) >= 1);
        prop_assert!(rep.certified().is_finite());
    }
}

/// Two equal cylinders (r = 0.5) whose axes are 2r − 10⁻³ apart overlap in a crease of
/// `sin(β/2) ≈ √(10⁻³/r) ≈ 0.045`: once the polyhedra overlap there (sagitta below the overlap),
/// the bound is about the sagitta over that, 22× the sagitta. The refinement to the sagitta
/// at which that opening meets ε brings it within ε = 10⁻² in one rebuild; where the budget
/// does not, the mesh stays closed, one component and honest (the witnesses check the true
/// depth), and the report counts the triangles that exceed ε (the CLI warns).
#[test]
fn narrow_crease_is_honest_and_reported() {
    // Axes along a generic direction, so that no polyhedron edge lies along the crease.
    let u = tubecast::V3::new(1.0, 0.37, 0.21);
    let u = u * (2.0 / u.length());
    let w = u.cross(tubecast::V3::new(0.3, 0.5, 0.8));
    let w = w * ((1.0 - 1e-3) / w.length());
    let p = |v: tubecast::V3<f64>| [v.x, v.y, v.z];
    let o = tubecast::V3::new(0.0, 0.0, 0.0);
    let lines = [line(&[p(o), p(u)], &[0.5, 0.5]), line(&[p(w), p(u + w)], &[0.5, 0.5])];
    let s = Scene::from_polylines(&lines, 0.5, "t").unwrap();
    let (m, rep) = check(&s, 1e-2, false);
    assert_eq!(checks::components(&m), 1, "{rep:?}");
    assert!(rep.min_sin_half < 0.06, "{rep:?}");
    assert!(rep.depth > 10.0 * rep.sagitta, "the crease, not the sagitta, sets the bound: {rep:?}");
    if rep.certified() > 1e-2 {
        assert!(rep.outside > 0 && rep.tries == 4, "every build made: {rep:?}");
    }
}

/// Trees that the contour mesher failed (a notch of 40°, a coincident copy beside a sharp
/// notch, a crease through a split vertex): kept as regressions of the union at ε.
#[test]
fn plain_tree_5_492317_meets_eps() {
    let (_, rep) = check(&tree(5, 492317, 0), 2e-2, true);
    assert_eq!(rep.outside, 0, "{rep:?}");
}

#[test]
fn coincident_tree_5_227841_meets_eps() {
    check(&tree(5, 227841, 1), 2e-2, true);
}

#[test]
fn plain_tree_5_227858_meets_eps() {
    check(&tree(5, 227858, 0), 2e-2, true);
}

/// The notches the contour could not follow (`sin(β/2)` 0.07–0.14): n = 4 seed 7919 in all
/// three twists, n = 5 seed 95028 with a zero-length link.
#[test]
fn sharp_notch_trees_meet_eps() {
    for (n, seed, twist) in [(4, 7919, 0), (4, 7919, 1), (4, 7919, 2), (5, 95028, 2), (5, 7919, 0), (5, 95028, 0)] {
        let (_, rep) = check(&tree(n, seed, twist), 2e-2, true);
        assert!(rep.certified() <= 2e-2, "n {n} seed {seed} twist {twist}: {rep:?}");
    }
}

/// A ball tangent to (or 10⁻³ from) a node's sphere where a link's side bulges past it: the
/// ball overlaps the link by a hair, in a lens whose crease nearly faces itself (`sin(β/2)`
/// down to 0.02). Until the polyhedra overlap inside the lens (a sagitta below the overlap),
/// a vertex of one polyhedron in the lens lies as deep as the lens's radius however fine the
/// spheres: 0.016–0.025 here (a brute-force search of the exterior, 4,000 directions per
/// radius step of 10⁻⁴), against ε = 0.02. The certificate must find the crease's nearest
/// point, and the spheres must be refined to the sagitta at which the lens's opening meets ε
/// (the excess does not fall with the sagitta until then). They certified 2.38·10⁻²,
/// 3.36·10⁻², 2.31·10⁻², 2.95·10⁻², 3.42·10⁻² and 2.52·10⁻² (random-tree counterexamples).
#[test]
fn lens_trees_meet_eps() {
    for (n, seed, twist) in
        [(3, 102947, 4), (5, 39941, 4), (3, 75593, 4), (4, 315086, 4), (4, 518123, 5), (3, 710947, 5)]
    {
        let (_, rep) = check(&tree(n, seed, twist), 2e-2, true);
        assert_eq!(rep.outside, 0, "n {n} seed {seed} twist {twist}: {rep:?}");
    }
}

/// A certified bound within a hair of the true depth (2.0·10⁻² against 1.95–1.99·10⁻², a
/// vertex at the joint of three links): the exterior at the bound's distance is then a small
/// cap, which the check's 4,000 directions missed until the least inside was climbed
/// (random-tree counterexamples).
#[test]
fn tight_bound_trees_are_witnessed() {
    // Also n = 5, seed 620018: certified 1.99533·10⁻², true depth 1.9930–1.9950·10⁻² (a
    // radial search, 2·10⁶ directions per radius), beyond 400,000 directions' reach (tried).
    for (n, seed) in [(4, 453), (5, 620018)] {
        check(&tree(n, seed, 0), 2e-2, true);
    }
}

/// The sweep behind the design note's figure: trees of 3–5 nodes in every twist (plain,
/// coincident, zero-length, nested, tangent, pinched), seeds k·7919 mod 10⁶, at ε = 2e-2;
/// prints the report of each tree that misses ε and the count per twist (a diagnostic, not a
/// check):
/// `cargo test -p tubecast-render --test union_mesh sweep -- --ignored --nocapture`.
#[test]
#[ignore]
fn sweep() {
    let eps = 2e-2;
    let (mut ok, mut all, mut worst) = ([0; 6], [0; 6], [0.0f64; 6]);
    // `SWEEP_ONLY=n,seed,twist` runs that one tree (any seed, e.g. a proptest failure).
    let only: Option<(usize, u64, u8)> = std::env::var("SWEEP_ONLY").ok().map(|v| {
        let f: Vec<&str> = v.split(',').collect();
        (f[0].parse().unwrap(), f[1].parse().unwrap(), f[2].parse().unwrap())
    });
    let cases: Vec<(usize, u64, u8)> = match only {
        Some(c) => vec![c],
        None => (3..=5)
            .flat_map(|n| (0..=5u8).flat_map(move |tw| (1..=15u64).map(move |k| (n, k * 7919 % 1_000_000, tw))))
            .collect(),
    };
    for (n, seed, twist) in cases {
        let tw = twist as usize;
        let s = tree(n, seed, twist);
        let t0 = std::time::Instant::now();
        let (m, rep) = tubecast_render::mesh::tessellate_union(&s, eps).unwrap();
        let dt = t0.elapsed();
        all[tw] += 1;
        let c = rep.certified();
        worst[tw] = worst[tw].max(c / eps);
        if c <= eps {
            ok[tw] += 1;
            continue;
        }
        println!(
            "FAIL n={n} seed={seed} twist={twist}: certified {c:.3e} {rep:?} tris {} {dt:.2?}",
            m.mesh.triangles.len()
        );
    }
    for tw in 0..6 {
        println!("twist {tw}: {} of {} within eps; worst certified/eps {:.3}", ok[tw], all[tw], worst[tw]);
    }
}
