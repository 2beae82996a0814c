//! The peers report's speed and memory section (feature `embree`): per scene, one run, the same
//! `f32` camera rays for Embree `ROUND_LINEAR_CURVE` (`rtcIntersect1`, isolated segments: the
//! same solid) and our trees (the binary [`Bvh`] with lane packets, and the 8-wide
//! [`WideBvh`] over whole primitives and built compactly from the scene as the CLI does,
//! [`WideBvh::from_scene`]), on one thread and on all threads; build times; bytes per link
//! (ours: [`Tracer::memory_bytes`]; Embree's: its device memory monitor after the build).

use super::peers::best_of;
use super::ReportError;
use crate::peer::embree::{Device, Scene as EScene};
use crate::peer::SceneInputs;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Instant;
use tubecast::{Ray, V3};
use tubecast_render::accel::{Bvh, Tracer, WideBvh};
use tubecast_render::render::Camera;
use tubecast_render::scene::generate::Rng;
use tubecast_render::scene::{Model, Scene};

/// One scene's figures.
pub(super) struct SceneSpeed {
    name: String,
    links: usize,
    /// Build seconds: Embree, Bvh, WideBvh (whole), WideBvh (compact).
    build: [f64; 4],
    /// Mrays/s, one thread: Embree, Bvh, WideBvh (whole), WideBvh (compact).
    one: [f64; 4],
    /// Mrays/s on all threads: Embree, WideBvh (whole), WideBvh (compact).
    all: [f64; 3],
    threads: usize,
    /// Bytes per link: Embree, Bvh, WideBvh (whole), WideBvh (compact).
    bytes: [f64; 4],
    /// Hits: Embree, WideBvh (whole), WideBvh (compact); rays.
    hits: [usize; 3],
    rays: usize,
}

fn count<T: Tracer>(t: &T, rays: &[Ray<f64>]) -> usize {
    rays.iter().filter(|r| t.closest_hit(r).is_some()).count()
}

/// Which rays a row measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Rays {
    /// A fitted camera's `side × side` pixel rays (coherent, from outside the scene).
    Camera,
    /// `side²` rays with origins uniform in the scene's box and directions uniform on the
    /// sphere (incoherent; many start inside a tube or between tubes).
    Random,
}

/// Measure `scene` on `side²` rays of kind `kind`.
pub(super) fn measure(
    dev: &Arc<Device>,
    name: &str,
    scene: &Scene,
    side: u32,
    kind: Rays,
) -> Result<SceneSpeed, ReportError> {
    let perr = |e: crate::peer::embree::EmbreeError| ReportError::Peer(e.to_string());
    let st = scene.stats();
    let cam =
        Camera::fit(st.bounds.0, st.bounds.1, 35.0, side, side).map_err(|e| ReportError::Render(e.to_string()))?;
    let SceneInputs { mut rays32, mut rays64, links32 } = crate::peer::scene_inputs(scene, &cam, side);
    if kind == Rays::Random {
        let (lo, hi) = st.bounds;
        let mut rng = Rng::new(0x5eed);
        rays32 = rays32
            .iter()
            .map(|_| {
                let o: [f64; 3] = std::array::from_fn(|i| lo[i] + (hi[i] - lo[i]) * rng.uniform());
                (o.map(|x| x as f32), rng.unit().map(|x| x as f32))
            })
            .collect();
        rays64 = rays32.iter().map(|(o, d)| Ray::new(V3::from(*o).cast(), V3::from(*d).cast())).collect();
    }
    let name = format!("{name}, {} rays", if kind == Rays::Camera { "camera" } else { "random" });
    let m0 = dev.memory_bytes();
    let t0 = Instant::now();
    let emb = EScene::round_linear(dev, &links32).map_err(perr)?;
    let b_emb = t0.elapsed().as_secs_f64();
    let emb_bytes = (dev.memory_bytes() - m0).max(0) as f64;
    let t0 = Instant::now();
    let bvh = Bvh::build(scene.primitives());
    let b_bvh = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let wide = WideBvh::build(scene.primitives());
    let b_wide = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let compact = WideBvh::from_scene(scene, Model::Links).map_err(|e| ReportError::Render(e.to_string()))?;
    let b_compact = t0.elapsed().as_secs_f64();
    let reps = 3;
    let (t_emb, h_emb) = best_of(reps, || emb.count_hits(&rays32));
    let (t_bvh, _) = best_of(reps, || count(&bvh, &rays64));
    let (t_wide, h_wide) = best_of(reps, || count(&wide, &rays64));
    let (t_compact, h_compact) = best_of(reps, || count(&compact, &rays64));
    let chunk = 256;
    let (a_emb, _) = best_of(reps, || rays32.par_chunks(chunk).map(|c| emb.count_hits(c)).sum());
    let (a_wide, _) = best_of(reps, || rays64.par_chunks(chunk).map(|c| count(&wide, c)).sum());
    let (a_compact, _) = best_of(reps, || rays64.par_chunks(chunk).map(|c| count(&compact, c)).sum());
    let nr = rays32.len() as f64;
    let mr = |t: f64| nr / t / 1e6;
    let nl = scene.links.len() as f64;
    Ok(SceneSpeed {
        name,
        links: scene.links.len(),
        build: [b_emb, b_bvh, b_wide, b_compact],
        one: [mr(t_emb), mr(t_bvh), mr(t_wide), mr(t_compact)],
        all: [mr(a_emb), mr(a_wide), mr(a_compact)],
        threads: rayon::current_num_threads(),
        bytes: [emb_bytes / nl, bvh.memory_bytes() as f64 / nl, wide.memory_bytes() as f64 / nl, {
            compact.memory_bytes() as f64 / nl
        }],
        hits: [h_emb, h_wide, h_compact],
        rays: rays32.len(),
    })
}

/// The markdown table of `rows` and the ratios it implies ("whole": [`WideBvh::build`] over
/// whole primitives, the layout before clusters; "compact": [`WideBvh::from_scene`], the CLI's).
pub(super) fn table(rows: &[SceneSpeed]) -> String {
    let mut md = String::from(
        "| scene | links | rays (hits Embree / whole / compact) | Mrays/s 1 thread: Embree / Bvh / WideBvh whole / \
         compact | ÷ Embree: whole / compact | Mrays/s all threads: Embree / whole / compact | ÷ Embree: whole / \
         compact | build ms: Embree / Bvh / whole / compact | build compact ÷ Embree | bytes per link: Embree / \
         Bvh / whole / compact |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let f = |v: &[f64], p: usize| v.iter().map(|x| format!("{x:.p$}")).collect::<Vec<_>>().join(" / ");
        let _ = writeln!(
            md,
            "| {} | {} | {} ({} / {} / {}) | {} | {:.2} / {:.2} | {} ({} threads) | {:.2} / {:.2} | {} | {:.2} | {} |",
            r.name,
            r.links,
            r.rays,
            r.hits[0],
            r.hits[1],
            r.hits[2],
            f(&r.one, 2),
            r.one[2] / r.one[0],
            r.one[3] / r.one[0],
            f(&r.all, 2),
            r.threads,
            r.all[1] / r.all[0],
            r.all[2] / r.all[0],
            f(&r.build.map(|b| b * 1e3), 1),
            r.build[3] / r.build[0],
            f(&r.bytes, 1),
        );
    }
    md
}
