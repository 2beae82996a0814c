//! **Experiment, not a kernel** (can a spline hit cost about what a link costs?): does a fixed-count Newton solve
//! with a positivity certificate — the simplest "proven-bracket finish" — make the spline
//! kernel's hits cheap enough for ≤ 4× `RoundCone::intersect` in f32 scalar and in lanes?
//! Nothing in tubecast uses this code; its rounding bounds are rough (constants below, not
//! derived), so its answers are not to be trusted, only its cost and how often it certifies.
//!
//! `cargo bench -p tubecast-lab --bench newton_certificate` prints, for the spline bench's
//! 64 hit rays (`benches/spline.rs`, `spline_hits`: same generator, same seed), how many the
//! experiment certifies in f32 and f64 and their largest distance from the kernel's f64
//! answer, then times per ray, in one run, `RoundCone::intersect` (the unit), the kernel's
//! default solver and the experiment, each consuming entry **and** exit (the spline bench
//! consumes the entry only), f32 and f32x8.
//!
//! # The design measured
//! Ray space as in the kernel (origin at the line's point nearest `p(½)`, unit `d̂ = e`,
//! units of the bounding radius). Entry `s* = min f`, `f = h − √g` (`h = q·e`,
//! `g = r² − |q × e|²`); the exit is the entry along `−e`.
//! 1. *Start*: `f` at `t = 0, ¼, ½, ¾, 1`, best real sample; where none is real, four
//!    trust-region Newton steps uphill on `g` from its best sample.
//! 2. *Solve*: `NIT` trust-region Newton steps on `f'` (`f''` from `g, g', g''`), a step kept
//!    only if it stays real and does not raise `f` (else the radius halves); entry and exit in
//!    one loop (independent chains).
//! 3. *Certificate* that `s_lo = f(t*) − δ` is below every sphere's entry, which holds iff
//!    for every `t`: `h(t) ≥ s_lo ⇒ D(t) = |s_lo e − q(t)|² − r(t)² ≥ 0` and
//!    `h(t) < s_lo ⇒ g(t) < 0` (a sphere whose centre projects before `s_lo` must miss the
//!    line, else it is entered before `s_lo`). Near `t*` a Taylor bound of the quartic `D`
//!    about `t*`; elsewhere `[0, 1]` is cut at the roots of the quadratic `h − s_lo` and each
//!    piece is certified by the Bernstein coefficients of `D` (or `−g`) formed from the
//!    de Casteljau control vectors, halving up to `DEPTH` times. `f(t*)` itself is a sphere's
//!    entry, so `s* ∈ [s_lo, f(t*)]`.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use tubecast::{Mask, Primitive, QuadTube, Ray, Real, RoundCone, WideF32x8, V3};

/// Newton steps on `f'` per side.
const NIT: usize = 8;
/// Halvings of a piece whose Bernstein coefficients do not certify it.
const DEPTH: u32 = 3;

/// The ray-space frame.
struct Frame<T> {
    c: [V3<T>; 3],
    r: [T; 3],
    e: V3<T>,
    tc: T,
    scale: T,
}

#[inline(always)]
fn frame<T: Real>(tube: &QuadTube<T>, ray: &Ray<T>) -> Frame<T> {
    let two = T::cst(2.0);
    let [b0, b1, b2] = tube.b;
    let m = (b0 + b1 * two + b2) * T::cst(0.25);
    let d2 = ray.d.length2();
    let dlen = d2.sqrt();
    let e = ray.d * (T::one() / dlen);
    let tc = (m - ray.o).dot(ray.d) / d2;
    let l = (ray.o - m) + ray.d * tc;
    let rmax = tube.r[0].max(tube.r[1]).max(tube.r[2]);
    let big = (b0 - m).length().max((b1 - m).length()).max((b2 - m).length()) + rmax;
    let inv = T::one() / big;
    let c = [(b0 - m - l) * inv, (b1 - m - l) * inv, (b2 - m - l) * inv];
    let r = [tube.r[0] * inv, tube.r[1] * inv, tube.r[2] * inv];
    Frame { c, r, e, tc, scale: big / dlen }
}

#[inline(always)]
fn blossom<T: Real>(c: [V3<T>; 3], a: T, b: T) -> V3<T> {
    let (sa, sb) = (T::one() - a, T::one() - b);
    c[0] * (sa * sb) + c[1] * (sa * b + a * sb) + c[2] * (a * b)
}
#[inline(always)]
fn blossom_s<T: Real>(c: [T; 3], a: T, b: T) -> T {
    let (sa, sb) = (T::one() - a, T::one() - b);
    c[0] * (sa * sb) + c[1] * (sa * b + a * sb) + c[2] * (a * b)
}

/// min over Bernstein coefficients of |v|^2 - r^2 (deg 4) minus an error bound; > 0 certifies.
#[inline(always)]
fn bern_margin<T: Real>(v: [V3<T>; 3], r: [T; 3]) -> T {
    let third = T::cst(1.0 / 3.0);
    let two = T::cst(2.0);
    let d0 = v[0].dot(v[0]) - r[0] * r[0];
    let d1 = v[0].dot(v[1]) - r[0] * r[1];
    let d2 = (v[0].dot(v[2]) + two * v[1].dot(v[1]) - r[0] * r[2] - two * r[1] * r[1]) * third;
    let d3 = v[1].dot(v[2]) - r[1] * r[2];
    let d4 = v[2].dot(v[2]) - r[2] * r[2];
    let vm = v[0].length2().max(v[1].length2()).max(v[2].length2()).sqrt();
    let rm = r[0].abs().max(r[1].abs()).max(r[2].abs());
    let err = T::epsilon() * T::cst(64.0) * (vm + rm + T::one()) * (vm + rm);
    d0.min(d1).min(d2).min(d3).min(d4) - err
}

fn certify<T: Real>(f: &Frame<T>, e: V3<T>, s_lo: T, hu: [T; 3], a: T, b: T, depth: u32) -> T::Mask {
    let vc = [e * s_lo - blossom(f.c, a, a), e * s_lo - blossom(f.c, a, b), e * s_lo - blossom(f.c, b, b)];
    let rcp = [blossom_s(f.r, a, a), blossom_s(f.r, a, b), blossom_s(f.r, b, b)];
    let mid = (a + b) * T::cst(0.5);
    let um = (hu[0] * mid + hu[1]) * mid + hu[2];
    let pos = um.ge(T::zero());
    let m = if pos.all() {
        bern_margin(vc, rcp)
    } else {
        let wc = [vc[0].cross(e), vc[1].cross(e), vc[2].cross(e)];
        let mg = bern_margin(wc, rcp);
        if pos.none() {
            mg
        } else {
            T::select(pos, bern_margin(vc, rcp), mg)
        }
    };
    let good = m.gt(T::zero()) | !b.gt(a);
    if good.all() || depth == 0 {
        return good;
    }
    let l = certify(f, e, s_lo, hu, a, mid, depth - 1);
    let r = certify(f, e, s_lo, hu, mid, b, depth - 1);
    good | (l & r)
}

/// Power-basis curve data in the frame.
struct Poly<T> {
    qa: V3<T>,
    qb: V3<T>,
    qc: V3<T>,
    ra: T,
    rb: T,
    rc: T,
}

#[inline(always)]
fn hg<T: Real>(p: &Poly<T>, e: V3<T>, t: T) -> (T, T) {
    let q = (p.qa * t + p.qb) * t + p.qc;
    let r = (p.ra * t + p.rb) * t + p.rc;
    let w = q.cross(e);
    let wl = w.length();
    (q.dot(e), (r - wl) * (r + wl))
}

/// One trust-region Newton step on f = σh − √g for both σ at once (independent chains).
#[inline(always)]
fn newton2<T: Real>(p: &Poly<T>, e: V3<T>, t: [T; 2], ft: [T; 2], rho: [T; 2]) -> ([T; 2], [T; 2], [T; 2]) {
    let two = T::cst(2.0);
    let q2 = p.qa * two;
    let r2 = p.ra * two;
    let h2 = q2.dot(e);
    let w2 = q2.cross(e);
    let mut out = (t, ft, rho);
    for k in 0..2 {
        let sigma = if k == 0 { T::one() } else { -T::one() };
        let t = t[k];
        let q = (p.qa * t + p.qb) * t + p.qc;
        let q1 = p.qa * (two * t) + p.qb;
        let r = (p.ra * t + p.rb) * t + p.rc;
        let r1 = p.ra * (two * t) + p.rb;
        let (w, w1) = (q.cross(e), q1.cross(e));
        let wl = w.length();
        let g = ((r - wl) * (r + wl)).max(T::cst(1e-30));
        let g1 = two * (r * r1 - w.dot(w1));
        let g2 = two * (r1 * r1 + r * r2 - w1.dot(w1) - w.dot(w2));
        let sg = g.sqrt();
        let fp = sigma * q1.dot(e) - g1 / (two * sg);
        let fpp = sigma * h2 - (two * g * g2 - g1 * g1) / (T::cst(4.0) * g * sg);
        let step = (-fp / fpp.abs()).clamp(-rho[k], rho[k]);
        let tn = (t + step).clamp(T::zero(), T::one());
        let (hn, gn) = hg(p, e, tn);
        let fnew = sigma * hn - gn.max(T::zero()).sqrt();
        let acc = gn.ge(T::zero()) & fnew.le(ft[k]);
        out.0[k] = T::select(acc, tn, t);
        out.1[k] = T::select(acc, fnew, ft[k]);
        out.2[k] = T::select(acc, rho[k], rho[k] * T::cst(0.5));
    }
    out
}

/// Certify that no sphere is entered before s_lo along e (entry σ = 1; the exit is the entry
/// along −e). Returns the lanes certified.
#[inline(always)]
fn certify_entry<T: Real>(f: &Frame<T>, p: &Poly<T>, e: V3<T>, t: T, s_lo: T) -> T::Mask {
    let two = T::cst(2.0);
    let q = (p.qa * t + p.qb) * t + p.qc;
    let q1 = p.qa * (two * t) + p.qb;
    let q2 = p.qa * two;
    let r = (p.ra * t + p.rb) * t + p.rc;
    let r1 = p.ra * (two * t) + p.rb;
    let r2 = p.ra * two;
    let v = e * s_lo - q;
    let (v1, v2) = (-q1, -q2);
    let vl = v.length();
    let a0 = (vl - r) * (vl + r);
    let a1 = two * (v.dot(v1) - r * r1);
    let a2 = v1.dot(v1) + v.dot(v2) - r1 * r1 - r * r2;
    let a3 = v1.dot(v2) - r1 * r2;
    let a4 = (v2.dot(v2) - r2 * r2) * T::cst(0.25);
    let w3 = T::cst(0.25) * a2 / a3.abs().max(T::cst(1e-30));
    let w4 = (T::cst(0.25) * a2 / a4.abs().max(T::cst(1e-30))).max(T::zero()).sqrt();
    let w = T::select(a2.gt(T::zero()), T::cst(0.25).min(w3).min(w4), T::cst(0.02));
    let cc = a2 - a3.abs() * w - a4.abs() * w * w;
    let ul = (-w).max(-t);
    let uh = w.min(T::one() - t);
    let qv = |u: T| a0 + a1 * u + cc * u * u;
    let mut mn = qv(ul).min(qv(uh));
    let uv = (-a1 / (two * cc)).clamp(ul, uh);
    mn = T::select(cc.gt(T::zero()), mn.min(qv(uv)), mn);
    let terr = T::epsilon() * T::cst(32.0) * (vl + r) * (T::one() + vl + r);
    let mut ok = mn.gt(terr);
    let (ha, hb, hc) = (p.qa.dot(e), p.qb.dot(e), p.qc.dot(e) - s_lo);
    let disc = hb * hb - T::cst(4.0) * ha * hc;
    let sq = disc.max(T::zero()).sqrt();
    let qq = -(hb + sq.copysign_of(hb)) * T::cst(0.5);
    let has = disc.gt(T::zero());
    let nan_to = |x: T| T::select(x.is_finite() & has, x, T::cst(2.0));
    let (x1, x2) = (nan_to(qq / ha), nan_to(hc / qq));
    let cuts = [x1.min(x2), x1.max(x2)];
    for (pa, pb) in [(T::zero(), t + ul), (t + uh, T::one())] {
        let mut a = pa;
        // Up to three pieces: ends at the cuts inside (a, pb) (else empty), then pb.
        for (k, &cut) in cuts.iter().chain(std::iter::once(&pb)).enumerate() {
            let b = if k < 2 { T::select(cut.gt(a) & cut.lt(pb), cut, a) } else { pb };
            let nonempty = b.gt(a);
            if nonempty.any() {
                let ok_p = certify(f, e, s_lo, [ha, hb, hc], a, b, DEPTH);
                ok = ok & (!nonempty | ok_p);
            }
            a = T::select(nonempty, b, a);
        }
    }
    ok
}

#[inline(always)]
fn cert_intersect<T: Real>(tube: &QuadTube<T>, ray: &Ray<T>) -> (T, T, T::Mask, T::Mask) {
    let f = frame(tube, ray);
    let two = T::cst(2.0);
    let [c0, c1, c2] = f.c;
    let [r0, r1, r2] = f.r;
    let p = Poly {
        qa: c0 - c1 * two + c2,
        qb: (c1 - c0) * two,
        qc: c0,
        ra: r0 - r1 * two + r2,
        rb: (r1 - r0) * two,
        rc: r0,
    };
    let e = f.e;
    // Shared samples: g is the same for both σ.
    let inf = T::infinity();
    let (mut bt, mut bf, mut gt, mut gb) = ([T::zero(); 2], [inf; 2], T::zero(), -inf);
    for k in 0..5 {
        let t = T::cst(k as f64 * 0.25);
        let (h, g) = hg(&p, e, t);
        let sg = g.max(T::zero()).sqrt();
        let real = g.ge(T::zero());
        for (j, fv) in [h - sg, -h - sg].into_iter().enumerate() {
            let ok = real & fv.lt(bf[j]);
            bf[j] = T::select(ok, fv, bf[j]);
            bt[j] = T::select(ok, t, bt[j]);
        }
        let ok = g.gt(gb);
        gb = T::select(ok, g, gb);
        gt = T::select(ok, t, gt);
    }
    let real0 = bf[0].lt(inf);
    let mut t = [T::select(real0, bt[0], gt), T::select(real0, bt[1], gt)];
    if (!real0).any() {
        let mut rho = T::cst(0.125);
        let mut tg = gt;
        for _ in 0..4 {
            let q = (p.qa * tg + p.qb) * tg + p.qc;
            let q1 = p.qa * (two * tg) + p.qb;
            let r = (p.ra * tg + p.rb) * tg + p.rc;
            let rr1 = p.ra * (two * tg) + p.rb;
            let (w, w1, w2) = (q.cross(e), q1.cross(e), (p.qa * two).cross(e));
            let g = r * r - w.dot(w);
            let g1 = two * (r * rr1 - w.dot(w1));
            let g2 = two * (rr1 * rr1 + r * p.ra * two - w1.dot(w1) - w.dot(w2));
            let step = (g1 / g2.abs()).clamp(-rho, rho);
            let tn = (tg + step).clamp(T::zero(), T::one());
            let (_, gn) = hg(&p, e, tn);
            let acc = gn.ge(g);
            tg = T::select(acc, tn, tg);
            rho = T::select(acc, rho, rho * T::cst(0.5));
        }
        let (h, g) = hg(&p, e, tg);
        let sg = g.max(T::zero()).sqrt();
        let rg = g.ge(T::zero()) & !real0;
        bf = [T::select(rg, h - sg, bf[0]), T::select(rg, -h - sg, bf[1])];
        t = [T::select(real0, t[0], tg), T::select(real0, t[1], tg)];
    }
    let real = bf[0].lt(inf);
    let mut ft = bf;
    let mut rho = [T::cst(0.25); 2];
    for _ in 0..NIT {
        (t, ft, rho) = newton2(&p, e, t, ft, rho);
    }
    let (hi, gi) = hg(&p, e, t[0]);
    let (ho, go) = hg(&p, e, t[1]);
    let s_in = hi - gi.max(T::zero()).sqrt();
    let s_out = ho + go.max(T::zero()).sqrt();
    let real = real & gi.ge(T::zero()) & go.ge(T::zero());
    let delta = T::epsilon() * T::cst(256.0);
    let ok = certify_entry(&f, &p, e, t[0], s_in - delta) & certify_entry(&f, &p, -e, t[1], -s_out - delta);
    (f.tc + s_in * f.scale, f.tc + s_out * f.scale, real, ok)
}

const N: usize = 64;
include!("../../../benches/common/spline_cases.rs");

/// Certified count and largest distance (along the ray, world units) from the kernel's f64
/// interval, in precision `T`.
fn certified<T: tubecast::Scalar>(cs: &[(QuadTube<f64>, RoundCone<f64>, Ray<f64>)]) -> (usize, f64) {
    let (mut n, mut err) = (0, 0.0f64);
    for (t, _, r) in cs {
        let k = t.intersect(r);
        let (ti, to, real, ok) = cert_intersect(&t.cast::<T>(), &Ray::new(r.o.cast::<T>(), r.d.cast::<T>()));
        if real && ok {
            n += 1;
            let e = (ti.to_f64() - k.entry.t).abs().max((to.to_f64() - k.exit.t).abs()) * r.d.length();
            err = err.max(e);
        }
    }
    (n, err)
}

fn bench(c: &mut Criterion) {
    let cs = cases(Mix::Hits);
    let (n32, e32) = certified::<f32>(&cs);
    let (n64, e64) = certified::<f64>(&cs);
    eprintln!(
        "certified hits: f32 {n32}/64 (max distance from the kernel's f64 answer {e32:.3e}), f64 {n64}/64 ({e64:.3e})"
    );
    let s: Vec<(QuadTube<f32>, RoundCone<f32>, Ray<f32>)> = cs
        .iter()
        .map(|(t, l, r)| {
            (
                t.cast(),
                RoundCone::new(l.a.cast(), l.ra as f32, l.b.cast(), l.rb as f32).unwrap(),
                Ray::new(r.o.cast(), r.d.cast()),
            )
        })
        .collect();
    type W = WideF32x8;
    let w: Vec<(QuadTube<W>, RoundCone<W>, Ray<W>)> = (0..8)
        .map(|k| {
            (
                QuadTube::<W>::from_lanes(|i| s[k * 8 + i].0),
                RoundCone::<W>::from_lanes(|i| s[k * 8 + i].1),
                Ray::<W>::from_fn(|i| s[k * 8 + i].2),
            )
        })
        .collect();
    let lanes: usize = w
        .iter()
        .map(|(t, _, r)| cert_intersect(t, r))
        .map(|(_, _, re, ok)| (0..8).filter(|&i| (re & ok).lane(i)).count())
        .sum();
    eprintln!("certified hits in f32x8 lanes: {lanes}/64");
    let mut g = c.benchmark_group("newton_certificate_hits/f32");
    g.throughput(Throughput::Elements(64));
    g.bench_function("round_cone_link", |b| {
        b.iter(|| {
            s.iter()
                .map(|(_, l, r)| black_box(l).intersect(black_box(r)))
                .map(|iv| iv.entry.t.min(1e9) + iv.exit.t.min(1e9))
                .sum::<f32>()
        })
    });
    g.bench_function("spline/polynomial", |b| {
        b.iter(|| {
            s.iter()
                .map(|(t, _, r)| black_box(t).intersect(black_box(r)))
                .map(|iv| iv.entry.t.min(1e9) + iv.exit.t.min(1e9))
                .sum::<f32>()
        })
    });
    g.bench_function("experiment", |b| {
        b.iter(|| {
            s.iter()
                .map(|(t, _, r)| cert_intersect(black_box(t), black_box(r)))
                .map(|(ti, to, re, ok)| ti.min(1e9) + to.min(1e9) + if re & ok { 1.0 } else { 0.0 })
                .sum::<f32>()
        })
    });
    g.finish();
    let mut g = c.benchmark_group("newton_certificate_hits/f32x8");
    g.throughput(Throughput::Elements(64));
    let big = W::cst(1e9);
    g.bench_function("round_cone_link", |b| {
        b.iter(|| {
            w.iter()
                .map(|(_, l, r)| black_box(l).intersect(black_box(r)))
                .fold(W::zero(), |a, iv| a + iv.entry.t.min(big) + iv.exit.t.min(big))
        })
    });
    g.bench_function("spline/polynomial", |b| {
        b.iter(|| {
            w.iter()
                .map(|(t, _, r)| black_box(t).intersect(black_box(r)))
                .fold(W::zero(), |a, iv| a + iv.entry.t.min(big) + iv.exit.t.min(big))
        })
    });
    g.bench_function("experiment", |b| {
        b.iter(|| {
            w.iter()
                .map(|(t, _, r)| cert_intersect(black_box(t), black_box(r)))
                .fold(W::zero(), |a, (ti, to, re, ok)| {
                    a + ti.min(big) + to.min(big) + W::select(re & ok, W::one(), W::zero())
                })
        })
    });
    g.finish();
}

criterion_group! {
    name = newton_certificate;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(1)).warm_up_time(std::time::Duration::from_millis(300));
    targets = bench
}
criterion_main!(newton_certificate);
