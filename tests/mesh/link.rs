//! Certified tessellation of single links: the kernel's exact signed distance at dense mesh
//! samples and the mesh's distance at dense exact-surface samples are both within ε, the mesh
//! is closed and consistently oriented outward — on the hard cases (thin and long, tiny and
//! huge scales, far origins, zero length, one ball nearly inside the other, tips, steep tapers).

use crate::common::{assert_watertight, link_surface, triangle_samples, volume, MeshDist, P};
use tubecast::{tessellate_link, Mesh, Primitive, RoundCone, V3};

/// Rounding allowance: every vertex is `origin + (c + ρ(cos·u + sin·v))` in f64 from
/// coordinates of size ≤ `scale` (a few roundings of magnitude ≤ scale each), and the kernel's
/// SDF and the test's sample arithmetic add a few more; 64 ulps of `scale` covers them with a
/// wide margin and is far below every ε tested (≥ 1e-3 of the radius).
fn slack(scale: f64) -> f64 {
    64.0 * f64::EPSILON * scale
}

/// The two-sided check: |sdf| ≤ ε at mesh samples, mesh distance ≤ ε at surface samples.
pub fn check_two_sided(mesh: &Mesh, sdf: &dyn Fn(P) -> f64, surface: &[P], eps: f64, scale: f64) {
    assert!(mesh.certified <= eps, "certified {} > ε {eps}", mesh.certified);
    assert_watertight(mesh);
    assert!(volume(mesh) > 0.0, "inward orientation");
    let tol = eps + slack(scale);
    let mut worst_in: f64 = 0.0;
    for x in triangle_samples(mesh, 3) {
        let d = sdf(x);
        worst_in = worst_in.max(d.abs());
        assert!(d.abs() <= tol, "mesh point {x:?} at sdf {d} (ε {eps})");
    }
    let md = MeshDist::new(mesh);
    let mut used = 0;
    for &y in surface {
        // Keep points on the boundary of the union (not inside another piece).
        if sdf(y) < -slack(scale) {
            continue;
        }
        used += 1;
        let d = md.dist(y);
        assert!(d <= tol, "surface point {y:?} at distance {d} from the mesh (ε {eps})");
    }
    assert!(used * 2 >= surface.len(), "too few surface samples on the boundary: {used}");
    assert!(worst_in > 0.0);
}

fn check_link(a: P, ra: f64, b: P, rb: f64, eps: f64) -> Mesh {
    let link = RoundCone::new(a, ra, b, rb).unwrap();
    let mesh = tessellate_link(&link, eps).unwrap();
    let scale = a.max_abs().max(b.max_abs()) + ra.max(rb);
    let surface = link_surface(a, ra, b, rb, 60);
    check_two_sided(&mesh, &|p| link.sdf(p), &surface, eps, scale);
    mesh
}

fn v(x: f64, y: f64, z: f64) -> P {
    V3::new(x, y, z)
}

#[test]
fn cone_cylinder_and_tolerances() {
    for eps in [1e-2, 1e-3] {
        check_link(v(0.0, 0.0, 0.0), 1.0, v(3.0, 0.5, 0.2), 0.5, eps);
        check_link(v(0.0, 0.0, 0.0), 0.5, v(0.0, 0.0, 2.0), 0.5, eps * 0.5);
    }
}

#[test]
fn thin_long_and_steep_tapers() {
    check_link(v(0.0, 0.0, 0.0), 1e-3, v(100.0, 1.0, -2.0), 1e-3, 1e-5);
    check_link(v(0.0, 0.0, 0.0), 1.0, v(2.0, 0.0, 0.0), 1e-3, 1e-2);
    check_link(v(0.0, 0.0, 0.0), 0.0, v(0.0, 3.0, 0.0), 1.0, 1e-2); // a tip
    check_link(v(0.0, 0.0, 0.0), 1.2, v(1.0, 0.0, 0.0), 0.25, 1e-2); // steep: |Δr| near L
}

#[test]
fn tiny_huge_and_far() {
    let (a, b) = (v(0.0, 0.0, 0.0), v(3.0, 0.5, 0.2));
    for s in [1e-9, 1e9] {
        check_link(a.scale(s), s, b.scale(s), 0.5 * s, 1e-2 * s);
    }
    let far = v(1e7, -2e7, 3e6);
    check_link(far + a, 1.0, far + b, 0.5, 1e-2);
}

#[test]
fn degenerate_links_are_spheres() {
    // Zero length: the larger ball.
    let m = check_link(v(1.0, 2.0, 3.0), 1.0, v(1.0, 2.0, 3.0), 0.5, 1e-2);
    let zero_len = m.triangles.len();
    // One ball nearly inside the other (|Δr| = L(1 − 1e-9)) and exactly inside.
    check_link(v(0.0, 0.0, 0.0), 1.0, v(0.5, 0.0, 0.0), 0.5 + 0.5e-9, 1e-2);
    let inside = check_link(v(0.0, 0.0, 0.0), 1.0, v(0.25, 0.0, 0.0), 0.5, 1e-2);
    assert_eq!(inside.triangles.len(), zero_len);
}

#[test]
fn counts_follow_the_chord_bound() {
    // Halving ε multiplies both counts by about √2 (the error is quadratic in the steps):
    // triangles grow by about 2, between 1.6 and 2.6 after ceilings.
    let link = RoundCone::new(v(0.0, 0.0, 0.0), 1.0, v(4.0, 0.0, 0.0), 0.5).unwrap();
    let t = |e: f64| tessellate_link(&link, e).unwrap().triangles.len() as f64;
    for e in [1e-2, 1e-3, 1e-4] {
        let ratio = t(e / 2.0) / t(e);
        assert!((1.6..2.6).contains(&ratio), "ε {e}: ratio {ratio}");
    }
}

#[test]
fn bad_input_is_an_error() {
    let link = RoundCone::new(v(0.0, 0.0, 0.0), 1.0, v(4.0, 0.0, 0.0), 0.5).unwrap();
    for eps in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-16] {
        assert!(tessellate_link(&link, eps).is_err(), "ε {eps}");
    }
    let f = RoundCone::new(V3::new(0.0f32, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
    assert!(tessellate_link(&f, 1e-2f32).unwrap().certified <= 1e-2);
}
