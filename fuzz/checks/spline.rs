// Shared by fuzz/fuzz_targets/spline.rs and tests/kernels/fuzz_corpus.rs.
// Bytes -> (quadratic tube, ray, solver). Byte 0: bits 0..2 the solver, bit 7 "raw" mode
// (coordinates are arbitrary f64 bit patterns: NaN, ∞, huge — validators must reject without
// panicking); otherwise coordinates are i16/1000 (|x| ≤ 32.8). Valid input must give, in f64
// and f32 and for every solver: no NaN, t_in ≤ t_out, unit normals, u ∈ [0, 1]; and in f64,
// on intervals at least 1e-6·S long, hit points not outside the tube by more than
// E = √(64ε)·S + 8εS (tests/splines/kernel.rs) + 8ε(D + |t·d|) (rounding of o + t·d), and for
// the polynomial solver within E of the surface (exact tube SDF).
#[allow(unused_imports)]
use tubecast::{Primitive, QuadTube, Ray, Solver, V3};
include!("decode.rs");
include!("sane.rs");

fn val(data: &[u8], i: usize, raw: bool) -> f64 {
    if raw {
        f64_at(data, 1 + i * 8)
    } else {
        let lo = *data.get(1 + 2 * i).unwrap_or(&0);
        let hi = *data.get(2 + 2 * i).unwrap_or(&0);
        i16::from_le_bytes([lo, hi]) as f64 / 1000.0
    }
}

/// Tube, ray and solver exactly as [`check`] builds them from the bytes; `None` where the
/// validators (`QuadTube::new`, `Ray::validate`) reject them.
pub fn input(data: &[u8]) -> Option<(QuadTube<f64>, Ray<f64>, Solver)> {
    let mode = *data.first().unwrap_or(&0);
    let raw = mode & 0x80 != 0;
    let solver = match mode & 7 {
        0 | 5 => Solver::Polynomial,
        1 => Solver::Itp,
        2 | 6 => Solver::Newton,
        3 => Solver::Bisection { iters: 10 },
        _ => Solver::Bisection { iters: 40 },
    };
    let v = |i: usize| val(data, i, raw);
    let b = [V3::new(v(0), v(1), v(2)), V3::new(v(3), v(4), v(5)), V3::new(v(6), v(7), v(8))];
    let r = [v(9).abs(), v(10), v(11).abs()];
    let ray = Ray::new(V3::new(v(12), v(13), v(14)), V3::new(v(15), v(16), v(17)));
    let t = QuadTube::new(b, r).ok()?;
    ray.validate().ok()?;
    Some((t, ray, solver))
}

/// `S`: the spline kernel's error scale. Ray-space coordinates reach the bounding radius
/// twice: S ≤ 4·(extent + radius), extent and radius bounded by `s`, the largest control-point
/// offset from b₀ (per axis, so ·√3 for the length) or radius.
pub fn scale(t: &QuadTube<f64>) -> f64 {
    let mut s: f64 = 0.0;
    for i in 0..3 {
        s = s.max((t.b[i] - t.b[0]).max_abs()).max(t.r[i].abs());
    }
    4.0 * (s * 3f64.sqrt() + s)
}

/// The bound E on the distance of a hit at `tt` from the surface: √(64ε)·S + 8εS
/// (tests/splines/kernel.rs), plus the rounding of the hit point o + t·d itself (and of t),
/// ≤ 8ε(D + |t·d|) with D = |o − b₀| (a far origin cancels against t·d), plus, with `subnormal`,
/// the absolute rounding of a subnormal t (|t| < MIN_POSITIVE: a multiple of q = 2⁻¹⁰⁷⁴,
/// whatever the kernel does): t = tc + s·(big·(1/|d|)), |s| ≤ 1, is four roundings of ≤ q/2
/// each there, 2q in all: |d|·4q covers it (a fuzz finding, tests/splines/extreme_scales.rs: tiny tubes
/// hit by rays with |d| ~ 1e149; that test calls it without the term to show it is needed).
pub fn surface_bound(t: &QuadTube<f64>, ray: &Ray<f64>, tt: f64, subnormal: bool) -> f64 {
    let s = scale(t);
    let far = 8.0 * f64::EPSILON * (norm(ray.o - t.b[0]) + norm(ray.d * tt));
    let far = if subnormal { far + 4.0 * norm(ray.d) * f64::from_bits(1) } else { far };
    (64.0 * f64::EPSILON).sqrt() * s + 8.0 * f64::EPSILON * s + far
}

/// |v| without the underflow (or overflow) of its squares: `length` squares the components, so
/// a vector shorter than ~1e-162 has length 0 (fuzz finding regression-underflowed-bound: a
/// far term 8ε·|o − b₀| with |o − b₀| = 2.6e-265 was taken as 0).
pub fn norm(v: V3<f64>) -> f64 {
    let m = v.max_abs();
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    V3::new(v.x / m, v.y / m, v.z / m).length() * m
}

pub fn check(data: &[u8]) {
    let Some((t, ray, solver)) = input(data) else { return };
    let (b, r) = (t.b, t.r);
    let iv = t.intersect_with(&ray, solver);
    sane(&iv);
    for p in t.intersect_pieces(&ray, solver) {
        sane(&p);
    }
    // Every solver reports points of the closed tube (sdf ≤ bound); the polynomial solver,
    // which rests on no empirical claim, reports surface points (|sdf| ≤ bound). The Russig
    // cascade can miss a minimum where the claims fail (tests/splines/derivative_roots.rs documents a
    // case) and then reports a point inside.
    if iv.hit {
        let s = scale(&t);
        let dl = ray.d.length();
        if (iv.exit.t - iv.entry.t) * dl > 1e-6 * s {
            // The hit point and the tube relative to b₀, (o − b₀) + t·d, as the bound's far
            // term 8ε(|o − b₀| + |t·d|) assumes: o + t·d in world coordinates rounds by ε|o|,
            // which for a tube far from the world's origin exceeds the tube itself (campaign
            // seed 2102, regression-ball-far-from-origin: a ball of radius 3.2e-5 at 1.5e144,
            // the kernel's t exact, its point o + t·d rounded back to the centre).
            let rel = QuadTube { b: [V3::new(0.0, 0.0, 0.0), b[1] - b[0], b[2] - b[0]], r };
            for tt in [iv.entry.t, iv.exit.t] {
                let e = rel.sdf((ray.o - b[0]) + ray.d * tt);
                let mut bound = surface_bound(&t, &ray, tt, true);
                if let Solver::Bisection { iters } = solver {
                    // A root of g located to δ = 2^-iters (of a bracket ≤ 1) is a sphere missed
                    // by ≤ (max|p'| + max|r'|)·δ, with |p'| ≤ 2·max|bᵢ − bⱼ|, |r'| ≤ 2·max|rᵢ − rⱼ|.
                    let mut lip: f64 = 0.0;
                    for i in 0..3 {
                        for j in 0..3 {
                            lip = lip.max(2.0 * (b[i] - b[j]).length() + 2.0 * (r[i] - r[j]).abs());
                        }
                    }
                    bound += 2.0 * lip * 0.5f64.powi(iters as i32);
                }
                assert!(e <= bound, "hit {tt} outside the tube by {e} > {bound}: {t:?} {ray:?} {solver:?}");
                if solver == Solver::Polynomial {
                    assert!(e.abs() <= bound, "hit {tt} off the surface by {e} > {bound}: {t:?} {ray:?} {solver:?}");
                }
            }
        }
    }
    if let Ok(t32) = QuadTube::new([b[0].cast::<f32>(), b[1].cast(), b[2].cast()], [r[0] as f32, r[1] as f32, r[2] as f32]) {
        let r32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
        if r32.validate().is_ok() {
            sane(&t32.intersect_with(&r32, solver));
        }
    }
}
