//! The set-up every command shares: loading a scene (the selection of streamlines,
//! `--max-streamlines`, `--subsample`; the memory estimate checked before anything large is
//! allocated, `--memory-limit`; the load progress bar), the accelerator over it, the worker
//! pool (`-j`), and warnings. It imports the argument types and leaf modules only; every
//! command imports it, and it imports no command.
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

use crate::args::{Accel, RadiusArgs, RunArgs, SelectArgs};
use crate::error::CliError;
use crate::values::Radius;
use std::path::Path;
use tubecast_render::accel::grid::{padded_extent, Footprint, Grid, GridParams, SceneSums};
use tubecast_render::accel::{Bvh, Tracer, WideBvh};
use tubecast_render::estimate::{self, PerLink, Work};
use tubecast_render::io::data::Field;
use tubecast_render::io::stream::Selection;
use tubecast_render::scene::{generate, LoadOptions, LoadReport, Model, Prim, Scene};

/// Streamlines the memory estimate's sample holds at most.
pub const SAMPLE_STREAMLINES: usize = 200;

/// Print `tubecast: warning: {msg}` on stderr.
pub fn warn(msg: &str) {
    eprintln!("tubecast: warning: {msg}");
}

/// The selection of streamlines `--max-streamlines` and `--subsample` ask for.
pub fn selection(s: &SelectArgs) -> Selection {
    let max = s.max_streamlines.map(|n| usize::try_from(n).unwrap_or(usize::MAX));
    Selection { max_streamlines: max, subsample: s.subsample }
}

/// Run `f` on a rayon pool of `threads` threads (`None`: one per core, rayon's default).
pub fn with_threads<R: Send>(threads: Option<u16>, f: impl FnOnce() -> R + Send) -> Result<R, CliError> {
    match threads {
        None => Ok(f()),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n.into()).build().map_err(CliError::Threads)?;
            Ok(pool.install(f))
        }
    }
}

/// Links, or with `splines` the spline model.
pub fn model(splines: bool) -> Model {
    if splines {
        Model::Splines
    } else {
        Model::Links
    }
}

/// A scene as a command loads it: the data fields of the file too when asked.
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// The file's data fields (empty unless asked for).
    pub fields: Vec<Field>,
}

/// Load the scene at `input` ([`load_scene`]); warn about radii raised to `--min-radius` and,
/// with `empty` (what the command does then), about a scene without nodes; with `data`, keep
/// the file's data fields.
pub fn load(
    input: &Path,
    radius: &RadiusArgs,
    (select, run): (&SelectArgs, &RunArgs),
    plan: Plan,
    empty: &str,
    data: bool,
) -> Result<Loaded, CliError> {
    let (scene, rep, fields) = load_scene(input, radius, (select, run), plan, data)?;
    if let (Some(r), true) = (radius.min_radius, rep.replaced > 0) {
        warn(&format!(
            "{}: {} of {} radii were below --min-radius {r} ({} of them ≤ 0) and were set to {r}",
            input.display(),
            rep.replaced,
            scene.nodes.len(),
            rep.placeholders
        ));
    }
    if scene.nodes.is_empty() {
        warn(&format!("{}: no streamlines or nodes (empty scene); {empty}", input.display()));
    }
    Ok(Loaded { scene, fields })
}

/// The chosen acceleration structure over `prims` (under a progress spinner). `rays`: how many
/// rays the command will trace through it (`None`: unknown), which the grid's resolution
/// weighs against its build (`GridParams::rays_per_build`; a command builds once).
pub fn tracer(accel: Accel, prims: Vec<Prim>, rays: Option<f64>) -> Box<dyn Tracer> {
    crate::progress::step(&format!("building the accelerator over {} primitives", prims.len()), || match accel {
        Accel::Bvh => Box::new(WideBvh::build(prims)) as Box<dyn Tracer>,
        Accel::Bvh2 => Box::new(Bvh::build(prims)),
        Accel::Grid => {
            let params = GridParams { rays_per_build: rays, ..GridParams::default() };
            Box::new(Grid::build_with(prims, &params))
        }
    })
}

/// The chosen acceleration structure over the scene's own primitives of model `m` (`prims`, or
/// none yet: `None` computes them): the 8-wide BVH keeps the links model compact
/// ([`WideBvh::from_scene`]), the others trace the same primitives
/// ([`WideBvh::scene_primitives`]), so every `--accel` gives the same answers.
pub fn scene_tracer(
    accel: Accel,
    scene: &Scene,
    m: Model,
    prims: Option<Vec<Prim>>,
    rays: Option<f64>,
) -> Result<Box<dyn Tracer>, CliError> {
    if matches!(accel, Accel::Bvh) && m == Model::Links {
        drop(prims);
        let bvh = crate::progress::step("building the compact 8-wide BVH", || WideBvh::from_scene(scene, m))?;
        return Ok(Box::new(bvh));
    }
    if m == Model::Links {
        drop(prims); // the tracer's own list replaces the caller's: not two lists at once
        return Ok(tracer(accel, WideBvh::scene_primitives(scene), rays));
    }
    Ok(tracer(accel, prims.map_or_else(|| scene.model_primitives(m), Ok)?, rays))
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

    /// The grid's parameters as [`tracer`] sets them.
    fn grid_params(&self) -> GridParams {
        GridParams { rays_per_build: self.rays, ..GridParams::default() }
    }
}

/// Load `input` as the command will use it: configure progress, check the memory estimate,
/// resolve a relative radius, then stream the file in (with the data fields when `data`).
pub fn load_scene(
    input: &Path,
    radius: &RadiusArgs,
    (select, run): (&SelectArgs, &RunArgs),
    plan: Plan,
    data: bool,
) -> Result<(Scene, LoadReport, Vec<Field>), CliError> {
    crate::progress::configure(run.progress, run.quiet);
    let (sel, min_radius) = (selection(select), radius.min_radius);
    let sample_radius = match radius.radius {
        Radius::Absolute(r) => r,
        Radius::Relative(_) => 1.0,
    };
    check_memory(input, &LoadOptions { default_radius: sample_radius, min_radius }, &sel, select.memory_limit, plan)?;
    let r = resolve_radius(input, radius.radius, min_radius, &sel)?;
    let opts = LoadOptions { default_radius: r, min_radius };
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
        // The grid's own primitives ([`scene_tracer`]), for their sums and box.
        let prims = match plan.model {
            Model::Links => WideBvh::scene_primitives(&scene),
            m => scene.model_primitives(m).ok()?,
        };
        (0.0, Some((SceneSums::of(&prims), padded_extent(&prims))))
    } else {
        let tracer = scene_tracer(plan.accel, &scene, plan.model, None, None).ok()?;
        (per(tracer.memory_bytes()), None)
    };
    let per_link = PerLink { scene: per(scene.memory_bytes()), tracer };
    let lines = scene.nodes.len().saturating_sub(links);
    let avg = (!is_swc && lines > 0).then(|| scene.nodes.len() as f64 / lines as f64);
    Some(Sample { per_link, avg, nodes_per_link: scene.nodes.len() as f64 / links as f64, links: links as u64, grid })
}

/// The default radius: absolute, or the fraction of the diagonal of the bounding box of the
/// points kept (read once more to measure it; a file of one point: the fraction of 1 unit).
pub fn resolve_radius(input: &Path, r: Radius, min_radius: Option<f64>, sel: &Selection) -> Result<f64, CliError> {
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
