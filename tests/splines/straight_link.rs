//! Findings of the `differential` fuzz target (fuzz/checks/differential.rs) against the spline
//! kernel, decoded exactly as the check decodes them, with their answers derived by hand.

use tubecast::{Primitive, QuadTube, Ray, RoundCone, Solver, V3};

/// Differential campaign on fbab6e0 (seed 2002, 167,721 executions), kept as
/// fuzz/corpus/differential/regression-spline-f32-exit-at-end.
const EXIT_AT_END: &[u8] = include_bytes!("../../fuzz/corpus/differential/regression-spline-f32-exit-at-end");

/// The check's decoding: f64 words 0…13, each rounded to f32.
fn decode(data: &[u8]) -> (RoundCone<f64>, Ray<f64>) {
    let f = |i: usize| {
        let mut w = [0u8; 8];
        w.copy_from_slice(&data[i * 8..i * 8 + 8]);
        f64::from_le_bytes(w) as f32 as f64
    };
    let v = |i| V3::new(f(i), f(i + 1), f(i + 2));
    (RoundCone::new(v(0), f(3), v(4), f(7)).unwrap(), Ray::new(v(8), v(11)))
}

/// A link 131,101 long and 32.5 thick (L/r ≈ 4,000) along x: a = (131101.17, 0, 32.501957),
/// b = (0, 1.65·10⁻²⁴, 32.501961), radii 32.501961 and 32.478523. The ray starts at
/// o = (32.5018, 0, 32.501778), 32.5 from end b and 1.8·10⁻⁴ off the axis, with
/// d = (0, −35.277, 192): it crosses the tube at right angles to the axis (d·x̂ = 0).
///
/// *Exact answer.* The line stays in the plane x = o.x. The axis has slope
/// |Δz|/L = 3·10⁻¹¹ and the radius |Δr|/L = 1.8·10⁻⁷, so the sweep meets that plane in a circle of
/// radius r(u) (the spheres near u, u = 1 − x/Lₓ, to a relative O(slope²) = 3·10⁻¹⁴) about the axis
/// point c(u): 2-D circle–line intersection in (y, z), formed below in f64. The line
/// passes 1.8·10⁻⁴ from c, so it meets the circle almost head on (cos > 1 − 10⁻¹⁰):
/// a distance error E on the surface is an error E/|d| in t.
///
/// *Band.* The spline kernel's band in f32 ([`tubecast::spline_error_band`]) is
/// E = 1024ε·R + 8ε|o − m| with R ≤ L/2 + r ≤ 65,584 and |o − m| ≤ 65,551 (m the midpoint):
/// E ≤ 8.07 + 0.07 = 8.14, to which forming the f32 middle control point adds
/// ε(√3|m| + r) ≤ 0.014 (fuzz/checks/differential.rs); t within 8.2/|d| = 0.042 of the exact.
///
/// *Was:* the default `Polynomial` solver in f32 put the exit at 9.2·10⁻⁷ on end sphere b
/// (u = 1): all of P's roots were lost to rounding, and the real interval's only candidates
/// were its ends, where √g = 0.
#[test]
fn thin_tube_crossed_at_right_angles_near_its_end() {
    let (link, ray) = decode(EXIT_AT_END);
    assert_eq!(ray.d.x, 0.0, "the derivation needs a line in the plane x = o.x");
    let u = 1.0 - ray.o.x / link.a.x;
    let c = link.a + (link.b - link.a) * u;
    let r = link.ra + (link.rb - link.ra) * u;
    // |o + t d − c|² = r² in (y, z).
    let (py, pz) = (ray.o.y - c.y, ray.o.z - c.z);
    let (a2, b1, c0) = (ray.d.y * ray.d.y + ray.d.z * ray.d.z, py * ray.d.y + pz * ray.d.z, py * py + pz * pz - r * r);
    let root = (b1 * b1 - a2 * c0).sqrt();
    let (t_in, t_out) = ((-b1 - root) / a2, (-b1 + root) / a2);
    assert!(t_in < 0.0 && t_out > 0.16 && t_out < 0.17, "derivation: {t_in} {t_out}");
    let l32: RoundCone<f32> = link.cast();
    let r32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    let q32 = QuadTube::from_link(&l32).unwrap();
    let q64 = QuadTube::from_link(&link).unwrap();
    let eps = f32::EPSILON as f64;
    let forming = eps * (3f64.sqrt() * q64.point(0.5).length() + link.ra.max(link.rb));
    let band = (q64.error_band(ray.o, eps) + forming) / ray.d.length();
    assert!(band <= 8.2 / ray.d.length(), "derivation: band {band}");
    for solver in [Solver::Polynomial, Solver::Newton, Solver::Itp] {
        let iv = q32.intersect_with(&r32, solver);
        assert!(iv.hit, "{solver:?} f32 misses");
        let (ti, to) = (iv.entry.t as f64, iv.exit.t as f64);
        assert!((ti - t_in).abs() <= band, "{solver:?} f32 t_in {ti} vs {t_in} (band {band})");
        assert!((to - t_out).abs() <= band, "{solver:?} f32 t_out {to} vs {t_out} (band {band})");
        // f64: the same band with ε = 2⁻⁵² is below 10⁻¹⁰ in t.
        let iv = q64.intersect_with(&ray, solver);
        assert!(
            iv.hit && (iv.entry.t - t_in).abs() <= 1e-10 && (iv.exit.t - t_out).abs() <= 1e-10,
            "{solver:?} f64 {iv:?}"
        );
    }
    // The clipped interval starts at the origin, inside: the ray's own hit is the exit.
    let hit = q32.intersect(&r32);
    assert!(hit.hit && ((hit.exit.t as f64) - t_out).abs() <= band);
}
