//! Spline-tube kernel cost: f32, f64, WideF32x8, WideF64x4 × each solver, and the stable link
//! kernel `RoundCone::intersect` on the same rays in the same run (the unit of cost).
//!
//! `cargo bench --bench spline` (add `RUSTFLAGS="-C target-cpu=x86-64-v3"` for full-width
//! lanes). Every benchmark of a group runs the same fixed set of 64 (segment, ray) pairs —
//! `spline/*`: the first 64 generated, 22 of them hits; `spline_hits/*`, `spline_misses/*`: the first
//! 64 that hit / miss — and reports the time per ray (lane benches: per ray, i.e. divided by
//! the lane count via `Throughput::Elements`); the link runs on the same rays in each group.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use tubecast::QuadTube;
use tubecast::Solver;
use tubecast::{Primitive, Real, Scalar, WideF32x8, WideF64x4};
use tubecast::{Ray, RoundCone, V3};

const N: usize = 64;

include!("common/spline_cases.rs");

const SOLVERS: [(&str, Solver); 5] = [
    ("bisection10", Solver::Bisection { iters: 10 }),
    ("bisection20", Solver::Bisection { iters: 20 }),
    ("itp", Solver::Itp),
    ("newton", Solver::Newton),
    ("polynomial", Solver::Polynomial),
];

/// One group per precision; scalars are the one-lane case (`T::LANES == 1`).
fn lanes<T: Real>(c: &mut Criterion, name: &str, mix: Mix)
where
    T::Elem: Scalar,
{
    let cs = cases(mix);
    let w = T::LANES;
    let packs: Vec<(QuadTube<T>, RoundCone<T>, Ray<T>)> = (0..N / w)
        .map(|k| {
            let t = QuadTube::<T>::from_lanes(|i| cs[k * w + i].0.cast());
            let l = RoundCone::<T>::from_lanes(|i| cs[k * w + i].1.cast());
            let r = Ray::<T>::from_fn(|i| Ray::new(cs[k * w + i].2.o.cast(), cs[k * w + i].2.d.cast()));
            (t, l, r)
        })
        .collect();
    let group = match mix {
        Mix::All => "spline",
        Mix::Hits => "spline_hits",
        Mix::Misses => "spline_misses",
    };
    let mut g = c.benchmark_group(format!("{group}/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("round_cone_link", |b| {
        b.iter(|| {
            let mut acc = T::zero();
            for (_, l, r) in &packs {
                acc += black_box(l).intersect(black_box(r)).entry.t.min(T::cst(1e9));
            }
            acc
        })
    });
    for (sn, s) in SOLVERS {
        g.bench_with_input(BenchmarkId::new("spline", sn), &s, |b, &s| {
            b.iter(|| {
                let mut acc = T::zero();
                for (t, _, r) in &packs {
                    acc += black_box(t).intersect_with(black_box(r), s).entry.t.min(T::cst(1e9));
                }
                acc
            })
        });
    }
    g.finish();
}

/// Segments, links and rays of [`leaf`].
type Leaf = (Vec<QuadTube<f64>>, Vec<RoundCone<f64>>, Vec<Ray<f64>>);

/// A renderer's leaf: eight consecutive C¹ quadratic segments of one smooth tube (radius 0.05,
/// chords ≈ 0.5: `b₂` of one is `b₀` of the next, `b₁` mirrored through it), the links on their
/// chords, and 64 rays from 5 away aimed at uniform points of the leaf's box (what reaches a
/// leaf; `hit`: at points within 0.8 radii of the centre line, so every ray hits). One lane
/// call tests a ray against all eight, as `crates/render`'s link packets do.
fn leaf(hit: bool) -> Leaf {
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut u = || V3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
    let (mut b0, mut leg) = (V3::new(0.0, 0.0, 0.0), V3::new(0.25, 0.0, 0.0));
    let (mut tubes, mut links) = (Vec::new(), Vec::new());
    let (mut lo, mut hi) = (b0, b0);
    for _ in 0..8 {
        let b1 = b0 + leg;
        let turn = u() * 0.12;
        let b2 = b1 + (leg + turn) * (0.25 / (leg + turn).length());
        tubes.push(QuadTube::new([b0, b1, b2], [0.05, 0.05, 0.05]).unwrap());
        links.push(RoundCone::new(b0, 0.05, b2, 0.05).unwrap());
        for p in [b1, b2] {
            lo = V3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = V3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        leg = b2 - b1;
        b0 = b2;
    }
    let (lo, hi) = (lo - V3::new(0.05, 0.05, 0.05), hi + V3::new(0.05, 0.05, 0.05));
    let mut rays = Vec::new();
    while rays.len() < N {
        let (f, dir) = (u(), u());
        if dir.length() < 0.2 {
            continue;
        }
        let tgt = if hit {
            // A point of a segment's centre line, moved by under 0.8 radii.
            let k = ((f.x + 1.0) * 4.0).min(7.99) as usize;
            tubes[k].point((f.y + 1.0) * 0.5) + u() * (0.04 / 3f64.sqrt())
        } else {
            let s = |a: f64, l: f64, h: f64| l + (a + 1.0) * 0.5 * (h - l);
            V3::new(s(f.x, lo.x, hi.x), s(f.y, lo.y, hi.y), s(f.z, lo.z, hi.z))
        };
        rays.push(Ray::new(tgt - dir * (5.0 / dir.length()), dir));
    }
    (tubes, links, rays)
}

/// `spline_leaf/*`, `spline_leaf_hits/*`: each ray against a leaf's eight segments, f32 (eight calls) and f32x8 (one
/// call), the links on the same leaf in the same run.
fn leaf_bench(c: &mut Criterion, hit: bool) {
    let (tubes, links, rays) = leaf(hit);
    let group = if hit { "spline_leaf_hits" } else { "spline_leaf" };
    let hits = rays.iter().filter(|r| tubes.iter().any(|t| t.intersect(r).hit)).count();
    let tests: usize = rays.iter().map(|r| tubes.iter().filter(|t| t.intersect(r).hit).count()).sum();
    eprintln!("{group}: {hits} of {N} rays hit the leaf's tube, {tests} segment hits");
    let t32: Vec<QuadTube<f32>> = tubes.iter().map(|t| t.cast()).collect();
    let l32: Vec<RoundCone<f32>> =
        links.iter().map(|l| RoundCone::new(l.a.cast(), l.ra as f32, l.b.cast(), l.rb as f32).unwrap()).collect();
    let r32: Vec<Ray<f32>> = rays.iter().map(|r| Ray::new(r.o.cast(), r.d.cast())).collect();
    let mut g = c.benchmark_group(format!("{group}/f32"));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("round_cone_link", |b| {
        b.iter(|| {
            r32.iter()
                .map(|r| l32.iter().map(|l| black_box(l).intersect(black_box(r)).entry.t.min(1e9)).sum::<f32>())
                .sum::<f32>()
        })
    });
    g.bench_function("spline/polynomial", |b| {
        b.iter(|| {
            r32.iter()
                .map(|r| t32.iter().map(|t| black_box(t).intersect(black_box(r)).entry.t.min(1e9)).sum::<f32>())
                .sum::<f32>()
        })
    });
    g.finish();
    let tw = QuadTube::<WideF32x8>::from_lanes(|i| t32[i]);
    let lw = RoundCone::<WideF32x8>::from_lanes(|i| l32[i]);
    let rw: Vec<Ray<WideF32x8>> = r32.iter().map(|r| Ray::broadcast(*r)).collect();
    let big = WideF32x8::cst(1e9);
    let mut g = c.benchmark_group(format!("{group}/f32x8"));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("round_cone_link", |b| {
        b.iter(|| rw.iter().fold(WideF32x8::zero(), |a, r| a + black_box(&lw).intersect(black_box(r)).entry.t.min(big)))
    });
    g.bench_function("spline/polynomial", |b| {
        b.iter(|| rw.iter().fold(WideF32x8::zero(), |a, r| a + black_box(&tw).intersect(black_box(r)).entry.t.min(big)))
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    leaf_bench(c, false);
    leaf_bench(c, true);
    for mix in [Mix::All, Mix::Hits, Mix::Misses] {
        lanes::<f32>(c, "f32", mix);
        lanes::<f64>(c, "f64", mix);
        lanes::<WideF32x8>(c, "f32x8", mix);
        lanes::<WideF64x4>(c, "f64x4", mix);
    }
}

criterion_group! {
    name = spline;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(1)).warm_up_time(std::time::Duration::from_millis(300));
    targets = benches
}
criterion_main!(spline);
