//! Embree 3 vs tubecast on the same scene and the same `f32` rays (feature `embree`):
//! `cargo bench --features embree --bench peers`.
//!
//! Scene: a generated *Furball* of ~10⁴ links; rays: 64×64 camera rays rounded to `f32`.
//! Groups: whole-scene closest hit (our BVH + stable `f32` links, and the 8-wide `WideBvh` with
//! the static link filter, vs Embree `ROUND_LINEAR_CURVE`
//! as isolated segments, the same solid; Embree `ROUND_HERMITE_CURVE`, a swept circle, speed only)
//! and one ray–link test (our kernel vs a one-segment Embree scene, which includes Embree's
//! traversal overhead of one node).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use tubecast::{Primitive, Ray, RoundCone, V3};
use tubecast_lab::peer::embree::{Device, Scene as EScene};
use tubecast_lab::peer::{scene_inputs, SceneInputs};
use tubecast_render::accel::{Bvh, Tracer, WideBvh};
use tubecast_render::render::Camera;
use tubecast_render::scene::{generate, Scene};

fn peers(c: &mut Criterion) {
    let lines = generate::furball(128, 78, 1);
    let scene = Scene::from_polylines(&lines, 0.05, "furball").expect("scene");
    let st = scene.stats();
    let side = 64;
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 35.0, side, side).expect("camera");
    let SceneInputs { rays32, rays64, links32 } = scene_inputs(&scene, &cam, side);
    let dev = Device::new().expect("embree device");
    let emb = EScene::round_linear(&dev, &links32).expect("embree scene");
    let bvh = Bvh::build(scene.primitives());
    let wide = WideBvh::build(scene.primitives());

    let mut g = c.benchmark_group("peers_scene_closest_hit");
    g.throughput(Throughput::Elements(rays32.len() as u64));
    g.bench_function("tubecast_bvh_stable_f32", |b| {
        b.iter(|| rays64.iter().filter(|r| bvh.closest_hit(black_box(r)).is_some()).count())
    });
    g.bench_function("tubecast_wide_bvh_filtered", |b| {
        b.iter(|| rays64.iter().filter(|r| wide.closest_hit(black_box(r)).is_some()).count())
    });
    g.bench_function("embree_round_linear", |b| b.iter(|| emb.count_hits(black_box(&rays32))));
    let segs: Vec<_> = lines
        .iter()
        .flat_map(|l| {
            let p = l.points.clone();
            let r = l.radii.clone();
            (0..p.len() - 1).map(move |k| {
                let t = [0, 1, 2].map(|i| (p[k + 1][i] - p[k][i]) as f32);
                let dr = (r[k + 1] - r[k]) as f32;
                let v = |q: [f64; 3], rr: f64| [q[0] as f32, q[1] as f32, q[2] as f32, rr as f32];
                (v(p[k], r[k]), [t[0], t[1], t[2], dr], v(p[k + 1], r[k + 1]), [t[0], t[1], t[2], dr])
            })
        })
        .collect();
    let herm = EScene::round_hermite(&dev, &segs).expect("embree hermite scene");
    g.bench_function("embree_round_hermite_swept_circle", |b| b.iter(|| herm.count_hits(black_box(&rays32))));
    g.finish();

    // One link, many rays aimed at it.
    let l = RoundCone::new(V3::new(0.0f32, 0.0, 0.0), 1.0, V3::new(4.0, 0.5, 0.0), 0.4).expect("link");
    let one = EScene::round_linear(&dev, &[l]).expect("embree scene");
    let rays: Vec<([f32; 3], [f32; 3])> = (0..1024)
        .map(|i| {
            let y = (i as f32 / 1024.0) * 3.0 - 1.5;
            ([2.0, y, -10.0], [0.01 * (i % 7) as f32, 0.0, 1.0])
        })
        .collect();
    let ours: Vec<Ray<f32>> = rays.iter().map(|(o, d)| Ray::new(V3::from(*o), V3::from(*d))).collect();
    let mut g = c.benchmark_group("peers_one_link");
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("tubecast_stable_f32", |b| {
        b.iter(|| ours.iter().filter(|r| l.intersect(black_box(r)).hit).count())
    });
    g.bench_function("embree_round_linear_one_segment", |b| b.iter(|| one.count_hits(black_box(&rays))));
    g.finish();
}

criterion_group!(benches, peers);
criterion_main!(benches);
