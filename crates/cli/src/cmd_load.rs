//! Loading a scene for `render`, `info` and `intersect`: the selection of streamlines
//! (`--max-streamlines`, `--subsample`), the memory estimate checked before anything large is
//! allocated (`--memory-limit`), and the load progress bar (`--progress`, `--quiet`).
//!
//! # The estimate
//! [`check_memory`] counts the links from the file's header and size
//! ([`tubecast_render::estimate::probe`]), measures bytes per link on a sample (the file's
//! first streamlines, up to [`SAMPLE_STREAMLINES`], loaded and built exactly as the command
//! will: same radius, selection, model and accelerator; an SWC tree: a generated bundle), and
//! refuses a scene whose peak ([`tubecast_render::estimate`]'s model) exceeds `--memory-limit`
//! or, without it, the memory available. The voxel grid is not built on the sample: its bytes
//! per link depend on the link count, so the estimate asks the grid's own resolution what it
//! will build over the whole scene ([`estimate::grid_footprint`], with the command's rays).

use crate::args::Accel;
use crate::error::CliError;
use crate::render_opts::Radius;
use clap::Args;
use std::path::Path;
use tubecast_render::accel::grid::{padded_extent, Footprint, GridParams, SceneSums};
use tubecast_render::accel::WideBvh;
use tubecast_render::estimate::{self, PerLink, Work};
use tubecast_render::io::stream::Selection;
use tubecast_render::scene::{generate, LoadOptions, Model, Scene};

/// Streamlines the memory estimate's sample holds at most.
pub const SAMPLE_STREAMLINES: usize = 200;

/// What every command that loads a scene accepts about memory and progress.
#[derive(Args, Clone, Debug, Default)]
pub struct LoadArgs {
    /// Keep only the first N streamlines (after --subsample); the rest of the file is not
    /// read. Not for SWC files (one tree).
    #[arg(long, value_name = "N")]
    pub max_streamlines: Option<usize>,
    /// Keep about a fraction F of the streamlines, 0 < F ≤ 1: streamline i (file order) is
    /// kept when SplitMix64 seeded with i draws below F·2⁶⁴ (deterministic, the same on every
    /// run; no aliasing of an interleaved file as a stride would). Not for SWC files.
    #[arg(long, value_name = "F")]
    pub subsample: Option<f64>,
    /// Refuse a scene whose estimated peak memory exceeds BYTES (suffixes K, M, G, T: powers
    /// of 1024) instead of the memory available (MemAvailable, or the cgroup's limit).
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub memory_limit: Option<u64>,
    /// Show the progress bars even where stderr is not a terminal.
    #[arg(long)]
    pub progress: bool,
    /// Hide the progress bars.
    #[arg(long)]
    pub quiet: bool,
}

impl LoadArgs {
    /// The selection of streamlines.
    pub fn selection(&self) -> Selection {
        Selection { max_streamlines: self.max_streamlines, subsample: self.subsample }
    }
}

/// `1234`, `512K`, `1.5G`, ...: bytes, with binary suffixes.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (num, mult) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M') => (&t[..t.len() - 1], 1 << 20),
        Some('G') => (&t[..t.len() - 1], 1 << 30),
        Some('T') => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    match num.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 && v * (mult as f64) < 1.8e19 => Ok((v * mult as f64) as u64),
        _ => Err(format!("{s:?} is not a byte count (e.g. 8G, 512M, 1000000)")),
    }
}

/// How a command will build its scene: model and accelerator (for the sample), and what
/// `render` holds besides.
#[derive(Clone, Copy)]
pub struct Plan {
    /// Links or splines.
    pub model: Model,
    /// The accelerator the command builds.
    pub accel: Accel,
    /// What `render` holds besides (`None`: no image).
    pub render: Option<RenderPlan>,
    /// Rays the command traces through its tracer (`None`: unknown), which the grid's
    /// resolution weighs against its build (`GridParams::rays_per_build`).
    pub rays: Option<f64>,
}

/// What `render` holds besides the scene and its tracer.
#[derive(Clone, Copy)]
pub struct RenderPlan {
    /// Whether thin tubes may be clamped.
    pub thin: bool,
    /// Pixels of the image.
    pub pixels: u64,
    /// Whether a list of the scene's primitives is held beside it (every path but the compact
    /// tree's exact one, which builds from the scene alone).
    pub list: bool,
}

impl Plan {
    /// What the command builds besides the scene, for the estimate (`nodes_per_link`: of the
    /// sample). The clamp is counted whenever `--thin` is on, whether or not a tube turns out
    /// thinner than `--min-pixels` (an over-estimate of 12 B per node otherwise).
    fn work(&self, nodes_per_link: f64, grid: Option<Footprint>) -> Work {
        let compact = matches!(self.accel, Accel::Bvh) && self.model == Model::Links;
        let r = self.render.unwrap_or(RenderPlan { thin: false, pixels: 0, list: false });
        let thin_nodes = if r.thin { nodes_per_link as f32 } else { 0.0 };
        // `intersect` holds its rays (`render`'s are made one at a time).
        let rays = if self.render.is_none() { self.rays.unwrap_or(0.0) as u64 } else { 0 };
        Work { compact, prim_list: r.list, thin_nodes, pixels: r.pixels, grid, rays }
    }

    /// The grid's parameters as [`crate::commands::tracer`] sets them.
    fn grid_params(&self) -> GridParams {
        GridParams { rays_per_build: self.rays, ..GridParams::default() }
    }
}

/// Load `input` as the command will use it: configure progress, check the memory estimate,
/// resolve a relative radius, then stream the file in (with the data fields when `data`).
pub fn load_scene(
    input: &Path,
    radius: Radius,
    min_radius: Option<f64>,
    load: &LoadArgs,
    plan: Plan,
    data: bool,
) -> Result<(Scene, tubecast_render::scene::LoadReport, Vec<tubecast_render::io::data::Field>), CliError> {
    crate::progress::configure(load.progress, load.quiet);
    let sel = load.selection();
    let sample_radius = match radius {
        Radius::Absolute(r) => r,
        Radius::Relative(_) => 1.0,
    };
    check_memory(input, &LoadOptions { default_radius: sample_radius, min_radius }, &sel, load.memory_limit, plan)?;
    let radius = resolve_radius(input, radius, min_radius, &sel)?;
    let opts = LoadOptions { default_radius: radius, min_radius };
    let len = std::fs::metadata(input).map(|m| m.len()).unwrap_or(0);
    let bar = crate::progress::bytes(len, &format!("loading {}", input.display()));
    let r = Scene::load_selected(input, &opts, &sel, data, &bar);
    bar.finish_and_clear();
    crate::progress::report_peak(Some("load"));
    Ok(r?)
}

/// Refuse, before loading, a scene whose estimated peak memory exceeds `limit` (or, without
/// one, the memory available). Returns the estimate in bytes (`None`: nothing to estimate).
pub fn check_memory(
    input: &Path,
    opts: &LoadOptions,
    sel: &Selection,
    limit: Option<u64>,
    plan: Plan,
) -> Result<Option<u64>, CliError> {
    let available = match limit {
        Some(b) => (b, "--memory-limit".to_string()),
        None => match estimate::available() {
            Some(a) => a,
            None => return Ok(None),
        },
    };
    // Unreadable or malformed files are reported by the load itself, with its own message.
    let Ok(counts) = estimate::probe(input) else { return Ok(None) };
    let Some(Sample { mut per_link, avg, nodes_per_link, links, grid }) = sample(input, opts, sel, plan) else {
        return Ok(None);
    };
    let kept = (counts.links(sel, avg), counts.kept_lines(sel, avg));
    let grid = grid.map(|(sums, ext)| {
        let f = estimate::grid_footprint(&sums, links, ext, kept.0, &plan.grid_params());
        per_link.tracer = f.finished_bytes() / kept.0.max(1) as f64;
        f
    });
    let name = input.display().to_string();
    let work = plan.work(nodes_per_link, grid);
    Ok(Some(estimate::check_with(&name, kept, per_link, work, available).map_err(CliError::Memory)?))
}

/// What the estimate measures on a sample of the file.
struct Sample {
    /// Bytes per link (the tracer's: 0 for the grid, which is not built on the sample).
    per_link: PerLink,
    /// Points per streamline (not for SWC).
    avg: Option<f64>,
    /// Nodes per link.
    nodes_per_link: f64,
    /// Links of the sample.
    links: u64,
    /// For `--accel grid`: the sums and padded box of the sample's primitives.
    grid: Option<(SceneSums, [f64; 3])>,
}

/// Bytes per link of the first streamlines of `input` (a generated bundle for SWC), built as
/// `plan` says, their points per streamline and nodes per link; `None` when the sample has no
/// links.
fn sample(input: &Path, opts: &LoadOptions, sel: &Selection, plan: Plan) -> Option<Sample> {
    let is_swc = input.extension().is_some_and(|e| e.eq_ignore_ascii_case("swc"));
    let scene = if is_swc {
        Scene::from_polylines(&generate::bundle(16, 64, 1), opts.default_radius, "sample").ok()?
    } else {
        let max = sel.max_streamlines.unwrap_or(usize::MAX).min(SAMPLE_STREAMLINES);
        let few = Selection { max_streamlines: Some(max), subsample: sel.subsample };
        let hidden = indicatif::ProgressBar::hidden();
        Scene::load_selected(input, opts, &few, false, &hidden).ok()?.0
    };
    let links = scene.links.len();
    if links == 0 {
        return None;
    }
    let per = |b: usize| b as f64 / links as f64;
    let (tracer, grid) = if matches!(plan.accel, Accel::Grid) {
        // The grid's own primitives ([`crate::commands::scene_tracer`]), for their sums and box.
        let prims = match plan.model {
            Model::Links => WideBvh::scene_primitives(&scene),
            m => scene.model_primitives(m).ok()?,
        };
        (0.0, Some((SceneSums::of(&prims), padded_extent(&prims))))
    } else {
        let tracer = crate::commands::scene_tracer(plan.accel, &scene, plan.model, None, None).ok()?;
        (per(tracer.memory_bytes()), None)
    };
    let per_link = PerLink { scene: per(scene.memory_bytes()), tracer };
    let lines = scene.nodes.len().saturating_sub(links);
    let avg = (!is_swc && lines > 0).then(|| scene.nodes.len() as f64 / lines as f64);
    Some(Sample { per_link, avg, nodes_per_link: scene.nodes.len() as f64 / links as f64, links: links as u64, grid })
}

/// The default radius: absolute, or the fraction of the diagonal of the bounding box of the
/// points kept (read once more to measure it; a file of one point: the fraction of 1 unit).
fn resolve_radius(input: &Path, r: Radius, min_radius: Option<f64>, sel: &Selection) -> Result<f64, CliError> {
    let f = match r {
        Radius::Absolute(v) => return Ok(v),
        Radius::Relative(f) => f,
    };
    let opts = LoadOptions { default_radius: 1.0, min_radius };
    let hidden = indicatif::ProgressBar::hidden();
    let (scene, ..) = Scene::load_selected(input, &opts, sel, false, &hidden)?;
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for n in &scene.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(n.pos[k]);
            hi[k] = hi[k].max(n.pos[k]);
        }
    }
    let diag = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    Ok(if diag.is_finite() && diag > 0.0 { f * diag } else { f })
}
