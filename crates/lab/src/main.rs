//! `tubecast-lab`: writes the reports (SVG charts, markdown, CSV) into a folder.
//!
//! ```text
//! cargo run --release -p tubecast-lab -- accuracy|stability|speed|thin|mesh|mesh-real|mesh-size|peers|gpu|voxel|voxel-ao|voxel-quantized|voxel-timing|spline-lanes|all|tables [--out DIR]
//!     [--seed N] [--quick] [--big] [--threads N] [--quiet]
//! ```
//!
//! `--big` extends the speed report to 10⁶ segments; `--quick` is the tiny test setting;
//! `peers` needs `--features embree` (and `libembree-dev`); `gpu` needs `--features embree,gpu`
//! (and a Vulkan adapter: Mesa's lavapipe is a software one). Defaults: the settings of
//! `docs/report/`.

use clap::{Parser, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tubecast_lab::report::{self, ReportError, ReportFiles, ReportOptions};

#[derive(Parser)]
#[command(name = "tubecast-lab", version, about = "tubecast's accuracy, stability, speed and peer reports")]
struct Args {
    /// Which report.
    #[arg(value_enum)]
    which: Which,
    /// Output folder for the SVG charts and the markdown summary.
    #[arg(long, default_value = "docs/report")]
    out: PathBuf,
    /// Seed of every case generator.
    #[arg(long)]
    seed: Option<u64>,
    /// The tiny test-sized run (seconds).
    #[arg(long)]
    quick: bool,
    /// Speed report up to 10⁶ segments (default 10⁵).
    #[arg(long)]
    big: bool,
    /// Worker threads for the speed report (1 makes frame times comparable).
    #[arg(long)]
    threads: Option<usize>,
    /// Hide the progress bars.
    #[arg(long)]
    quiet: bool,
}

/// The reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Which {
    /// Error (max, p99) against cost for every kernel × precision × solver.
    Accuracy,
    /// False-miss / false-hit rates and errors in each failure region.
    Stability,
    /// Frame time and rays/s against segment count, opaque and transparent.
    Speed,
    /// The certified mesh path against the exact kernels (Salm's question).
    Mesh,
    /// Embree 3's round linear curves on the same rays (feature `embree`).
    Peers,
    /// The GPU walk against the CPU path and Embree (features `embree` and `gpu`).
    Gpu,
    /// Spline kernel: error and false answers against length/radius, per solver.
    Thin,
    /// Dynamic line sets: rebuild + render per frame, voxel grid vs BVH.
    Voxel,
    /// Mesh and automatic choice on real-world-like scenes: cost against certified error.
    MeshReal,
    /// Triangles and bytes against certified error: link models, shells and the union mesh.
    MeshSize,
    /// Write `<name>.tables.json` beside every markdown report in --out (measures nothing).
    Tables,
    /// Ambient occlusion: voxel cone tracing vs rays, error against cost.
    VoxelAo,
    /// Kanzler's quantized lines: rendering from them, memory, and their LoD for AO.
    VoxelQuantized,
    /// Voxelization and pyramid build timings by repeated median.
    VoxelTiming,
    /// Spline kernel against the link per call, scalar and lanes, and the per-call lane floor.
    SplineLanes,
    /// Every report this build has (peers only with feature `embree`).
    All,
}

type Job = fn(&Path, &ReportOptions) -> Result<ReportFiles, ReportError>;

fn jobs(which: Which) -> Result<Vec<(&'static str, Job)>, String> {
    let mut jobs: Vec<(&'static str, Job)> = Vec::new();
    let all = which == Which::All;
    if all || which == Which::Accuracy {
        jobs.push(("accuracy", report::run_accuracy));
    }
    if all || which == Which::Stability {
        jobs.push(("stability", report::run_stability));
    }
    if all || which == Which::Speed {
        jobs.push(("speed", report::run_speed));
    }
    if all || which == Which::Thin {
        jobs.push(("thin", report::run_thin));
    }
    if all || which == Which::Voxel {
        jobs.push(("voxel", report::run_voxel));
    }
    if all || which == Which::VoxelAo {
        jobs.push(("voxel-ao", report::run_voxel_ao));
    }
    if all || which == Which::VoxelQuantized {
        jobs.push(("voxel-quantized", report::run_voxel_quantized));
    }
    if all || which == Which::VoxelTiming {
        jobs.push(("voxel-timing", report::run_voxel_timing));
    }
    if all || which == Which::SplineLanes {
        jobs.push(("spline-lanes", report::run_spline_lanes));
    }
    if all || which == Which::Mesh {
        jobs.push(("mesh", report::run_mesh));
    }
    if all || which == Which::MeshReal {
        jobs.push(("mesh-real", report::run_mesh_real));
    }
    if all || which == Which::MeshSize {
        jobs.push(("mesh-size", report::run_mesh_size));
    }
    #[cfg(feature = "embree")]
    if all || which == Which::Peers {
        jobs.push(("peers", report::run_peers));
    }
    #[cfg(not(feature = "embree"))]
    if which == Which::Peers {
        return Err("the peers report needs `--features embree` (and libembree-dev)".into());
    }
    // Not in `all`: it needs an adapter, and on a software one it measures the CPU twice.
    #[cfg(all(feature = "gpu", feature = "embree"))]
    if which == Which::Gpu {
        jobs.push(("gpu", report::run_gpu));
    }
    #[cfg(not(all(feature = "gpu", feature = "embree")))]
    if which == Which::Gpu {
        return Err("the gpu report needs `--features embree,gpu` (libembree-dev and a Vulkan adapter)".into());
    }
    Ok(jobs)
}

fn main() -> ExitCode {
    let a = Args::parse();
    let mut opts = if a.quick { ReportOptions::quick() } else { ReportOptions::default() };
    if let Some(s) = a.seed {
        opts.seed = s;
    }
    if a.big {
        opts.max_segments = 1_000_000;
    }
    if let Some(t) = a.threads {
        opts.threads = t;
    }
    opts.progress = !a.quiet;
    if a.which == Which::Tables {
        return match report::write_tables_json(&a.out) {
            Ok(f) => {
                f.iter().for_each(|p| println!("tables: wrote {}", p.display()));
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("tubecast-lab tables: {e}");
                ExitCode::FAILURE
            }
        };
    }
    let jobs = match jobs(a.which) {
        Ok(j) => j,
        Err(e) => {
            eprintln!("tubecast-lab: {e}");
            return ExitCode::from(2);
        }
    };
    for (name, job) in jobs {
        match job(&a.out, &opts) {
            Ok(f) => println!("{name}: wrote {} and {} chart(s)", f.markdown.display(), f.charts.len()),
            Err(e) => {
                eprintln!("tubecast-lab {name}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
