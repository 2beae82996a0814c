//! The spline-tube kernel (`QuadTube::intersect_pieces` + CSG union) against the manifold3d +
//! libigl ground truth for a quadratic Bézier sphere sweep (`reference/fixtures/
//! spline_quadratic.json`; generator and bounds in `reference/README.md`).
//!
//! Same checks and tolerance analysis as `tests/reference/links.rs` (shared code in
//! `fixtures.rs`), with one difference: the mesh is the union of hulls of 160
//! consecutive sampled spheres, which strays from the true sweep by at most
//! `chord_error = (|p''| + |r''|)/(8·160²)` **either way** (a hull of two sample spheres is the
//! sweep of the linear interpolants; `|p_lin − p| ≤ |p''|Δu²/8`, same for r, and a sphere sweep
//! moves by at most `|Δp| + |Δr|`). `MeshInfo::outward_slack` and `inward_bound` include it.
//! Kernel budget: `64·EPS·(S + D)` as for the stable link kernel — the spline kernel also
//! re-centres the origin (at the point of the line closest to p(½)) and its roots are polished
//! to a few ulps; the hit point is then backward stable to a few dozen roundings of values ≤
//! S + D.
use crate::fixtures::*;
use tubecast::Primitive;
use tubecast::Solver;

#[test]
fn spline_polynomial_matches_mesh() {
    check_scene("spline_quadratic", Kernel::Spline(Solver::Polynomial));
}

#[test]
fn spline_newton_cascade_matches_mesh() {
    check_scene("spline_quadratic", Kernel::Spline(Solver::Newton));
}

#[test]
fn spline_itp_cascade_matches_mesh() {
    check_scene("spline_quadratic", Kernel::Spline(Solver::Itp));
}

/// libigl's SDF at points with exactly known signed distance, within
/// `[−chord − μ, h + chord + μ]`; and our `sdf::quadratic_tube` equals the exact value outside
/// and is ≤ it inside (the sweep's `min_u |x − p(u)| − r(u)` is the negated depth in the
/// deepest single sphere there, which is at least the true depth δ).
#[test]
fn spline_sdf_samples_within_mesh_bound() {
    let fx = load("spline_quadratic");
    let Scene::Spline(tube) = &fx.scene else { panic!("spline fixture") };
    let (mu, h) = (fx.mesh.outward_slack(), fx.mesh.inward_bound());
    let mut max_err: f64 = 0.0;
    for s in &fx.sdf {
        let err = s.mesh - s.exact;
        // libigl: point–triangle distances in double, ~16 roundings of values ≤ |x| + S.
        let round = 32.0 * EPS * (s.x.length() + fx.radius);
        assert!(err >= -mu - round && err <= h + round, "libigl sdf {:e} vs exact {:e} at {:?}", s.mesh, s.exact, s.x);
        max_err = max_err.max(err);
        let ours = tube.sdf(s.x);
        // A minimum over u found to a few ulps of u changes the value only to second order;
        // the distance itself carries ~20 roundings of values ≤ |x| + S.
        let tol = 64.0 * EPS * (s.x.length() + fx.radius);
        if s.exact >= 0.0 {
            assert!((ours - s.exact).abs() <= tol, "quadratic_tube {ours:e} vs exact {:e} at {:?}", s.exact, s.x);
        } else {
            assert!(ours <= s.exact + tol, "quadratic_tube {ours:e} vs exact {:e} (inside) at {:?}", s.exact, s.x);
        }
    }
    // Not vacuous (see reference_links::sdf_samples_within_mesh_bound).
    assert!(max_err >= h / 4.0, "largest mesh SDF error {max_err:e} ≪ h = {h:e}");
}
