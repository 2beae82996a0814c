//! Criterion benches: every link kernel × {f32, f64, f32x8, f64x4}, with ray–sphere as the
//! baseline. Throughput is in rays (one ray–primitive test each), so criterion prints rays/s
//! per core; compare kernels by the ratio to `sphere` measured in the same run.
//!
//!     RUSTFLAGS="-C target-cpu=x86-64-v3" cargo bench --bench kernels
use criterion::measurement::Measurement;
use criterion::{black_box, criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion, Throughput};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tubecast::baseline::cone::{intersect_stump_precomputed, TangentCone, UnitConeTransform};
use tubecast::baseline::HanLink;
use tubecast::{Interval, Primitive, Ray, Real, RoundCone, Sphere, WideF32x8, WideF64x4, V3};

const N: usize = 1024;

/// Links of random radii near the origin and rays aimed near them (about half hit).
fn workload() -> (Vec<RoundCone<f64>>, Vec<Ray<f64>>) {
    let mut rng = StdRng::seed_from_u64(7);
    let mut v = |s: f64| V3::new(rng.gen_range(-s..s), rng.gen_range(-s..s), rng.gen_range(-s..s));
    let mut links = Vec::new();
    let mut rays = Vec::new();
    for _ in 0..N {
        let a = v(1.0);
        let b = a + v(2.0);
        let target = (a + b) * 0.5 + v(0.5);
        let o = v(10.0) + V3::new(20.0, 0.0, 0.0);
        links.push(RoundCone::new(a, 0.2 + 0.1 * target.x.abs(), b, 0.15 + 0.1 * target.y.abs()).unwrap());
        rays.push(Ray::new(o, target - o));
    }
    (links, rays)
}

fn bench_precision<T: Real>(c: &mut Criterion, name: &str, links: &[RoundCone<f64>], rays: &[Ray<f64>])
where
    T::Elem: tubecast::Scalar,
{
    let cast = |l: &RoundCone<f64>| l.cast::<T::Elem>();
    let castr = |r: &Ray<f64>| Ray::<T::Elem>::new(r.o.cast(), r.d.cast());
    let w = T::LANES;
    let ls: Vec<RoundCone<T>> = (0..N / w).map(|k| RoundCone::from_lanes(|i| cast(&links[k * w + i]))).collect();
    let rs: Vec<Ray<T>> = (0..N / w).map(|k| Ray::from_fn(|i| castr(&rays[k * w + i]))).collect();
    let hans: Vec<HanLink<T>> = ls.iter().map(HanLink::new).collect();
    let cones: Vec<(TangentCone<T>, UnitConeTransform<T>)> = ls
        .iter()
        .map(|l| {
            let c = TangentCone::new(l.a, l.ra, l.b, l.rb);
            (c, UnitConeTransform::new(&c))
        })
        .collect();
    let spheres: Vec<Sphere<T>> = ls.iter().map(|l| Sphere { c: l.a, r: l.ra }).collect();
    let mut g = c.benchmark_group(format!("kernels/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    run(&mut g, "sphere", name, &rs, |k, r| spheres[k].intersect(r));
    run(&mut g, "link_stable", name, &rs, |k, r| ls[k].intersect(r));
    run(&mut g, "link_han_precomputed", name, &rs, |k, r| hans[k].intersect(r));
    run(&mut g, "link_han_on_the_fly", name, &rs, |k, r| ls[k].intersect_han_on_the_fly(r));
    run(&mut g, "stump_han_precomputed", name, &rs, |k, r| intersect_stump_precomputed(r, &cones[k].0, &cones[k].1));
    run(&mut g, "stump_stable", name, &rs, |k, r| ls[k].intersect_stump_stable(r));
    g.finish();
}

/// One bench: `f(k, ray)` over every lane group `k` (generic, so the kernel is inlined).
fn run<T: Real, M: Measurement>(
    g: &mut BenchmarkGroup<'_, M>,
    id: &str,
    name: &str,
    rs: &[Ray<T>],
    f: impl Fn(usize, &Ray<T>) -> Interval<T>,
) {
    g.bench_function(BenchmarkId::new(id, name), |b| {
        b.iter(|| {
            for (k, r) in rs.iter().enumerate() {
                black_box(f(k, r));
            }
        })
    });
}

fn kernels(c: &mut Criterion) {
    let (links, rays) = workload();
    bench_precision::<f32>(c, "f32", &links, &rays);
    bench_precision::<f64>(c, "f64", &links, &rays);
    bench_precision::<WideF32x8>(c, "f32x8", &links, &rays);
    bench_precision::<WideF64x4>(c, "f64x4", &links, &rays);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_secs(1));
    targets = kernels
}
criterion_main!(benches);
