//! Whole-frame render time and BVH build time.
//!
//! * `frame/{scene}/{links|splines}/{opaque|transparent}`: one frame of a generated scene at
//!   64×48 (3072 primary rays; throughput in rays/s), camera fitted to the scene, lit
//!   shading, no AO or shadows; transparent = opacity 0.4 (CSG union of every interval along
//!   each ray). Links: [`Scene::primitives`]; splines: [`Scene::spline_primitives`] (the
//!   certified split of each curved link into quadratic pieces). Rows run on rayon's pool (all cores).
//! * `bvh_build/{links|splines}/{segments}`: [`Bvh::build`] over a bundle of 1k … 100k links
//!   (splines: twice as many primitives); throughput in primitives/s.
//!
//! Scenes (default: reduced, so the bench stays short; `TUBECAST_FRAMES_FULL=1`: the
//! papers' sizes): bundle 125×84 (full 1250×84), furball 1000×78 (full 10000×78), neurons
//! 2³ (full 4³) procedural neurons, helix 2×200.
//!
//! `cargo bench --bench frames --features render` (add `-- frame/helix` to filter).

use criterion::{black_box, criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput};
use std::time::Duration;
use tubecast_render::accel::Bvh;
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Scene};

const W: u32 = 64;
const H: u32 = 48;

fn scenes() -> Vec<(&'static str, Scene)> {
    let full = std::env::var("TUBECAST_FRAMES_FULL").is_ok_and(|v| v == "1");
    let (bundle, furball, n) = if full { (1250, 10_000, 4) } else { (125, 1000, 2) };
    let lines = |name: &str, l: Vec<tubecast_render::io::Polyline>| Scene::from_polylines(&l, 0.2, name).unwrap();
    vec![
        ("bundle", lines("bundle", generate::bundle(bundle, 84, 1))),
        ("furball", lines("furball", generate::furball(furball, 78, 1))),
        ("neurons", Scene::from_swc(&generate::neurons(n, &[generate::base_neuron(1)], 1), "neurons").unwrap()),
        ("helix", lines("helix", generate::helix(200))),
    ]
}

fn frames(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame");
    g.throughput(Throughput::Elements((W * H) as u64));
    for (name, scene) in scenes() {
        for (model, prims) in [("links", scene.primitives()), ("splines", scene.spline_primitives().unwrap())] {
            let st = scene.stats_of(&prims);
            let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, W, H).unwrap();
            let bvh = Bvh::build(prims);
            for (mode, opacity) in [("opaque", 1.0), ("transparent", 0.4)] {
                let opts = Options { opacity, ..Options::default() };
                g.bench_function(BenchmarkId::new(format!("{name}/{model}"), mode), |b| {
                    b.iter(|| black_box(render(&scene, &bvh, &cam, &opts).unwrap()))
                });
            }
        }
    }
    g.finish();
}

fn bvh_build(c: &mut Criterion) {
    let mut g = c.benchmark_group("bvh_build");
    for tubes in [12, 120, 1200] {
        // 84 links per tube: ≈ 1k, 10k, 100k links.
        let scene = Scene::from_polylines(&generate::bundle(tubes, 84, 1), 0.2, "bundle").unwrap();
        for (model, prims) in [("links", scene.primitives()), ("splines", scene.spline_primitives().unwrap())] {
            g.throughput(Throughput::Elements(prims.len() as u64));
            g.bench_function(BenchmarkId::new(model, scene.links.len()), |b| {
                b.iter_batched(|| prims.clone(), |p| black_box(Bvh::build(p)), BatchSize::LargeInput)
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = frames, bvh_build
}
criterion_main!(benches);
