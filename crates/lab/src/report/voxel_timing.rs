//! Voxelization timings by repeated median (not criterion): the three round-cone voxelizations
//! (`tubecast::voxel` and the baselines of `tubecast::baseline::voxel`) against link length
//! and orientation, and the occupancy pyramid's build on one thread against all threads. Each
//! figure is the median of `REPS` timed repetitions, with the interquartile range beside it so
//! a loaded machine shows as spread, not as a number.

use super::voxel_clock::Clock;
use super::{ensure_dir, fmt_num, machine, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast::baseline;
use tubecast::voxel::{self, Dims};
use tubecast::{RoundCone, V3};
use tubecast_render::accel::grid::Pyramid;
use tubecast_render::scene::{generate, Scene};

/// Timed repetitions per figure.
const REPS: usize = 15;
const DIMS: Dims = [256, 256, 256];

/// Median and quartiles of `REPS` timed repetitions of `f(k)` — `k` calls of the measured work,
/// `k` chosen so that one repetition takes at least 20 ms — in seconds per call, in CPU time
/// (`cpu`) or wall time. The work must run on a rayon pool's worker: a sleeping thread's CPU
/// time is exact, a running one's (the caller's) is only updated at scheduler ticks.
fn quartiles(cpu: bool, mut f: impl FnMut(usize)) -> [f64; 3] {
    let t0 = Instant::now();
    f(1); // warm-up and calibration
    let k = (20e-3 / t0.elapsed().as_secs_f64().max(1e-9)).ceil().clamp(1.0, 1e6) as usize;
    let mut t: Vec<f64> = (0..REPS)
        .map(|_| {
            let (c0, w0) = (Clock::now(), Instant::now());
            f(k);
            let s = if cpu { Clock::now().since(c0) } else { w0.elapsed().as_secs_f64() };
            s / k as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    [t[REPS / 4], t[REPS / 2], t[3 * REPS / 4]]
}

// `links(dir, len)`: the cases of `benches/voxel.rs`.
include!("../../../../benches/common/voxel_cases.rs");

fn voxelize_table(md: &mut String) -> Result<(), ReportError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| ReportError::Render(format!("thread pool: {e}")))?;
    let methods: [(&str, Method); 3] = [
        ("Alg. 1", |l, d, f| voxel::voxelize_round_cone(l, d, f)),
        ("AABB", |l, d, f| baseline::voxel::voxelize_aabb(l, d, f)),
        ("DDA", |l, d, f| baseline::voxel::voxelize_dda(l, d, f)),
    ];
    md.push_str(
        "| orientation | length (voxels) | method | voxels per link | ns per link: median | q1 – q3 |\n\
         |---|---|---|---|---|---|\n",
    );
    for (dname, dir) in [("axis", [1.0, 0.0, 0.0]), ("face diagonal", [1.0, 1.0, 0.0]), ("space diagonal", [1.0; 3])] {
        for len in [1.0, 4.0, 16.0, 64.0] {
            let ls = links(dir, len);
            for (mname, m) in methods {
                let count = visited(m, &ls);
                let q = quartiles(true, |k| {
                    pool.install(|| (0..k).for_each(|_| _ = std::hint::black_box(sweep(m, &ls))));
                })
                .map(|s| s * 1e9 / ls.len() as f64);
                let _ = writeln!(
                    md,
                    "| {dname} | {len} | {mname} | {:.1} | {} | {} – {} |",
                    count as f64 / ls.len() as f64,
                    fmt_num(q[1]),
                    fmt_num(q[0]),
                    fmt_num(q[2])
                );
            }
        }
    }
    Ok(())
}

fn pyramid_table(md: &mut String, opts: &ReportOptions) -> Result<(), ReportError> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let _ = write!(
        md,
        "\n## Occupancy pyramid build: one thread against {threads}\n\n| links | base cells | CPU ms, 1 thread: \
         median (q1 – q3) | CPU ms, {threads} threads | wall ms, 1 thread | wall ms, {threads} threads | wall {threads} \
         ÷ 1 |\n|---|---|---|---|---|---|---|\n"
    );
    for links in [10_000usize, 100_000].into_iter().filter(|&n| n <= opts.max_segments.max(10_000)) {
        let scene = Scene::from_polylines(&generate::bundle(links.div_ceil(84), 84, opts.seed), 0.12, "bundle")
            .map_err(|e| ReportError::Render(e.to_string()))?;
        let (lo, hi) = scene.stats().bounds;
        let h = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max) / 128.0;
        let lo = lo.map(|x| x - 2.0 * h);
        let dims: [u32; 3] = std::array::from_fn(|i| ((hi[i] - lo[i]) / h).ceil() as u32 + 2);
        let on = |n: usize, cpu: bool| -> Result<[f64; 3], ReportError> {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| ReportError::Render(format!("thread pool: {e}")))?;
            Ok(quartiles(cpu, |k| {
                for _ in 0..k {
                    std::hint::black_box(pool.install(|| Pyramid::build(&scene, lo, h, dims, 0.5 * h)));
                }
            })
            .map(|s| s * 1e3))
        };
        let q = |v: [f64; 3]| format!("{} ({} – {})", fmt_num(v[1]), fmt_num(v[0]), fmt_num(v[2]));
        let (c1, cn, w1, wn) = (on(1, true)?, on(threads, true)?, on(1, false)?, on(threads, false)?);
        let cells = dims.iter().map(|&d| d as u64).product::<u64>();
        let _ = writeln!(
            md,
            "| {} | {cells} | {} | {} | {} | {} | {:.2} |",
            scene.links.len(),
            q(c1),
            q(cn),
            q(w1),
            q(wn),
            wn[1] / w1[1]
        );
    }
    Ok(())
}

/// Writes `voxel_timing.md` into `out`.
pub fn run_voxel_timing(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let mut md = format!(
        "# Voxelization timings (repeated median)\n\nGenerated by `cargo run --release -p tubecast-lab -- \
         voxel-timing` (plain release build, no RUSTFLAGS).\nMachine: {}; {} logical CPUs available.\n\n\
         Measure: each figure is the median of {REPS} timed repetitions after one warm-up (each repetition \
         long enough to take ≥ 20 ms, run on a one-thread rayon pool), with the first and third quartiles (q1 – q3) beside it, in process CPU time \
         (`/proc/self/task/*/schedstat`) unless marked wall; this replaces the criterion numbers of `cargo bench --bench voxel` \
         (same cases), whose spread was too large on this shared machine. Links: 64 per case, radius 0.5 voxel, \
         sub-voxel offsets, on a 256³ grid; time per link, one thread.\n\n",
        machine(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    voxelize_table(&mut md)?;
    pyramid_table(&mut md, opts)?;
    let _ = write!(
        md,
        "\nPyramid: Russig's *Bundle* (seed {}), 128 cells along its longest side; the base level's contributions \
         are computed in parallel (rayon) in chunks of links and added in link order, so the result is the same \
         bits on any number of threads (`crates/render/tests/accel/grid_pyramid_parallel.rs`).\n",
        opts.seed
    );
    let mdp = out.join("voxel_timing.md");
    write_text(&mdp, &md)?;
    Ok(ReportFiles { markdown: mdp, charts: Vec::new() })
}
