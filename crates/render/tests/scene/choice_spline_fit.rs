//! Quadratic-spline fitting in the automatic choice ([`choose_with`], [`fit_quad`]): arcs
//! collapse to a few quadratic pieces whose certified bound holds against the oracle, zigzags
//! are not fitted, straight runs stay single links, degenerate input never panics.

use tubecast_oracle::rng::{splitmix, FloatRng};
use tubecast_oracle::{sweep_dist, Link, Quad, Vec3};
use tubecast_render::io::Polyline;
use tubecast_render::scene::choice::{choose, choose_with, Choice, Tolerance};
use tubecast_render::scene::fit::fit_quad;
use tubecast_render::scene::{PrimKind, Scene};

fn v(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

/// The oracle's distance outside a quadratic sweep, sampled at `n + 1` parameters, and the
/// sampling error: `φ(t) = |x − q(t)| − ρ(t)` is Lipschitz with `L ≤ max|q'| + max|ρ'|`, both
/// derivatives linear in `t` (largest at an end: `2|b₁ − b₀|`, `2|b₂ − b₁|`), and the true
/// minimiser is within `1/(2n)` of a sample, so the sampled minimum exceeds the true one by at
/// most `L/(2n)` and never falls below it.
fn quad_field(q: &Quad, x: Vec3, n: usize) -> (f64, f64) {
    let d = (0..=n).map(|i| i as f64 / n as f64).map(|t| (x - q.point(t)).length() - q.radius(t));
    let lq = 2.0 * (q.b[1] - q.b[0]).length().max((q.b[2] - q.b[1]).length());
    let lr = 2.0 * (q.r[1] - q.r[0]).abs().max((q.r[2] - q.r[1]).abs());
    (d.fold(f64::INFINITY, f64::min), (lq + lr) / (2.0 * n as f64))
}

fn link_field(links: &[Link], x: Vec3) -> f64 {
    links.iter().map(|l| sweep_dist(l, x).0).fold(f64::INFINITY, f64::min)
}

fn arc(n: usize, radius: f64, angle: f64, tube: f64) -> Scene {
    let pts: Vec<[f64; 3]> =
        (0..=n).map(|i| i as f64 / n as f64 * angle).map(|a| [radius * a.cos(), radius * a.sin(), 0.1 * a]).collect();
    let radii = (0..=n).map(|i| tube * (1.0 + 0.3 * (i as f64 / n as f64))).collect();
    Scene::from_polylines(&[Polyline { points: pts, radii }], tube, "arc").unwrap()
}

/// Checks the chosen model against the scene's links at random points near the nodes: the
/// distance outside moves by at most `c.worst` (module docs of `scene::fit`), up to the
/// quadratic sampling error and the oracle's rounding (~1e-15 of the scale ≤ 20: 1e-12).
fn check_against_oracle(scene: &Scene, c: &Choice, seed: u64) {
    let link = |l: &tubecast::RoundCone<f64>| Link { a: v(l.a.to_array()), ra: l.ra, b: v(l.b.to_array()), rb: l.rb };
    let orig: Vec<Link> = (0..scene.links.len()).map(|k| link(&scene.link(k))).collect();
    let chosen: Vec<Link> = c.links.iter().map(link).collect();
    let quads: Vec<Quad> = c.quads.iter().map(|q| Quad::new(q.b.map(|p| p.to_array()), q.r)).collect();
    let mut rng = splitmix(seed);
    let mut worst_seen: f64 = 0.0;
    for _ in 0..200 {
        let i = (rng.uniform() * scene.nodes.len() as f64) as usize % scene.nodes.len();
        let (node, u, r) = (&scene.nodes[i], rng.unit(), rng.range(0.0, 3.0 * scene.radius(i)));
        let x = v(node.pos) + Vec3::new(u[0], u[1], u[2]) * r;
        let f = link_field(&orig, x);
        let (mut g, mut slack) = (link_field(&chosen, x), 0.0f64);
        for q in &quads {
            let (d, s) = quad_field(q, x, 2000);
            if d < g {
                g = d;
            }
            slack = slack.max(s);
        }
        // g is the sampled field: true ≤ g ≤ true + slack.
        assert!(g >= f - c.worst - 1e-12, "{g} below {f} − {}", c.worst);
        assert!(g - slack <= f + c.worst + 1e-12, "{g} (−{slack}) above {f} + {}", c.worst);
        worst_seen = worst_seen.max((g - f).abs());
    }
    assert!(worst_seen <= c.worst + 1e-9);
}

#[test]
fn sampled_arc_collapses_to_a_few_certified_quadratics() {
    let scene = arc(200, 10.0, std::f64::consts::PI, 0.2);
    for tol in [2e-2, 2e-3] {
        let c = choose_with(&scene, &Tolerance::Absolute(tol), true);
        let kinds = c.prims.iter().filter(|p| p.kind() == PrimKind::Spline).count();
        assert_eq!((kinds, c.quads.len()), (c.splines, c.splines));
        assert_eq!(c.prims.len(), c.links.len() + c.quads.len());
        assert_eq!(c.prims.len() + c.merged + c.fitted, scene.links.len());
        assert!(c.worst <= tol, "worst {} > {tol}", c.worst);
        let links_only = choose(&scene, &Tolerance::Absolute(tol));
        // A half turn of radius 10: chord sagitta of a merged link of angle θ is 10(1 − cos θ/2);
        // a quadratic's error is O(θ⁴), so it covers far more of the arc than a link does.
        assert!(c.splines >= 1 && c.prims.len() * 2 <= links_only.prims.len(), "{c:?} vs {}", links_only.prims.len());
        assert!(c.prims.len() <= 24, "{} prims", c.prims.len());
        check_against_oracle(&scene, &c, 7);
    }
}

#[test]
fn zigzag_is_not_fitted() {
    // Amplitude 0.5 over unit steps: any quadratic through three consecutive nodes departs from
    // the V by ≥ 1/16 (Δs²/4·|b₀ − 2b₁ + b₂| bound aside), far above the tolerance.
    let pts: Vec<[f64; 3]> = (0..20).map(|i| [i as f64, 0.5 * (i % 2) as f64, 0.0]).collect();
    let scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.1, "zig").unwrap();
    let c = choose_with(&scene, &Tolerance::Absolute(1e-2), true);
    assert_eq!((c.splines, c.fitted, c.merged, c.prims.len()), (0, 0, 0, 19));
    check_against_oracle(&scene, &c, 3);
}

#[test]
fn straight_runs_stay_single_links() {
    let pts: Vec<[f64; 3]> = (0..12).map(|i| [i as f64, 2.0 * i as f64, -(i as f64)]).collect();
    let scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.3, "line").unwrap();
    for tol in [0.0, 1e-3, 1e-1] {
        let c = choose_with(&scene, &Tolerance::Absolute(tol), true);
        assert_eq!((c.prims.len(), c.splines, c.merged), (1, 0, 10));
        assert_eq!(c.worst, 0.0);
    }
}

#[test]
fn degenerate_input_never_panics() {
    let p = [1.0, 2.0, 3.0];
    assert_eq!(fit_quad(&[(p, 0.0), (p, 0.0), (p, 0.0)]), None); // zero radius curve
    assert_eq!(fit_quad(&[([0.0; 3], 1.0), ([1.0, 0.0, 0.0], 1.0)]), None); // one link
    assert_eq!(fit_quad(&[([0.0; 3], 1.0), ([f64::NAN, 0.0, 0.0], 1.0), ([1.0, 0.0, 0.0], 1.0)]), None);
    // A tip tapering to zero: the radius curve touches 0, refused.
    assert_eq!(fit_quad(&[([0.0; 3], 1.0), ([1.0, 0.0, 0.0], 0.5), ([2.0, 0.0, 0.0], 0.0)]), None);
    // Coincident nodes with a radius: one ball, fitted up to the rounding of the least-squares
    // sums (a few operations on values ≤ |p| + r ≈ 4.3, ε = 2⁻⁵³ each: 16·ε·4.3 < 1e-14).
    let f = fit_quad(&[(p, 0.5), (p, 0.5), (p, 0.5), (p, 0.5)]).unwrap();
    assert!(f.bound < 1e-14, "{}", f.bound);
    // Scenes with zero radii and repeated points: built or refused, never a panic.
    let pts = vec![[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.1, 0.0], [3.0, 0.0, 0.0]];
    for radii in [vec![0.0; 6], vec![0.2, 0.0, 0.2, 0.0, 0.2, 0.0], vec![]] {
        if let Ok(scene) = Scene::from_polylines(&[Polyline { points: pts.clone(), radii }], 0.2, "d") {
            for tol in [0.0, 1e-2, 1.0, f64::INFINITY] {
                let c = choose_with(&scene, &Tolerance::Absolute(tol), true);
                assert_eq!(c.prims.len() + c.merged + c.fitted, scene.links.len());
                assert!(c.worst <= tol && c.worst.is_finite());
            }
        }
    }
}
