//! Closest-hit rays per second of the compact wide tree on generated scenes and a real
//! tractogram, one thread, best of five: for comparing two builds of the tracer on the same
//! rays (the hit count and the sum of `t` must agree between them).
//!
//! `cargo run --release -p tubecast-render --example trace_speed [SIDE]`

use std::time::Instant;
use tubecast::{Ray, V3};
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::scene::{generate, Model, Scene};

/// `side²` pinhole rays from outside the scene box, through a square that covers its middle.
fn camera_rays(scene: &Scene, side: usize) -> Vec<Ray<f64>> {
    let (lo, hi) = scene.stats().bounds;
    let c = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    let diag = (V3::from(hi) - V3::from(lo)).length();
    let view = V3::new(0.3, -0.2, 1.0).normalize_or_zero();
    let right = view.cross(V3::new(0.0, 1.0, 0.0)).normalize_or_zero();
    let up = right.cross(view);
    let eye = c - view * (1.5 * diag);
    (0..side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f64 / side as f64 - 0.5, (i / side) as f64 / side as f64 - 0.5);
            let target = c + right * (0.8 * diag * x) + up * (0.8 * diag * y);
            Ray::new(eye, target - eye)
        })
        .collect()
}

fn run(name: &str, scene: &Scene, side: usize) {
    let t0 = Instant::now();
    let tree = WideBvh::from_scene(scene, Model::Links).expect("builds");
    let build = t0.elapsed().as_secs_f64();
    let rays = camera_rays(scene, side);
    let mut best = f64::INFINITY;
    let (mut hits, mut sum) = (0, 0.0);
    for _ in 0..5 {
        let t = Instant::now();
        hits = 0;
        sum = 0.0;
        for r in &rays {
            if let Some(h) = tree.closest_hit(r) {
                hits += 1;
                sum += h.t;
            }
        }
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "{name}: {} links, build {:.0} ms, {:.3} Mrays/s, {hits} hits, sum t {sum:.9e}, {} bytes",
        scene.links.len(),
        build * 1e3,
        rays.len() as f64 / best * 1e-6,
        tree.memory_bytes()
    );
}

fn main() {
    let side = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(256);
    let fur = Scene::from_polylines(&generate::furball(1283, 78, 1), 0.05, "furball").unwrap();
    run("Furball 1e5", &fur, side);
    let bun = Scene::from_polylines(&generate::bundle(1191, 84, 1), 0.12, "bundle").unwrap();
    run("Bundle 1e5", &bun, side);
    let trk = concat!(env!("CARGO_MANIFEST_DIR"), "/../../reference/readers/nibabel/standard.trk");
    if let Ok(s) = Scene::load(std::path::Path::new(trk), 0.5) {
        run("standard.trk", &s, side);
    }
}
