//! The grid-resolution section of the voxel report: the resolution the cost model chooses
//! (`GridParams::cells_per_prim: None`, module docs of `tubecast_render::accel::grid`) against
//! a sweep of fixed cells-per-link `λ`, in process CPU time, on the bundle and the Furball.

use super::voxel_clock::Clock;
use super::{fmt_num, ReportError, ReportOptions};
use std::fmt::Write as _;
use tubecast_render::accel::grid::{Grid, GridParams};
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Scene};

/// The fixed `λ` of the sweep.
const LAMBDAS: [f64; 8] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];

/// Build and render CPU seconds and cells per link of one resolution (best of `reps`).
fn measure(
    scene: &Scene,
    cam: &Camera,
    cells_per_prim: Option<f64>,
    reps: usize,
    pool: &rayon::ThreadPool,
) -> Result<[f64; 3], ReportError> {
    let prims = scene.primitives();
    let params = GridParams { cells_per_prim, ..GridParams::default() };
    let (mut build, mut trace, mut lambda) = (f64::INFINITY, f64::INFINITY, 0.0);
    for _ in 0..reps {
        let p = prims.clone();
        let t0 = Clock::now();
        let grid = pool.install(|| Grid::build_with(p, &params));
        let t1 = Clock::now();
        pool.install(|| render(scene, &grid, cam, &Options::default()))
            .map_err(|e| ReportError::Render(e.to_string()))?;
        trace = trace.min(Clock::now().since(t1));
        build = build.min(t1.since(t0));
        lambda = grid.dims().iter().map(|&d| d as f64).product::<f64>() / prims.len().max(1) as f64;
    }
    Ok([build, trace, lambda])
}

/// The section (markdown) at each of `sizes` links, on `pool`.
pub(super) fn section(sizes: &[usize], opts: &ReportOptions, pool: &rayon::ThreadPool) -> Result<String, ReportError> {
    let mut md = format!(
        "\n## Grid resolution: the cost model against fixed λ (same run)\n\nThe default grid picks its voxel side \
         by minimising a per-ray cost model (DDA steps against primitive tests; its inputs are the link count, \
         total length, total radius and the box volume; the rule and its derivation are in the module docs of \
         `tubecast_render::accel::grid`, ρ = `STEP_COST`). Each row sweeps fixed cells per link λ ∈ {{{lams}}} \
         (`GridParams::cells_per_prim`) on the same scene; opaque {img}×{img} frames (primary rays, lit), {threads} \
         thread(s), process CPU time, best of 2 (one at 10⁶ links). *Render*: the trace alone; *frame*: build + \
         render, the dynamic-scene cost. Ratios: the model's time over the best fixed λ's (1 = as good as the \
         best of the sweep; below 1 better than all of them).\n\n\
         | resolution: scene | links | model λ (cells / link) | model build (ms) | model render (ms) | best fixed λ: render | \
         best render (ms) | model / best render | best fixed λ: frame | best frame (ms) | model / best frame | \
         λ = 2 frame / best frame |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        lams = LAMBDAS.map(|l| l.to_string()).join(", "),
        img = opts.image,
        threads = opts.threads,
    );
    for &links in sizes {
        let reps = if links >= 1_000_000 { 1 } else { 2 };
        let err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
        let bundle =
            Scene::from_polylines(&generate::bundle(links.div_ceil(84), 84, opts.seed), 0.12, "b").map_err(err)?;
        let fur =
            Scene::from_polylines(&generate::furball(links.div_ceil(20), 20, opts.seed), 0.06, "f").map_err(err)?;
        for (name, scene) in [("bundle", &bundle), ("furball", &fur)] {
            let st = scene.stats();
            let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, opts.image, opts.image)
                .map_err(|e| ReportError::Render(e.to_string()))?;
            let auto = measure(scene, &cam, None, reps, pool)?;
            let fixed: Vec<(f64, [f64; 3])> = LAMBDAS
                .iter()
                .map(|&l| measure(scene, &cam, Some(l), reps, pool).map(|m| (l, m)))
                .collect::<Result<_, _>>()?;
            let best = |key: &dyn Fn(&[f64; 3]) -> f64| {
                fixed
                    .iter()
                    .min_by(|a, b| key(&a.1).total_cmp(&key(&b.1)))
                    .map(|(l, m)| (*l, key(m)))
                    .unwrap_or((0.0, 1.0))
            };
            let (lr, br) = best(&|m| m[1]);
            let (lf, bf) = best(&|m| m[0] + m[1]);
            let two = fixed.iter().find(|(l, _)| *l == 2.0).map_or(f64::NAN, |(_, m)| m[0] + m[1]);
            let _ = writeln!(
                md,
                "| {name} | {} | {:.2} | {} | {} | {lr} | {} | {:.2} | {lf} | {} | {:.2} | {:.2} |",
                scene.links.len(),
                auto[2],
                fmt_num(auto[0] * 1e3),
                fmt_num(auto[1] * 1e3),
                fmt_num(br * 1e3),
                auto[1] / br,
                fmt_num(bf * 1e3),
                (auto[0] + auto[1]) / bf,
                two / bf
            );
        }
    }
    Ok(md)
}
