//! Our link kernels against the manifold3d + libigl ground truth in `reference/fixtures/`
//! (generator and bounds: `reference/README.md`). `cargo test` needs no Python.
//!
//! Chain of trust: (1) the kernel's first boundary ≈ the generator's exact one (numpy, closed
//! form per link + root finding; never our Rust code), to within rounding budgets; (2) the
//! kernel's first boundary vs libigl's first hit on the inscribed mesh, one-sided, to within a
//! band derived from the mesh's measured sagitta `h`; (3) libigl's SDF at the hit point, which
//! the generator evaluated at the exact point, transferred to ours by the 1-Lipschitz property.
//!
//! ## Tolerances (error analysis)
//! Let ε = 2⁻⁵² · ½ (f64 unit roundoff, `f64::EPSILON / 2`; we use `f64::EPSILON` = 2ε for
//! safety), `S` the scene's bounding radius, `D = |o − centre|`.
//! * `E_K` (kernel hit-point distance to the surface): stable kernel `64·EPS·(S + D)`, the bound
//!   derived in `tests/kernels/link/properties.rs` (re-centring costs 3ε·D, coefficients ≤ 16ε·S, backward
//!   stable root, forming `o + t·d` 2ε(D+S); factor ~2 safety). Faithful Han: its transform
//!   works from the apex at distance `p₂ = L·max r/|Δr|` and forms its quadratic from `o − A`
//!   without re-centring, so coefficient errors are `ε(D + p₂)²` and distance errors
//!   `ε(D + p₂)²/r_min`: `E_K = 64·EPS·D'·max(D'/r_min, 1)`, `D' = D + p₂` (as in link_props).
//! * `E_ref` (the generator's exact point): bisection on the sign of its SDF to the last bit of
//!   t; the SDF is evaluated at `o + t·d` (2ε(D + S) rounding) with ~16 roundings on values
//!   ≤ |x| + S: `E_ref = 32·EPS·(D + S + |centre|)`.
//! * A distance error `E` along a ray meeting the surface at incidence `cos α = |d̂·n|` moves t
//!   by at most `E/(cos α·|d|)` to first order (the surface is smooth at a link's boundary;
//!   unions add creases where the incidence is the larger of two cosines, so using the one at
//!   the reported piece is conservative).
//! * Mesh (inscribed) — see `reference/README.md` for the proofs: outward slack
//!   `μ = manifold_tolerance + vertex rounding` (~1e-11), inward bound `H = h + μ`. Rays from
//!   outside: `t_K − slack ≤ t_M ≤ t_K + s*/|d| + slack`, with
//!   `s* = r cosα − √(r²cos²α − 2rH' + H'²)` the depth-`H'` reach into the generating ball
//!   `B(c, r) ⊂ S` at the entry,
//!   `H' = H + E_K`; no real `s*` ⇔ grazing band, where the mesh may miss. Rays from inside:
//!   `deep_until − slack ≤ t_M ≤ t_K + slack`. `slack = (μ + E_K + E_ref + 8·EPS·(D + S))/(cos α·|d|)`
//!   (the last term: libigl's t recomputed in double from the triangle plane).
use crate::fixtures::*;
use tubecast::Primitive;

const LINK_SCENES: [&str; 6] =
    ["link_cone", "link_cylinder", "link_steep", "polyline", "bifurcation", "bifurcation_n64"];

#[test]
fn stable_links_match_mesh() {
    for s in LINK_SCENES {
        check_scene(s, Kernel::Stable);
    }
}

#[test]
fn han_links_match_mesh() {
    for s in LINK_SCENES {
        check_scene(s, Kernel::Han);
    }
}

#[test]
fn bifurcation_has_three_branches_with_different_radii() {
    let fx = load("bifurcation");
    let Scene::Links(links) = &fx.scene else { panic!("links") };
    // a node shared by ≥ 4 links (parent + ≥ 3 children) whose far radii all differ
    let mut best = 0;
    for l in links {
        for p in [l.a, l.b] {
            let mut radii: Vec<f64> = links
                .iter()
                .filter_map(|m| {
                    if m.a == p {
                        Some(m.rb)
                    } else if m.b == p {
                        Some(m.ra)
                    } else {
                        None
                    }
                })
                .collect();
            radii.sort_by(f64::total_cmp);
            radii.dedup();
            best = best.max(radii.len());
        }
    }
    assert!(best >= 4, "largest bifurcation has {best} distinct branch radii");
}

/// libigl's SDF at points with exactly known signed distance: `0 ≤ sdf_M − sdf_S ≤ h` (mesh
/// inscribed; proof in reference/README.md), and our `sdf::round_cone` (min over links) equals
/// the exact value outside and is ≤ it inside (min over links is the deepest piece).
#[test]
fn sdf_samples_within_mesh_bound() {
    for name in LINK_SCENES {
        let fx = load(name);
        let Scene::Links(links) = &fx.scene else { unreachable!() };
        let m = &fx.mesh;
        let mu = m.outward_slack();
        let h = m.inward_bound();
        let mut max_err: f64 = 0.0;
        for s in &fx.sdf {
            let err = s.mesh - s.exact;
            // libigl evaluates point–triangle distances in double on values ≤ |x| + S:
            // ~16 roundings, 32·EPS·(|x| + S).
            let round = 32.0 * EPS * (s.x.length() + fx.radius);
            assert!(
                err >= -mu - round && err <= h + round,
                "{name}: libigl sdf {:e} vs exact {:e} at {:?}",
                s.mesh,
                s.exact,
                s.x
            );
            max_err = max_err.max(err);
            let ours = links.iter().map(|l| l.sdf(s.x)).fold(f64::INFINITY, f64::min);
            // sdf.rs error: ≈ 20 roundings on values ≤ |x − a| + S (as in link_props).
            let tol = 64.0 * EPS * (s.x.length() + fx.radius);
            if s.exact >= 0.0 {
                assert!((ours - s.exact).abs() <= tol, "{name}: sdf::round_cone {ours:e} vs exact {:e}", s.exact);
            } else {
                assert!(ours <= s.exact + tol, "{name}: sdf::round_cone {ours:e} vs exact {:e} (inside)", s.exact);
            }
        }
        // The bound is not vacuous: surface samples reach a good part of it (sample points
        // fall anywhere on the triangles; the mean gap over a triangle is ~1/2 of its sagitta,
        // and 420 samples over ~10⁴ faces of similar size see the top of the distribution).
        assert!(max_err >= h / 4.0, "{name}: largest mesh SDF error {max_err:e} ≪ h = {h:e}");
        eprintln!("{name}: max libigl−exact sdf {max_err:e}, h {h:e}");
    }
}

/// The reference's resolution claim: the mesh error shrinks like 1/n². Same tree and rays at
/// n = 64 and 256; the sagitta of a triangle scales exactly with (edge length)² ∝ 1/n², so the
/// mean libigl SDF at the exact hit points should drop by (256/64)² = 16. The points are the same
/// at both resolutions but fall at unrelated positions within their triangles: the gap at a
/// point is its triangle's sagitta times a factor in [0, 1] with mean ~1/2 and coefficient of
/// variation ~0.6; over N ≥ 150 points the mean has a relative standard error ≤ 0.6/√150 = 5 %,
/// the ratio of two such ≤ 7 %; 4σ gives [16·0.72, 16·1.28] ≈ [11.5, 20.5].
#[test]
fn mesh_error_shrinks_like_inverse_n_squared() {
    let fine = load("bifurcation");
    let coarse = load("bifurcation_n64");
    assert_eq!(fine.rays.len(), coarse.rays.len());
    let (mut sf, mut sc, mut n) = (0.0, 0.0, 0usize);
    for (a, b) in fine.rays.iter().zip(&coarse.rays) {
        assert_eq!((a.o, a.d), (b.o, b.d), "the two fixtures must share their rays");
        if let (Some(ea), Some(eb)) = (&a.exact, &b.exact) {
            sf += ea.mesh_sdf;
            sc += eb.mesh_sdf;
            n += 1;
        }
    }
    assert!(n >= 150, "only {n} hit points");
    let ratio = sc / sf;
    let expect = (coarse.mesh.n as f64 / fine.mesh.n as f64).powi(-2);
    eprintln!(
        "mean mesh sdf at hits: n=64 {:e}, n=256 {:e}, ratio {ratio} (expect {expect})",
        sc / n as f64,
        sf / n as f64
    );
    assert!(ratio >= expect * 0.72 && ratio <= expect * 1.28, "ratio {ratio}, expected ≈ {expect}");
    // and h itself: same constant C in h = C·r_max/n² at both resolutions (C ≈ 13.3 for
    // manifold's octahedral spheres; the maximum over faces converges to its limit like 1/n²)
    for fx in [&fine, &coarse] {
        let c = fx.mesh.sagitta * (fx.mesh.n as f64).powi(2) / max_radius(fx);
        assert!((c - fx.mesh.sagitta_coeff).abs() <= 0.02 * fx.mesh.sagitta_coeff && c < 14.0, "h·n²/r = {c}");
    }
}
