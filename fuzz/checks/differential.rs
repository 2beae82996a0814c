// Differential check (the methods of one primitive held to each other's bounds), shared by
// fuzz/fuzz_targets/differential.rs and
// tests/kernels/fuzz_corpus.rs: every link method on the same input must agree within the
// bounds derived in tests/kernels/link/properties.rs (E = tubecast_oracle::link_error_bound):
// 1. lanes (f32x8, f64x4) equal the scalar calls bit for bit (same IEEE operations, in order);
// 2. f32 and f64 stable kernels on the same (f32-rounded) problem: the same hit/miss outside
//    the band |gap| ≤ E₃₂ + E₆₄, and entry/exit t within the E-band of the line (`same_t`);
// 3. Han (faithful) and stable in f64 where Han is well conditioned (apex ≤ 100 sizes away,
//    r_min ≥ 1e-3 r_max, E_Han = 64ε·D·max(1, D/r_min) < 1e-6 S), within E_Han + E₆₄;
// 4. the spline kernel on the same link as a straight segment (`QuadTube::from_link`, default
//    solver), in f64 and in f32, against the stable f64 link, within E₆₄ + E_spline + the
//    perturbation of forming the middle control point (derived at `spline_agrees_with_stable`).
// Any disagreement outside its bound is a finding. Inputs whose lengths span ≥ 1e12 get only
// check 1 (the bounds are stated below that span, as in checks/link.rs).
#[allow(unused_imports)]
use tubecast::baseline::HanLink;
use tubecast::{Interval, Primitive, Ray, RoundCone, WideF32x8, WideF64x4, V3};
include!("decode.rs");

fn r32(x: f64) -> f64 {
    x as f32 as f64
}

pub fn check(data: &[u8]) {
    let f = |i: usize| r32(f64_at(data, i * 8));
    let v = |i| V3::new(f(i), f(i + 1), f(i + 2));
    let Ok(link) = RoundCone::new(v(0), f(3), v(4), f(7)) else { return };
    let ray = Ray::new(v(8), v(11));
    let l32: RoundCone<f32> = link.cast();
    let ray32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    if ray.validate().is_err() || ray32.validate().is_err() || RoundCone::new(l32.a, l32.ra, l32.b, l32.rb).is_err() {
        return;
    }
    if let Err(m) = agree(&link, &ray) {
        panic!("differential: {m}\nlink {link:?}\nray {ray:?}");
    }
}

/// The three agreements above for an `f32`-representable link and ray, valid in both precisions.
pub fn agree(link: &RoundCone<f64>, ray: &Ray<f64>) -> Result<(), String> {
    lanes_equal_scalar(link, ray)?;
    let lens = [(link.b - link.a).length(), link.ra, link.rb, (ray.o - link.a).length(), ray.d.length()];
    let hi = lens.iter().cloned().fold(0.0, f64::max);
    let lo = lens.iter().cloned().filter(|x| *x > 0.0).fold(f64::INFINITY, f64::min);
    if hi / lo >= 1e12 {
        return Ok(());
    }
    f32_agrees_with_f64(link, ray)?;
    han_agrees_with_stable(link, ray)?;
    spline_agrees_with_stable(link, ray)
}

fn lanes_equal_scalar(link: &RoundCone<f64>, ray: &Ray<f64>) -> Result<(), String> {
    let l: RoundCone<f32> = link.cast();
    let r = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    let l8 = RoundCone::<WideF32x8>::from_lanes(|_| l);
    let r8 = Ray::<WideF32x8>::from_fn(|_| r);
    let (s8, h8) = (l8.intersect(&r8), HanLink::new(&l8).intersect(&r8));
    let (s, h) = (l.intersect(&r), HanLink::new(&l).intersect(&r));
    let l4 = RoundCone::<WideF64x4>::from_lanes(|_| *link);
    let r4 = Ray::<WideF64x4>::from_fn(|_| *ray);
    let (s4, h4) = (l4.intersect(&r4), HanLink::new(&l4).intersect(&r4));
    let (s64, h64) = (link.intersect(ray), HanLink::new(link).intersect(ray));
    for i in 0..8 {
        if s8.lane(i) != s || h8.lane(i) != h {
            return Err(format!("f32x8 lane {i} differs from the scalar call"));
        }
    }
    for i in 0..4 {
        if s4.lane(i) != s64 || h4.lane(i) != h64 {
            return Err(format!("f64x4 lane {i} differs from the scalar call"));
        }
    }
    Ok(())
}

fn olink(l: &RoundCone<f64>) -> tubecast_oracle::Link {
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    tubecast_oracle::Link { a: ov(l.a), ra: l.ra, b: ov(l.b), rb: l.rb }
}

/// `E` of tests/kernels/link/properties.rs for precision `eps`, and the oracle's signed line gap.
fn bound_and_gap(link: &RoundCone<f64>, ray: &Ray<f64>, eps: f64) -> (f64, f64) {
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let size = (link.b - link.a).length().max(link.ra).max(link.rb);
    let e = tubecast_oracle::link_error_bound(&olink(link), ov(ray.o), size, eps);
    let line = tubecast_oracle::Line { o: ov(ray.o), d: ov(ray.d) };
    (e, tubecast_oracle::line_gap(&olink(link), &line).0)
}

fn to64(iv: Interval<f32>) -> Interval<f64> {
    iv.to_f64()
}

/// Both hits' entry and exit `t` inside the E-bands of the line ([`e_bands`]), plus 1e-12·|t|
/// for the oracle's own rounding.
pub fn same_t(
    a: &Interval<f64>,
    b: &Interval<f64>,
    link: &RoundCone<f64>,
    ray: &Ray<f64>,
    e: f64,
) -> Result<(), String> {
    let [in_lo, in_hi, out_lo, out_hi] = e_bands(link, ray, e)?;
    for (what, iv) in [("first", a), ("second", b)] {
        if !within(iv.entry.t, in_lo, in_hi) {
            return Err(format!("{what} t_in {} outside the E-band [{in_lo}, {in_hi}] (E {e:e})", iv.entry.t));
        }
        if !within(iv.exit.t, out_lo, out_hi) {
            return Err(format!("{what} t_out {} outside the E-band [{out_lo}, {out_hi}] (E {e:e})", iv.exit.t));
        }
    }
    Ok(())
}

/// `t` in `[lo, hi]` up to 1e-12·(|t| + |lo| + |hi|), the oracle's own rounding.
fn within(t: f64, lo: f64, hi: f64) -> bool {
    let slack = 1e-12 * (t.abs() + lo.abs() + hi.abs());
    t >= lo - slack && t <= hi + slack
}

/// The line's E-bands `[in_lo, in_hi, out_lo, out_hi]`: every entry (exit) whose point lies
/// within `e` of the surface is between the line's entries (exits) into the sweep dilated by
/// `e` (radii + e, the exact e-offset) and eroded by `e` (radii − e, the link cut where that
/// reaches 0: every ball of it lies ≥ e inside) — the incidence-free form of `e/(γ|d|)`, which
/// stays right where the line runs along the surface (a fuzz finding: a line along a generator
/// through a cone's tip, where any point of the generator is an equally good entry). An error
/// if the line misses the dilated sweep (no point of it is within `e` of the surface).
fn e_bands(link: &RoundCone<f64>, ray: &Ray<f64>, e: f64) -> Result<[f64; 4], String> {
    let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
    let line = tubecast_oracle::Line { o: ov(ray.o), d: ov(ray.d) };
    let l = olink(link);
    let dilated = tubecast_oracle::Link { ra: l.ra + e, rb: l.rb + e, ..l };
    // r(u) − e is linear; where it would go negative the eroded sweep ends (at r(u*) = e), so
    // the link is cut there rather than given a zero radius (which would keep its old tip).
    let eroded = if l.ra.max(l.rb) <= e {
        None
    } else if l.ra.min(l.rb) >= e {
        Some(tubecast_oracle::Link { ra: l.ra - e, rb: l.rb - e, ..l })
    } else {
        let u = (l.ra - e) / (l.ra - l.rb); // r(u) = e, in (0, 1)
        let cut = l.a + (l.b - l.a) * u;
        Some(if l.ra > l.rb {
            tubecast_oracle::Link { b: cut, ra: l.ra - e, rb: 0.0, ..l }
        } else {
            tubecast_oracle::Link { a: cut, ra: 0.0, rb: l.rb - e, ..l }
        })
    };
    let Some(dil) = tubecast_oracle::line_interval(&dilated, &line) else {
        return Err(format!("a hit where the line misses the sweep dilated by E = {e:e}"));
    };
    let ero = eroded.and_then(|l| tubecast_oracle::line_interval(&l, &line));
    let (in_hi, out_lo) = ero.map_or((dil.t_out, dil.t_in), |c| (c.t_in, c.t_out));
    Ok([dil.t_in, in_hi, out_lo, dil.t_out])
}

/// Whether the ray's origin lies between the line's possible exits, or `t_max` between its
/// possible entries ([`e_bands`]): there a clipped ray may be hit or miss within the band.
fn at_an_edge(link: &RoundCone<f64>, ray: &Ray<f64>, e: f64) -> Result<bool, String> {
    let [in_lo, in_hi, out_lo, out_hi] = e_bands(link, ray, e)?;
    Ok(within(ray.t_min, out_lo, out_hi) || within(ray.t_max, in_lo, in_hi))
}

fn f32_agrees_with_f64(link: &RoundCone<f64>, ray: &Ray<f64>) -> Result<(), String> {
    let a = link.intersect(ray);
    let l32: RoundCone<f32> = link.cast();
    let b = to64(l32.intersect(&Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>())));
    let (e32, gap) = bound_and_gap(link, ray, f32::EPSILON as f64);
    let e = e32 + bound_and_gap(link, ray, f64::EPSILON).0;
    within_band(&a, &b, gap, e, link, ray, "f32 vs f64")
}

/// Two answers `a`, `b` for `link` and `ray`, each within `e` of the sweep (`gap`: the oracle's
/// signed line gap): hit and miss may differ only inside the band `|gap| ≤ e` (or for a
/// crossing at the ray's start, which may round either way, as in tests/kernels/link/properties.rs), and
/// both hits' entry and exit lie in the E-band of the line (`same_t`).
fn within_band(
    a: &Interval<f64>,
    b: &Interval<f64>,
    gap: f64,
    e: f64,
    link: &RoundCone<f64>,
    ray: &Ray<f64>,
    what: &str,
) -> Result<(), String> {
    if a.hit != b.hit && gap.abs() > e {
        // The line is deep inside, so the clipped ray may still be either hit or miss where one
        // of its ends lies in the line's E-band: the origin between the possible exits (an
        // origin at the exit, on a line that leaves the surface at a grazing angle, as in
        // regression-grazing-exit-at-origin: 2.6e-11 rad, so a 1.6e-11 band moves the exit by
        // 0.6 along the line) or t_max between the possible entries.
        if !at_an_edge(link, ray, e).map_err(|m| format!("{what}: {m}"))? {
            return Err(format!("{what}: disagree on hit outside the band: gap {gap:e}, E {e:e}"));
        }
    } else if a.hit && b.hit && gap < -e {
        same_t(a, b, link, ray, e).map_err(|m| format!("{what}: {m}"))?;
    }
    Ok(())
}

fn han_agrees_with_stable(link: &RoundCone<f64>, ray: &Ray<f64>) -> Result<(), String> {
    let len = (link.b - link.a).length();
    let size = len.max(link.ra).max(link.rb);
    let dr = (link.ra - link.rb).abs();
    let k = if dr == 0.0 || dr >= len { 1.0 } else { len * link.ra.max(link.rb) / dr / size };
    if k > 100.0 || link.ra.min(link.rb) < 1e-3 * link.ra.max(link.rb) {
        return Ok(());
    }
    let m = (link.a + link.b) * 0.5;
    let d = (ray.o - m).length() + 100.0 * size;
    let r_min = link.ra.max(link.rb) * 1e-3 + link.ra.min(link.rb);
    let e_han = 64.0 * f64::EPSILON * d * (d / r_min).max(1.0);
    if e_han >= 1e-6 * size {
        return Ok(());
    }
    let (a, b) = (link.intersect(ray), HanLink::new(link).intersect(ray));
    let (e64, gap) = bound_and_gap(link, ray, f64::EPSILON);
    let e = e_han + e64;
    if a.hit != b.hit {
        if gap.abs() > e && !at_an_edge(link, ray, e)? {
            return Err(format!("Han and stable disagree on hit: gap {gap:e}, E {e:e}"));
        }
    } else if a.hit && gap < -e {
        let dl = ray.d.length();
        let g = a.entry.n.dot(ray.d).abs() / dl;
        let tol = e / (g * dl) + 1e-12 * a.entry.t.abs();
        let dt = (a.entry.t - b.entry.t).abs();
        if dt.is_nan() || dt > tol {
            return Err(format!("Han vs stable t_in {} vs {} (tol {tol:e})", b.entry.t, a.entry.t));
        }
    }
    Ok(())
}

/// The spline kernel on the link as a straight segment agrees with the stable link. The two
/// solids differ only by rounding: `QuadTube::from_link` forms `b₁ = (a + b)/2` and
/// `r₁ = (ra + rb)/2` once each (errors ≤ ε·|m|·√3 and ε·r_max), and a Bézier moves by at most
/// half its middle control point's error (weight 2t(1 − t) ≤ ½), so every sphere of the sweep is
/// within `p = ε·(√3·|m| + r_max)` of the link's. The spline kernel's interval is that of a tube
/// whose radius is within `E_s = 1024·ε·R + 8·ε·|o − m|` of its own (spline.rs module docs, with
/// `R ≤ L/2 + r_max`, taken as `L + r_max`), the stable link's within `E₆₄`: both intervals lie
/// between the link's sweep eroded and dilated by `e = E₆₄ + E_s + p`, which `same_t` checks, and
/// hit/miss may differ only inside the band `|gap| ≤ e`.
fn spline_agrees_with_stable(link: &RoundCone<f64>, ray: &Ray<f64>) -> Result<(), String> {
    let a = link.intersect(ray);
    let (e64, gap) = bound_and_gap(link, ray, f64::EPSILON);
    let m = (link.a + link.b) * 0.5;
    let big_r = (link.b - link.a).length() + link.ra.max(link.rb);
    let om = (ray.o - m).length();
    let l32: RoundCone<f32> = link.cast();
    let r32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    let runs = [
        ("spline (f64) vs stable link", f64::EPSILON, tubecast::QuadTube::from_link(link).map(|q| q.intersect(ray))),
        (
            "spline (f32) vs stable link",
            f32::EPSILON as f64,
            tubecast::QuadTube::from_link(&l32).map(|q| to64(q.intersect(&r32))),
        ),
    ];
    for (what, eps, b) in runs {
        let Ok(b) = b else { continue };
        let e =
            e64 + tubecast::spline_error_band(eps, big_r, om) + eps * (3f64.sqrt() * m.length() + link.ra.max(link.rb));
        within_band(&a, &b, gap, e, link, ray, what)?;
    }
    Ok(())
}
