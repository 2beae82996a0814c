//! Speed of the GPU walk against the CPU's wide BVH (all cores, rayon) on the same primary rays
//! of a 640×480 frame of Russig's bundle, for growing scene sizes, one row per query: `hit`
//! (closest hits) and `all` (every union boundary: `crossings_table_gpu` against
//! `crossings_table`); with the hits or crossings each side found (they agree up to the
//! band of `tests/gpu`), the upload's size per link and the GPU's time per frame.
//! `TUBECAST_GPU_BENCH_LINKS` (comma-separated link counts) overrides the default sizes; a
//! software adapter (lavapipe) is labelled as such, its figures say nothing of a real GPU.

use rayon::prelude::*;
use std::time::Instant;
use tubecast::Ray;
use tubecast_gpu::{Gpu, GpuScene, Walk};
use tubecast_render::accel::{crossings_table, Tracer, WideBvh};
use tubecast_render::render::Camera;
use tubecast_render::scene::{generate, Model, Scene};

/// Largest scene with an `all` row. Its table grows with the crossings per ray (0.43 at 10⁴
/// links of this bundle, 3.5 at 10⁵: about eight times per decade), 64 bytes a row on each side
/// plus the GPU's interval lists: about 0.5 GB at 10⁶ links, 35 GB at 10⁸.
const ALL_MAX_LINKS: usize = 1_000_000;

/// The best of `n` runs of `f`, seconds.
fn best(n: usize, mut f: impl FnMut()) -> f64 {
    (0..n)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("gpu bench: skipped, {e}");
            return;
        }
    };
    let sizes: Vec<usize> = std::env::var("TUBECAST_GPU_BENCH_LINKS")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![10_000, 100_000]);
    let label = if gpu.is_software() { " (software adapter: not a GPU figure)" } else { "" };
    println!("adapter: {}{label}", gpu.describe());
    println!(
        "| links | query | upload MB | bytes/link | upload ms | GPU Mrays/s | GPU ms/frame | CPU Mrays/s ({} threads) \
         | GPU ÷ CPU | hits or crossings GPU / CPU |",
        rayon::current_num_threads()
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for links in sizes {
        // Fibres of 100 links each.
        let tubes = (links / 100).max(1);
        let scene = Scene::from_polylines(&generate::bundle(tubes, 100, 1), 0.12, "bundle").expect("bundle");
        let bvh = WideBvh::from_scene(&scene, Model::Links).expect("tree");
        let t = Instant::now();
        let gs = match GpuScene::upload(&gpu, &bvh) {
            Ok(g) => g,
            Err(e) => {
                println!("| {links} | | {e} |");
                continue;
            }
        };
        let upload = t.elapsed().as_secs_f64();
        let st = scene.stats();
        let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 640, 480).expect("camera");
        let rays: Vec<Ray<f64>> = (0..cam.height).flat_map(|y| (0..cam.width).map(move |x| cam.ray(x, y))).collect();
        let n = rays.len() as f64;
        let (mut found_g, mut found_c) = (0, 0);
        let hit = (
            best(3, || {
                let h = gs.closest_hits(&rays, Walk::Tree).expect("dispatch");
                found_g = h.iter().flatten().count();
            }),
            best(3, || {
                let h: Vec<_> = rays.par_iter().map(|r| bvh.closest_hit(r)).collect();
                found_c = h.iter().flatten().count();
            }),
            (found_g, found_c),
        );
        let mut rows = vec![("hit", hit)];
        if scene.links.len() <= ALL_MAX_LINKS {
            let all = (
                best(3, || found_g = tubecast_gpu::crossings_table_gpu(&gs, &bvh, &rays).expect("dispatch").len()),
                best(3, || found_c = crossings_table(&bvh, &rays).len()),
                (found_g, found_c),
            );
            rows.push(("all", all));
        }
        let mb = gs.bytes() as f64 / 1e6;
        let per = gs.bytes() as f64 / scene.links.len() as f64;
        for (query, (g, c, (fg, fc))) in rows {
            println!(
                "| {} | {query} | {mb:.1} | {per:.0} | {:.0} | {:.3} | {:.1} | {:.2} | {:.3} | {fg} / {fc} |",
                scene.links.len(),
                upload * 1e3,
                n / g / 1e6,
                g * 1e3,
                n / c / 1e6,
                c / g,
            );
        }
    }
}
