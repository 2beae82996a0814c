//! The GPU report (features `gpu` and `embree`): closest hits per second of the GPU walk
//! (`tubecast-gpu`, the CLI's `--device gpu`) against the CPU's wide BVH (the CLI's
//! `--device cpu`, all threads) and Embree 3's `ROUND_LINEAR_CURVE` (one thread and all
//! threads), on the same camera rays of the same scenes, with what the GPU path costs per link:
//! upload bytes and upload time.
//!
//! Every side gets the same `f32` rays (the GPU and the CPU read them widened to `f64`, as the
//! CLI does). Tracing only: scene loading and building are not in Mrays/s. The GPU's time is a
//! whole frame as a caller sees it: rays uploaded, the walk dispatched, hits read back.
//! A software adapter (Mesa's lavapipe runs the shaders on the CPU's cores) is named in the
//! report and its figures say nothing of a real GPU.
//!
//! Sizes: 10⁵ links, 10⁶ with `--big`; `TUBECAST_GPU_BENCH_LINKS` (comma-separated link counts,
//! as `crates/gpu/bench.sh` takes) replaces them, e.g. 10⁷ and 10⁸ on a machine with the memory.

use super::peers::best_of;
use super::{ensure_dir, machine, ReportError, ReportFiles, ReportOptions};
use crate::peer::embree::{Device, Scene as EScene};
use crate::peer::SceneInputs;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast_gpu::{Gpu, GpuScene, Walk};
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::render::Camera;
use tubecast_render::scene::{generate, Model, Scene};

/// Camera rays per frame: `SIDE × SIDE` (a GPU needs many rays in flight to be measured at all).
const SIDE: u32 = 512;

/// Repetitions per measurement (the best is kept).
const REPS: usize = 3;

/// One scene's figures.
struct Row {
    name: String,
    links: usize,
    rays: usize,
    /// Hits: Embree, CPU.
    hits: [usize; 2],
    /// Mrays/s: Embree one thread, Embree all threads, CPU all threads.
    mrays: [f64; 3],
    /// The GPU's hits, Mrays/s, upload (bytes, seconds) and seconds per frame, or why it could
    /// not run the scene (over the adapter's buffer limits).
    gpu: Result<(usize, f64, (u64, f64), f64), String>,
}

fn sizes(opts: &ReportOptions) -> Result<Vec<usize>, ReportError> {
    if let Ok(s) = std::env::var("TUBECAST_GPU_BENCH_LINKS") {
        return s
            .split(',')
            .map(|x| {
                x.trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n > 0)
                    .ok_or_else(|| ReportError::Options(format!("TUBECAST_GPU_BENCH_LINKS: {x:?} is not a link count")))
            })
            .collect();
    }
    let mut v = vec![opts.max_segments.min(100_000)];
    if opts.max_segments >= 1_000_000 {
        v.push(1_000_000);
    }
    Ok(v)
}

fn measure(gpu: &Gpu, dev: &std::sync::Arc<Device>, name: &str, scene: &Scene) -> Result<Row, ReportError> {
    let rerr = |e: String| ReportError::Render(e);
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 35.0, SIDE, SIDE).map_err(|e| rerr(e.to_string()))?;
    let SceneInputs { rays32, rays64, links32 } = crate::peer::scene_inputs(scene, &cam, SIDE);
    let emb = EScene::round_linear(dev, &links32).map_err(|e| ReportError::Peer(e.to_string()))?;
    drop(links32);
    let bvh = WideBvh::from_scene(scene, Model::Links).map_err(|e| rerr(e.to_string()))?;
    let n = rays64.len() as f64;
    let mr = |t: f64| n / t / 1e6;
    // The GPU side; a scene over the adapter's buffer limits is a row that says so.
    let gpu_side = || -> Result<(usize, f64, (u64, f64), f64), String> {
        let t = Instant::now();
        let gs = GpuScene::upload(gpu, &bvh).map_err(|e| e.to_string())?;
        let upload = t.elapsed().as_secs_f64();
        // One frame first: the pipelines are compiled on first use, which is not a frame's cost.
        gs.closest_hits(&rays64, Walk::Tree).map_err(|e| e.to_string())?;
        let mut err = None;
        let (t_gpu, h_gpu) = best_of(REPS, || match gs.closest_hits(&rays64, Walk::Tree) {
            Ok(h) => h.iter().flatten().count(),
            Err(e) => {
                err = Some(e.to_string());
                0
            }
        });
        match err {
            Some(e) => Err(e),
            None => Ok((h_gpu, mr(t_gpu), (gs.bytes(), upload), t_gpu)),
        }
    };
    let gpu = gpu_side();
    let chunk = 256;
    let (t_e1, h_emb) = best_of(REPS, || emb.count_hits(&rays32));
    let (t_ea, _) = best_of(REPS, || rays32.par_chunks(chunk).map(|c| emb.count_hits(c)).sum());
    let (t_cpu, h_cpu) = best_of(REPS, || {
        rays64.par_chunks(chunk).map(|c| c.iter().filter(|r| bvh.closest_hit(r).is_some()).count()).sum()
    });
    Ok(Row {
        name: name.into(),
        links: scene.links.len(),
        rays: rays64.len(),
        hits: [h_emb, h_cpu],
        mrays: [mr(t_e1), mr(t_ea), mr(t_cpu)],
        gpu,
    })
}

fn table(rows: &[Row], threads: usize) -> String {
    let mut md = format!(
        "| scene | links | rays | hits Embree / CPU / GPU | Mrays/s Embree 1 thread | Mrays/s Embree {threads} threads \
         | Mrays/s CPU {threads} threads | Mrays/s GPU | GPU ÷ Embree ({threads} threads) | GPU ÷ CPU \
         | upload bytes per link | upload ms (ns per link) | GPU ms per frame |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        let (g, ratios, up, frame) = match &r.gpu {
            Ok((h, m, (bytes, secs), frame)) => (
                format!("{h}"),
                format!("{m:.3} | {:.3} | {:.3}", m / r.mrays[1], m / r.mrays[2]),
                format!(
                    "{:.1} | {:.1} ({:.0})",
                    *bytes as f64 / r.links as f64,
                    secs * 1e3,
                    secs * 1e9 / r.links as f64
                ),
                format!("{:.1}", frame * 1e3),
            ),
            Err(e) => ("—".into(), format!("{e} | — | —"), "— | —".into(), "—".into()),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} / {} / {g} | {:.2} | {:.2} | {:.2} | {ratios} | {up} | {frame} |",
            r.name, r.links, r.rays, r.hits[0], r.hits[1], r.mrays[0], r.mrays[1], r.mrays[2],
        );
    }
    md
}

/// Writes `gpu.md` into `out`: the GPU walk against the CPU path and Embree (see the module's
/// documentation). Errors: no adapter, Embree's, or a scene over the adapter's limits.
pub fn run_gpu(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    ensure_dir(out)?;
    let gpu = Gpu::new().map_err(|e| ReportError::Peer(format!("gpu: {e}")))?;
    let dev = Device::new().map_err(|e| ReportError::Peer(e.to_string()))?;
    let render_err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
    // The machine's load when the run starts: a software adapter and the CPU side share its cores.
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into());
    let mut rows = Vec::new();
    for m in sizes(opts)? {
        // The scenes of the peers report: a dense tractography-like bundle and a furball.
        let bun = generate::bundle(m.div_ceil(84), 84, opts.seed);
        let scene = Scene::from_polylines(&bun, 0.12, "bundle").map_err(render_err)?;
        rows.push(measure(&gpu, &dev, "Bundle", &scene)?);
        drop(scene);
        let fur = generate::furball(m.div_ceil(78), 78, opts.seed);
        let scene = Scene::from_polylines(&fur, 0.05, "furball").map_err(render_err)?;
        rows.push(measure(&gpu, &dev, "Furball", &scene)?);
    }
    let trk = concat!(env!("CARGO_MANIFEST_DIR"), "/../../reference/readers/nibabel/standard.trk");
    let scene = Scene::load(Path::new(trk), 0.5).map_err(render_err)?;
    rows.push(measure(&gpu, &dev, "standard.trk", &scene)?);

    let software = if gpu.is_software() {
        " **A software adapter: its shaders run on this machine's CPU cores, so the GPU column measures \
         the CPU emulating a GPU and says nothing of a real GPU.**"
    } else {
        ""
    };
    let (env, big) = match std::env::var("TUBECAST_GPU_BENCH_LINKS") {
        Ok(v) => (format!("TUBECAST_GPU_BENCH_LINKS={v} "), ""),
        Err(_) => (String::new(), if opts.max_segments >= 1_000_000 { " --big" } else { "" }),
    };
    let threads = rayon::current_num_threads();
    let mut md = format!(
        "# The GPU path against the CPU and Embree\n\n\
         Generated by `{env}cargo run --release -p tubecast-lab --features embree,gpu -- gpu{big}` (seed {}; \
         `crates/gpu/bench.sh` runs it with the GPU bench). Machine: {}, load average {load} at the start. Adapter: {}.{software}\n\n",
        opts.seed,
        machine(),
        gpu.describe(),
    );
    md.push_str(&format!(
        "One run; the same {SIDE}×{SIDE} `f32` camera rays on every side, closest hits. Embree: \
         `ROUND_LINEAR_CURVE` isolated segments (quality high, robust), `rtcIntersect1`, one thread and \
         {threads} threads (rays in chunks of 256 over rayon's pool). CPU: the CLI's `--device cpu` tree \
         (`WideBvh::from_scene`), {threads} threads. GPU: the CLI's `--device gpu` walk of the same tree \
         (`GpuScene::closest_hits`), a whole frame as a caller sees it: rays up, walk, hits back (best of \
         {REPS}, after one frame that compiles the pipelines). Upload: nodes and primitives, timed from the \
         built tree to a scene ready to trace, so it includes compiling the closest- and any-hit \
         pipelines, a fixed cost that dominates small scenes (the bytes are the buffers'). Ratios above 1 favour the GPU. The hit counts are each side's \
         own; the GPU's answers are compared with the CPU's ray by ray, within the `f32` kernel's \
         band, by `crates/gpu/tests/gpu`.\n\n"
    ));
    md.push_str(&table(&rows, threads));
    let mdp = out.join("gpu.md");
    std::fs::write(&mdp, md).map_err(|e| ReportError::Io(format!("{}: {e}", mdp.display())))?;
    Ok(ReportFiles { markdown: mdp, charts: vec![] })
}
