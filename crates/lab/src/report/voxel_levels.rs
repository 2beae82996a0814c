//! Grid ablations for the voxel report, measured in the same run on the same scenes: the walk
//! with all coarse skip levels against the single level of 4³ blocks (and a plain DDA), and
//! the one-pass build (voxelize once, sort the pairs) against the two-pass one (voxelize
//! twice).

use super::voxel_clock::Clock;
use super::{fmt_num, ReportError, ReportOptions};
use std::fmt::Write as _;
use tubecast_render::accel::grid::{Grid, GridParams};
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Scene};

/// Repetitions per measurement (alternating the variants; the best is kept).
const REPS: usize = 3;

/// Process CPU seconds of `f` (`voxel_clock`).
fn seconds(f: impl FnOnce()) -> f64 {
    let t0 = Clock::now();
    f();
    Clock::now().since(t0)
}

/// One scene's row: skip levels, render ms for 0 / 1 / all levels, build ms two- / one-pass.
fn row(scene: &Scene, image: u32, pool: &rayon::ThreadPool) -> Result<(usize, [f64; 3], [f64; 2]), ReportError> {
    let prims = scene.primitives();
    let st = scene.stats_of(&prims);
    let cam =
        Camera::fit(st.bounds.0, st.bounds.1, 40.0, image, image).map_err(|e| ReportError::Render(e.to_string()))?;
    let params = |skip_levels, one_pass| GridParams { skip_levels, one_pass, ..GridParams::default() };
    let mut build = [f64::INFINITY; 2];
    for _ in 0..REPS {
        for (k, one_pass) in [false, true].into_iter().enumerate() {
            let p = prims.clone();
            build[k] =
                build[k].min(seconds(|| drop(pool.install(|| Grid::build_with(p, &params(u32::MAX, one_pass))))));
        }
    }
    let grids = [0, 1, u32::MAX].map(|s| pool.install(|| Grid::build_with(prims.clone(), &params(s, true))));
    let mut walk = [f64::INFINITY; 3];
    for _ in 0..REPS {
        for (k, g) in grids.iter().enumerate() {
            let mut res = Ok(());
            let t = seconds(|| res = pool.install(|| render(scene, g, &cam, &Options::default())).map(drop));
            res.map_err(|e| ReportError::Render(e.to_string()))?;
            walk[k] = walk[k].min(t);
        }
    }
    Ok((grids[2].skip_levels(), walk.map(|s| s * 1e3), build.map(|s| s * 1e3)))
}

/// The ablation section (markdown): the bundle, the (hollow) Furball and two bundles far
/// apart at each size.
pub(super) fn ablation(sizes: &[usize], opts: &ReportOptions, pool: &rayon::ThreadPool) -> Result<String, ReportError> {
    let mut md = format!(
        "\n## Grid ablations (same run)\n\nOpaque {0}×{0} frames (primary rays, lit) through grids built from the same \
         primitives at the default resolution (the cost model, next section), {1} thread(s), process CPU time, best of {REPS}: the walk with every coarse skip level (each 4³ cells of the \
         one below, up to ≤ 4 cells per axis) against the single level of 4³ blocks and against a plain DDA \
         (answers are bit-identical: `crates/render/tests/accel/grid_levels.rs`); and the build voxelizing each link once \
         (pairs sorted by voxel) against voxelizing it twice (count, then fill). Ratios below 1 favour the new \
         variant. *Two bundles apart*: half the links each, 300 units apart along y and z (mostly empty \
         space).\n\n\
         | scene | links | skip levels | plain DDA (ms) | 1 level (ms) | all levels (ms) | all / 1 level | \
         two-pass build (ms) | one-pass build (ms) | one / two-pass |\n|---|---|---|---|---|---|---|---|---|---|\n",
        opts.image, opts.threads
    );
    for &links in sizes {
        let err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
        let bundle =
            Scene::from_polylines(&generate::bundle(links.div_ceil(84), 84, opts.seed), 0.12, "b").map_err(err)?;
        let fur =
            Scene::from_polylines(&generate::furball(links.div_ceil(20), 20, opts.seed), 0.06, "f").map_err(err)?;
        // Two half-size bundles 300 units apart along y and z: mostly empty space.
        let mut two = generate::bundle(links.div_ceil(168), 84, opts.seed);
        let far = generate::bundle(links.div_ceil(168), 84, opts.seed + 1);
        two.extend(far.into_iter().map(|p| Polyline {
            points: p.points.iter().map(|q| [q[0], q[1] + 300.0, q[2] + 300.0]).collect(),
            radii: p.radii,
        }));
        let apart = Scene::from_polylines(&two, 0.12, "a").map_err(err)?;
        for (name, scene) in [("bundle", &bundle), ("furball", &fur), ("two bundles apart", &apart)] {
            let (levels, w, b) = row(scene, opts.image, pool)?;
            let _ = writeln!(
                md,
                "| {name} | {} | {levels} | {} | {} | {} | {:.2} | {} | {} | {:.2} |",
                scene.links.len(),
                fmt_num(w[0]),
                fmt_num(w[1]),
                fmt_num(w[2]),
                w[2] / w[1],
                fmt_num(b[0]),
                fmt_num(b[1]),
                b[1] / b[0]
            );
        }
    }
    Ok(md)
}
