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
                acc += black_box(l).intersect(black_box(r)).t_in.min(T::cst(1e9));
            }
            acc
        })
    });
    for (sn, s) in SOLVERS {
        g.bench_with_input(BenchmarkId::new("spline", sn), &s, |b, &s| {
            b.iter(|| {
                let mut acc = T::zero();
                for (t, _, r) in &packs {
                    acc += black_box(t).intersect_with(black_box(r), s).t_in.min(T::cst(1e9));
                }
                acc
            })
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
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
