//! Findings of the `link` fuzz target (fuzz/checks/link.rs), decoded exactly as the check
//! decodes them, with their answers derived by hand below.

use tubecast::{Primitive, Ray, RoundCone, V3};

/// This afternoon's link campaign (2.7e7 runs on d6a0b89), kept as
/// fuzz/corpus/link/regression-generator-tangent: 14 f64s at byte 8i (the last two absent: 0).
const BYTES: &[u8] = include_bytes!("../../../fuzz/corpus/link/regression-generator-tangent");

fn f(i: usize) -> f64 {
    BYTES.get(8 * i..8 * i + 8).map_or(0.0, |b| f64::from_le_bytes(b.try_into().unwrap()))
}

/// The link a = (1.9e-186, y₀ + δ, 3.97e-319), ra = 0 (a tip), b = (bₓ, y₀, rb), rb =
/// 3.310369715525099e-28 = y₀, δ = 4.617e-36 (≈ 1.4e-8·L); the ray o = (y₀, y₀, z₀),
/// z₀ = 6.1e-183, d = (−1.06e45, 0, 0): the line y = y₀, z = z₀ runs beside the cone's generator
/// through the tip (a to the bottom point B = (bₓ, y₀, 0) of sphere b), offset δ·λ-wise from it.
///
/// Where the line meets the hull: a hull point is P = λa + (1 − λ)p, λ ∈ [0, 1], p in ball b
/// (ra = 0). Ball b lies in z ≥ 0 and a.z ≥ 0, so P.z = z₀ needs p.z ≤ h = z₀/(1 − λ), and
/// then p is within √(2·rb·h) of B in x and y. P.y = y₀ needs (1 − λ)(p.y − y₀) = −λδ, so
/// λ²δ² ≤ (1 − λ)²·2·rb·h ≤ 2·rb·z₀: λ ≤ λ* = √(2·rb·z₀)/δ ≈ 4.4e-70, and
/// |P.x − bₓ| ≤ λ*·|bₓ − a.x| + √(2·rb·z₀/(1 − λ*)) ≈ 1.5e-97 =: W. So the exact answer is a
/// chord of length ≤ 2W about x = bₓ (the line grazes sphere b, z₀ deep).
///
/// Any point of the line at x is off sphere b by ≥ (x − bₓ)²/(2·rb)·(1 − …) − z₀ and off the hull
/// by at least that far from the chord, so a hit point within 2E (the check's bound, E ≈ 1.2e-41
/// here) of the surface has |x − bₓ| ≤ √(2·rb·(2E + z₀)) + W ≈ 1.3e-34 (with a factor 2 of slack
/// below for the (1 − …)). A miss is also right within E: the line is only z₀ ≪ E inside.
///
/// Before the fix the stable kernel's exit was at x = 6.5e-36 (near the tip, 1.35e-36 off the
/// surface, 5.6e4·E): the stump's quadratic has noise coefficients there and claimed the whole
/// slab; the cap end at the tip (g = 3.3e-36 > 0) was polished by one Newton step to a point
/// still 1.35e-36 outside, and accepted by the √ε-sized a-posteriori test (6.7e-35).
#[test]
fn line_beside_a_generator_through_a_tip() {
    let v = |i| V3::new(f(i), f(i + 1), f(i + 2));
    let link = RoundCone::new(v(0), f(3), v(4), f(7)).expect("valid link");
    let ray = Ray::new(v(8), v(11));
    assert!(ray.validate().is_ok());
    let (a, b, rb, o) = (link.a, link.b, link.rb, ray.o);
    assert_eq!((link.ra, b.y, b.z, o.y, ray.d.y, ray.d.z), (0.0, o.y, rb, rb, 0.0, 0.0));
    assert!(a.z >= 0.0 && o.z > 0.0, "the hull lies in z ≥ 0, the line at z₀ > 0");
    let (delta, z0) = (a.y - o.y, o.z);
    assert!(delta > 4.6e-36 && delta < 4.7e-36);
    let lam = (2.0 * rb * z0).sqrt() / delta;
    let w = lam * (b.x - a.x).abs() + (2.0 * rb * z0 / (1.0 - lam)).sqrt();
    assert!(w < 1e-96, "{w:e}");
    // E of tests/kernels/link/properties.rs (the check's), from the oracle crate.
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let ol = tubecast_oracle::Link { a: ov(a), ra: 0.0, b: ov(b), rb };
    let size = (b - a).length().max(rb);
    let e = tubecast_oracle::link_error_bound(&ol, ov(o), size, f64::EPSILON);
    assert!(e < 1e-40, "{e:e}");
    let reach = 2.0 * (2.0 * rb * (2.0 * e + z0)).sqrt() + w;
    let iv = link.intersect(&ray);
    if iv.hit {
        for t in [iv.entry.t, iv.exit.t] {
            let x = o.x + t * ray.d.x;
            assert!((x - b.x).abs() <= reach, "hit at x = {x:e}, {:e} from the chord > {reach:e}", (x - b.x).abs());
        }
    }
    // The tip is 4.6e-36 from the line: far outside the reach (the former exit was near it).
    assert!(b.x - reach > 1e3 * delta);
}

/// The next link campaign (8.0e6 runs on 9568536) found a mutant of the input above, kept as
/// fuzz/corpus/link/regression-generator-offset: the same tip a (ra = 0) at y₀ + δ, the same
/// line y = y₀, z = z₀ along x, but sphere b's centre moved to (bₓ, y₀ + η, rb), η = 7.35e-38.
///
/// The exact answer is a miss. A hull point on the line is P = λa + (1 − λ)p with p in ball b.
/// P.y = y₀ needs p.y − y₀ = −λδ/(1 − λ) ≤ 0, so p.y is ≥ η below the centre and p.z ≥ rb −
/// √(rb² − η²) ≥ η²/(2rb); P.z = z₀ (a.z ≥ 0) needs p.z ≤ z₀/(1 − λ). Together: 1 − λ ≤
/// 2·rb·z₀/η² ≈ 7.5e-136. But p in the ball needs λδ/(1 − λ) ≤ |p.y − y₀| ≤ rb + η, i.e. 1 − λ
/// ≥ δ/(δ + rb + η) ≈ 1.4e-8: no such λ.
///
/// So a hit is right only as a point within the kernel's error of the surface: the check's 2E.
/// Before the fix the stable kernel's exit was near the tip, where the line is 4.8e-41 = 4E off
/// the cone's side (it passes δ beside the generator, and the cross-section there is only
/// 2.2e-31 across): a root of F's noise accepted by the √ε-sized window.
#[test]
fn line_beside_a_generator_offset_at_both_ends() {
    const OFFSET: &[u8] = include_bytes!("../../../fuzz/corpus/link/regression-generator-offset");
    let f = |i: usize| OFFSET.get(8 * i..8 * i + 8).map_or(0.0, |b| f64::from_le_bytes(b.try_into().unwrap()));
    let v = |i| V3::new(f(i), f(i + 1), f(i + 2));
    let link = RoundCone::new(v(0), f(3), v(4), f(7)).expect("valid link");
    let ray = Ray::new(v(8), v(11));
    assert!(ray.validate().is_ok());
    let (a, b, rb, o) = (link.a, link.b, link.rb, ray.o);
    assert_eq!((link.ra, b.z, o.y, ray.d.y, ray.d.z), (0.0, rb, rb, 0.0, 0.0));
    assert!(a.z >= 0.0 && o.z > 0.0, "the hull lies in z ≥ 0, the line at z₀ > 0");
    let (delta, eta, z0) = (a.y - o.y, b.y - o.y, o.z);
    assert!(eta > 7.3e-38 && eta < 7.4e-38 && delta > 4.6e-36 && delta < 4.7e-36);
    // The two conditions on 1 − λ above cannot both hold: the exact answer is a miss.
    assert!(2.0 * rb * z0 / (eta * eta) < delta / (delta + rb + eta));
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let ol = tubecast_oracle::Link { a: ov(a), ra: 0.0, b: ov(b), rb };
    let size = (b - a).length().max(rb);
    let e = tubecast_oracle::link_error_bound(&ol, ov(o), size, f64::EPSILON);
    assert!(e < 1.3e-41, "{e:e}");
    let iv = link.intersect(&ray);
    if iv.hit {
        for t in [iv.entry.t, iv.exit.t] {
            // The oracle's distance to the sweep, min over u of |x − p(u)| − r(u): at this
            // scale (radii ≥ 1e-31 where it matters) f64 resolves it to ≈ 1e-47.
            let (d, _) = tubecast_oracle::sweep_dist(&ol, ov(ray.at(t)));
            assert!(d.abs() <= 2.0 * e, "hit point {d:e} off the surface > 2E = {:e}", 2.0 * e);
        }
    }
}

/// The differential campaign of 2026-12-01 (seed 2402, 9.7e6 runs on 86502c9) found, kept as
/// fuzz/corpus/differential/regression-generator-parallel-f32 (decoded as that check decodes:
/// f64s at byte 8i, rounded to f32): a tip a = (0, Y, Y), ra = 0, and b = (bₓ, Y, 0), rb = Y
/// (Y = 32.50196…), so the cone's top generator is the line y = z = Y, along x; the ray runs
/// along x at (y₀, z₀) = (Y − 0.219, Y − 1.6e-4).
///
/// *The exact answer is a miss.* The line is parallel to x, so it meets the hull iff its
/// projection (y₀, z₀) onto the yz-plane lies in the hull's projection, the convex hull of
/// A = (Y, Y) and the disc of radius rb = Y about B = (Y, 0). A is on that disc's circle
/// (|A − B| = Y = rb), so the projection is the disc itself, and the line misses by
/// `√((y₀ − Y)² + z₀²) − rb` = 5.8e-4, beyond the f32 bound E = 5.7e-4 (tests/kernels/link/properties.rs,
/// from the oracle crate): a hit is a false one.
///
/// Before the fix the f32 stable kernel returned a hit (t = 0.53 … 0.66): the line is parallel
/// to a generator, so the stump's A = c²|Q|² − s²zd² is noise (−8.9e-8), one root of F is
/// noise, and the a-posteriori test accepted it since g = 5.8e-4 (the line's true distance) was
/// within 64ε·scale = 7.9e-4 — a tolerance 50 times g's own rounding there.
#[test]
fn f32_line_parallel_to_a_generator_outside() {
    const PARALLEL: &[u8] = include_bytes!("../../../fuzz/corpus/differential/regression-generator-parallel-f32");
    let (link, ray) = differential_input(PARALLEL);
    let (a, b, rb, o, d) = (link.a, link.b, link.rb, ray.o, ray.d);
    // The configuration of the derivation: a on sphere b's circle in the yz-plane, d along x.
    assert_eq!((a.x, link.ra, a.y, a.z, b.y, b.z, d.y, d.z), (0.0, 0.0, rb, rb, rb, 0.0, 0.0, 0.0));
    let miss_by = ((o.y - b.y).powi(2) + o.z.powi(2)).sqrt() - rb;
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let ol = tubecast_oracle::Link { a: ov(a), ra: 0.0, b: ov(b), rb };
    let size = (b - a).length().max(rb);
    let e32 = tubecast_oracle::link_error_bound(&ol, ov(o), size, f32::EPSILON as f64);
    let e64 = tubecast_oracle::link_error_bound(&ol, ov(o), size, f64::EPSILON);
    assert!(miss_by > e32 + e64, "the line misses by {miss_by:e}, within E = {e32:e}");
    // And the oracle agrees on the gap (its own, independent minimisation).
    let gap = tubecast_oracle::line_gap(&ol, &tubecast_oracle::Line { o: ov(o), d: ov(d) }).0;
    assert!((gap - miss_by).abs() < 1e-9, "oracle gap {gap:e} against {miss_by:e}");
    let l32: RoundCone<f32> = link.cast();
    let r32 = Ray::new(o.cast::<f32>(), d.cast::<f32>());
    assert!(!l32.intersect(&r32).hit, "f32: a hit where the line misses by {miss_by:e} > E = {e32:e}");
    assert!(!link.intersect(&ray).hit, "f64: a hit where the line misses by {miss_by:e}");
}

/// The differential campaign on a first, tighter form of that fix (seed 2403) found, kept as
/// fuzz/corpus/differential/regression-apex-line-f32: a tip a = (A, 0, 0), A = 174.6, ra = 0,
/// and b = (0, 0, 2), rb = 2.0238; the ray runs along x at y₀ = 2.7e-23, z = 0, i.e. within y₀
/// of the tip, and inside ball b at x = 0 (|(0, y₀, 0) − b| = 2 < rb).
///
/// *The exit is near the tip.* The hull is convex and holds a and ball b, so for λ ∈ (0, 1] it
/// holds the ball `a + λ(ball b − a)`. The line's point P(x) = (x, y₀, 0), with λ = 1 − x/A,
/// is `a + λ(p′ − a)` for p′ = (0, y₀/λ, 0), which lies `rb − √(4 + y₀²/λ²)` deep in ball b;
/// so P(x) lies at least `λ·(rb − √(4 + y₀²/λ²))` deep in the hull. A kernel exit at x must be
/// within the check's band E₃₂ + E₆₄ of the surface, so that depth must not exceed it: an exit
/// at x ≈ 0 (0.0237 deep) is false, the exit is beyond x = A(1 − 0.09).
///
/// That tighter tolerance (16ε times the magnitudes g is formed from) rejected the real exit at
/// the tip, where g has a kink (the line passes through the apex) and Newton cannot settle
/// below it: g = 7.8e-25 against 1.5e-27. The fix's tolerance is 64ε·min(scale, S + D).
#[test]
fn f32_line_through_an_apex_exits_at_the_tip() {
    const APEX: &[u8] = include_bytes!("../../../fuzz/corpus/differential/regression-apex-line-f32");
    let (link, ray) = differential_input(APEX);
    let (a, b, rb, o, d) = (link.a, link.b, link.rb, ray.o, ray.d);
    // The configuration of the derivation.
    assert_eq!((a.y, a.z, link.ra, b.x, b.y, b.z, o.z, d.y, d.z), (0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0));
    assert!(o.x.abs() < 1e-20 && o.y.abs() < 1e-20 && rb > 2.0 && d.x > 0.0);
    let (big_a, y0) = (a.x, o.y);
    let depth = |x: f64| {
        let lam = 1.0 - x / big_a;
        if lam <= 0.0 {
            return 0.0;
        }
        lam * (rb - (4.0 + (y0 / lam).powi(2)).sqrt())
    };
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let ol = tubecast_oracle::Link { a: ov(a), ra: 0.0, b: ov(b), rb };
    let size = (b - a).length().max(rb);
    let e = tubecast_oracle::link_error_bound(&ol, ov(o), size, f32::EPSILON as f64)
        + tubecast_oracle::link_error_bound(&ol, ov(o), size, f64::EPSILON);
    assert!(depth(0.0) > 10.0 * e, "the line is deep inside at x = 0: {:e} against E {e:e}", depth(0.0));
    let l32: RoundCone<f32> = link.cast();
    let iv = l32.intersect(&Ray::new(o.cast::<f32>(), d.cast::<f32>()));
    assert!(iv.hit);
    let x_out = o.x + iv.exit.t as f64 * d.x;
    assert!(depth(x_out) <= e, "f32 exit at x = {x_out}, {:e} deep > E {e:e}", depth(x_out));
    let iv = link.intersect(&ray);
    let x_out = o.x + iv.exit.t * d.x;
    assert!(iv.hit && depth(x_out) <= e, "f64 exit at x = {x_out}, {:e} deep", depth(x_out));
}

/// A differential corpus input decoded as fuzz/checks/differential.rs decodes it: f64s at byte
/// 8i (bytes past the end read as 0), each rounded to f32; the link from the first eight, the
/// ray from the next six.
fn differential_input(bytes: &[u8]) -> (RoundCone<f64>, Ray<f64>) {
    let f = |i: usize| {
        let mut b = [0u8; 8];
        for (k, x) in b.iter_mut().enumerate() {
            *x = *bytes.get(8 * i + k).unwrap_or(&0);
        }
        f64::from_le_bytes(b) as f32 as f64
    };
    let v = |i| V3::new(f(i), f(i + 1), f(i + 2));
    (RoundCone::new(v(0), f(3), v(4), f(7)).expect("valid link"), Ray::new(v(8), v(11)))
}
