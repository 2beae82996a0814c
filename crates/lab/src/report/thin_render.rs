//! The `thin` report's render section: what the faithful split costs against Russig's pair
//! (`Scene::spline_primitives` against `Scene::pair_spline_primitives`) on `generate helix`:
//! pieces, primitives + BVH bytes ([`Tracer::memory_bytes`] of the CLI's [`WideBvh`]) and
//! the time of one opaque frame, both models in the same run on the same camera.

use super::{fmt_num, ReportError, ReportOptions};
use std::fmt::Write as _;
use std::time::Instant;
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Prim, Scene};

/// Segments per strand of the helix (`generate helix`'s default).
const SEGMENTS: usize = 200;

/// Frame time (best of `reps`, seconds), bytes and piece count for one primitive set.
fn measure(
    pool: &rayon::ThreadPool,
    scene: &Scene,
    prims: Vec<Prim>,
    cam: &Camera,
    reps: usize,
) -> Result<(f64, usize, usize), ReportError> {
    let n = prims.len();
    let bvh = WideBvh::build(prims);
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        pool.install(|| render(scene, &bvh, cam, &Options::default()))
            .map_err(|e| ReportError::Render(e.to_string()))?;
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Ok((best, bvh.memory_bytes(), n))
}

/// The markdown section (a heading, a sentence and a table).
pub fn helix_section(opts: &ReportOptions) -> Result<String, ReportError> {
    let err = |e: String| ReportError::Render(e);
    let scene = Scene::from_polylines(&generate::helix(SEGMENTS), 0.2, "helix").map_err(|e| err(e.to_string()))?;
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 35.0, opts.image, opts.image).map_err(|e| err(e.to_string()))?;
    let reps = if opts.time_ms == 0 { 1 } else { 3 };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads)
        .build()
        .map_err(|e| err(format!("thread pool: {e}")))?;
    let split = scene.spline_primitives().map_err(|e| err(e.to_string()))?;
    let pair = scene.pair_spline_primitives().map_err(|e| err(e.to_string()))?;
    let f = scene.spline_fidelity();
    let (ts, bs, ns) = measure(&pool, &scene, split, &cam, reps)?;
    let (tp, bp, np) = measure(&pool, &scene, pair, &cam, reps)?;
    let mut md = String::new();
    let _ = write!(
        md,
        "\n## Render: faithful split against Russig's pair\n\n`generate helix` ({} links), one opaque \
         {}×{} frame (default options, best of {reps}, {} thread(s)), the CLI's 8-wide BVH, both models in \
         this run. \
         Certified distance to the cubic's sweep: split ≤ {} radii, pair ≤ {} radii.\n\n",
        scene.links.len(),
        opts.image,
        opts.image,
        opts.threads,
        fmt_num(f.faithful_relative),
        fmt_num(f.pair_relative),
    );
    let _ = writeln!(md, "| model | pieces | primitives + BVH (bytes) | frame (s) | frame / pair's |");
    let _ = writeln!(md, "|---|---|---|---|---|");
    let _ = writeln!(md, "| faithful split | {ns} | {bs} | {} | {} |", fmt_num(ts), fmt_num(ts / tp));
    let _ = writeln!(md, "| Russig's pair | {np} | {bp} | {} | 1 |", fmt_num(tp));
    Ok(md)
}
