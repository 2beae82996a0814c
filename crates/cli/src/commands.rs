//! Each command: arguments into library calls, results to files or stdout.

use crate::args::{Accel, Color, GenerateArgs, InfoArgs, Kind, RenderArgs, Surface, Thin};
use crate::cmd_load::{LoadArgs, Plan, RenderPlan};
use crate::error::CliError;
use crate::render_opts::{check_out, Background, Radius};
use std::path::Path;
use tubecast_render::accel::{
    grid::{Grid, GridParams},
    Bvh, Tracer, WideBvh,
};
use tubecast_render::io::{self, npy::Array2};
use tubecast_render::render::{self, Camera, ColorBy, Options, Shading, View};
use tubecast_render::scene::Prim;
use tubecast_render::scene::{generate, Model, Scene};

type Res = Result<(), CliError>;

/// Print `tubecast: warning: {msg}` on stderr.
fn warn(msg: &str) {
    eprintln!("tubecast: warning: {msg}");
}

/// Load the scene at `input` ([`crate::cmd_load::load_scene`]); warn about radii raised to
/// `min_radius` and, with `empty` (what the command does then), about a scene without nodes;
/// with `field`, colour values from that data field of the file.
pub(crate) fn load(
    input: &Path,
    (radius, min_radius): (Radius, Option<f64>),
    args: &LoadArgs,
    plan: Plan,
    empty: &str,
    field: Option<&str>,
) -> Result<Scene, CliError> {
    let (mut scene, rep, fields) = crate::cmd_load::load_scene(input, radius, min_radius, args, plan, field.is_some())?;
    if let Some(key) = field {
        scene.select_values(&fields, key)?;
    }
    drop(fields);
    if let (Some(r), true) = (min_radius, rep.replaced > 0) {
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
    Ok(scene)
}

/// The chosen acceleration structure over `prims` (under a progress spinner). `rays`: how many
/// rays the command will trace through it (`None`: unknown), which the grid's resolution
/// weighs against its build (`GridParams::rays_per_build`; a command builds once).
pub(crate) fn tracer(accel: Accel, prims: Vec<Prim>, rays: Option<f64>) -> Box<dyn Tracer> {
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
pub(crate) fn scene_tracer(
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

/// Whether the minimum pixel footprint applies: `auto` turns it on for wireframe-like data
/// (formats without radii: .trk, .tck, .trx, .obj), off for SWC morphologies.
fn thin_on(t: Thin, input: &Path) -> bool {
    match t {
        Thin::On => true,
        Thin::Off => false,
        Thin::Auto => !input.extension().is_some_and(|e| e.eq_ignore_ascii_case("swc")),
    }
}

pub(crate) fn model(splines: bool) -> Model {
    if splines {
        Model::Splines
    } else {
        Model::Links
    }
}

pub fn render(a: &RenderArgs) -> Res {
    let field = match &a.color {
        Color::Data(key) => Some(key.as_str()),
        _ => None,
    };
    check_out(&a.out, a.force)?;
    if let Some(d) = &a.depth {
        check_out(d, a.force)?;
    }
    let m = model(a.splines);
    let exact = a.model != Surface::Mesh && a.tolerance.is_none() && a.pixel_error.is_none();
    // The compact tree over links builds from the scene alone: no list of primitives (80 B per
    // link) is held for the bounds or beside the clamped scene (issue 15: 10⁸ links).
    let compact = exact && matches!(a.accel, Accel::Bvh) && m == Model::Links;
    let image =
        RenderPlan { thin: thin_on(a.thin, &a.input), pixels: a.width as u64 * a.height as u64, list: !compact };
    // Camera rays, plus the AO rays when AO traces rays (cones trace none).
    let (ao, ao_method) = a.ao.resolve(a.ao_samples);
    let ao_rays = if ao_method == render::AoMethod::Rays { ao as f64 } else { 0.0 };
    let rays = Some(a.width as f64 * a.height as f64 * (1.0 + ao_rays));
    let plan = Plan { model: m, accel: a.accel, render: Some(image), rays };
    let empty = "the image shows the background only";
    if let (Surface::Quantized, Some(key)) = (a.model, field) {
        return Err(crate::cmd_quantized::QuantError::Data(key.into()).into());
    }
    let mut scene = load(&a.input, (a.radius, a.min_radius), &a.load, plan, empty, field)?;
    scene = crate::cmd_quantized::model_scene(a.model, scene, &a.quant, a.load.quiet)?;
    let list = |scene: &Scene| if compact { Ok(None) } else { scene.model_primitives(m).map(Some) };
    let mut prims = list(&scene)?;
    // Bounds of the primitives in use (a spline can bulge beyond its links' boxes); an empty
    // scene is viewed as if it were the box [-1, 1]³.
    let st = prims.as_deref().map_or_else(|| scene.primitive_stats(), |p| scene.stats_of(p));
    let cam = camera(a, if st.is_empty() { ([-1.0; 3], [1.0; 3]) } else { st.bounds })?;
    if thin_on(a.thin, &a.input) && render::clamp_thin(&mut scene, &cam, a.min_pixels) > 0 {
        drop(prims.take()); // not two lists at once
        prims = list(&scene)?;
    }
    let (prims, tol) = match (a.model, a.tolerance) {
        (Surface::Exact | Surface::Quantized, _) => {
            (prims.map(|p| crate::cmd_mesh::chosen(&scene, p, a.tolerance, a.pixel_error, &cam)), None)
        }
        (Surface::Mesh, t) => (prims, Some(t.ok_or(CliError::MeshTolerance)?)),
    };
    let owned = |p: Option<Vec<Prim>>| p.map_or_else(|| scene.model_primitives(m), Ok);
    let bvh = crate::cmd_intersect::with_threads(a.threads.map(usize::from), || match tol {
        None if exact => scene_tracer(a.accel, &scene, m, prims, rays),
        None => Ok(tracer(a.accel, owned(prims)?, rays)),
        Some(_) => crate::cmd_mesh::tracer(&scene, m, owned(prims)?, tol),
    })??;
    let background = match a.background {
        Background::Color(c) => c,
        Background::Transparent => [0.0; 3],
    };
    let opts = Options {
        color: match a.color {
            Color::Direction => ColorBy::Direction,
            Color::Radius => ColorBy::Radius,
            Color::Type => ColorBy::Type,
            Color::Data(_) => ColorBy::Values(a.colormap),
            Color::Solid(c) => ColorBy::Solid(c),
        },
        background,
        shading: Shading::Lit,
        opacity: a.opacity,
        ao,
        ao_method,
        shadows: a.shadows,
        progress: crate::progress::enabled() && (a.width as u64 * a.height as u64) >= 256 * 256,
    };
    let mut img = crate::cmd_intersect::with_threads(a.threads.map(usize::from), || {
        render::render(&scene, bvh.as_ref(), &cam, &opts)
    })??;
    if a.legend {
        match (&a.color, render::value_range(&scene.values)) {
            (Color::Data(_), Some((lo, hi))) => img.draw_legend(a.colormap, lo, hi, [0.0; 3]),
            (Color::Data(key), None) => warn(&format!("{key} has no finite values: no legend drawn")),
            _ => warn("--legend needs --color scalar:NAME or property:NAME: no legend drawn"),
        }
    }
    if let Some(d) = &a.depth {
        let arr = Array2 { rows: img.height as usize, cols: img.width as usize, data: img.depth.clone() };
        io::write_bytes(d, &io::npy::write(&arr))?;
    }
    match a.background {
        Background::Transparent => img.write_png_rgba(&a.out)?,
        Background::Color(_) => img.write_png(&a.out)?,
    }
    Ok(())
}

/// `render`'s camera for the scene bounds `bounds`: a preset view fitted to them, or the
/// given eye, target and up; orthographic with `--ortho`.
fn camera(a: &RenderArgs, bounds: ([f64; 3], [f64; 3])) -> Result<Camera, CliError> {
    let view = View { eye: a.eye, look_at: a.look_at, up: a.up, fov_deg: a.fov, width: a.width, height: a.height };
    let mut cam = match a.view {
        Some(p) if a.eye.is_none() && a.look_at.is_none() => {
            Camera::fit_preset(bounds.0, bounds.1, p, a.fov, a.width, a.height)?
        }
        _ => view.camera(bounds)?,
    };
    if a.ortho {
        let centre = std::array::from_fn(|k| 0.5 * (bounds.0[k] + bounds.1[k]));
        cam = cam.orthographic(a.look_at.unwrap_or(centre));
    }
    Ok(cam)
}

/// The coordinate units a format defines (by extension).
fn units(input: &Path) -> &'static str {
    match input.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase().as_str() {
        "trk" | "tck" | "trx" => "mm (RAS+ world space)",
        "swc" => "µm (the SWC convention; the file does not state it)",
        _ => "unknown (the format has no units)",
    }
}

pub fn info(a: &InfoArgs) -> Res {
    let plan = Plan { model: model(a.splines), accel: Accel::Bvh, render: None, rays: None };
    let scene = load(&a.input, (a.radius, a.min_radius), &a.load, plan, "counts are zero", None)?;
    let prims = if a.splines { scene.model_primitives(Model::Splines)? } else { Vec::new() };
    let st = if a.splines { scene.stats_of(&prims) } else { scene.stats() };
    let pieces = prims.iter().filter(|p| p.kind() == tubecast_render::scene::PrimKind::Spline).count();
    let bvh = if a.splines {
        crate::progress::step("building the 8-wide BVH", || WideBvh::build(prims))
    } else {
        crate::progress::step("building the compact 8-wide BVH", || WideBvh::from_scene(&scene, Model::Links))?
    };
    if a.json {
        let bounds = (!st.is_empty()).then(|| serde_json::json!({"min": st.bounds.0, "max": st.bounds.1}));
        let j = serde_json::json!({
            "file": a.input.display().to_string(),
            "units": units(&a.input),
            "nodes": st.nodes, "links": st.links, "cylinders": st.cylinders, "cones": st.cones,
            "spheres": st.spheres, "splines": st.splines, "bounds": bounds,
            "memory": {"scene_bytes": scene.memory_bytes(), "primitives_bvh_bytes": bvh.memory_bytes(),
                       "bvh_nodes": bvh.node_count()},
        });
        println!("{}", serde_json::to_string_pretty(&j).expect("a JSON value prints"));
        return Ok(());
    }
    println!("file       {}", a.input.display());
    println!("units      {}", units(&a.input));
    println!("nodes      {}", st.nodes);
    println!("links      {}", st.links);
    println!("cylinders  {}", st.cylinders);
    println!("cones      {}", st.cones);
    println!("spheres    {}", st.spheres);
    if a.splines {
        let f = scene.spline_fidelity();
        println!("splines    {} ({pieces} quadratic sub-segments)", st.splines);
        println!(
            "fidelity   traced: faithful split, {} pieces for ≤ {:.1e} radii from the cubic, certified; \
             Russig's pair would be ≤ {:.3e} radii ({:.3e} absolute)",
            f.faithful_pieces, f.faithful_relative, f.pair_relative, f.pair_distance
        );
    } else {
        println!("splines    {}", st.splines);
    }
    if st.is_empty() {
        println!("bounds     none (empty scene)");
    } else {
        println!("bounds min {:?}", st.bounds.0);
        println!("bounds max {:?}", st.bounds.1);
    }
    crate::cmd_mesh::info_choice(&scene, a.tolerance, a.pixel_error)?;
    println!(
        "memory     scene {} B, primitives + BVH {} B ({} 8-wide BVH nodes)",
        scene.memory_bytes(),
        bvh.memory_bytes(),
        bvh.node_count()
    );
    let per = |b: usize| b as f64 / st.links.max(1) as f64;
    println!(
        "per link   {:.1} B: scene {:.1} B + primitives and BVH {:.1} B",
        per(scene.memory_bytes() + bvh.memory_bytes()),
        per(scene.memory_bytes()),
        per(bvh.memory_bytes())
    );
    Ok(())
}

pub fn generate(a: &GenerateArgs) -> Res {
    // Whole-brain scale (issue 15): 10⁸ links generate in one call. The polylines are held as
    // f64 points (24 B each) while the file is written: `generate bundle --count 1190476
    // --segments 84` (10⁸ links) peaked at 4.44 GB resident (release build), so the cap of
    // 2·10⁸ stays under 9 GB.
    const MAX: usize = 200_000_000;
    let check = |c: usize, s: usize| {
        if c == 0 || s == 0 || c.saturating_mul(s) > MAX {
            Err(CliError::SceneSize { max: MAX })
        } else {
            Ok(())
        }
    };
    let lines = match a.kind {
        Kind::Bundle => {
            let (c, s) = (a.count.unwrap_or(1250), a.segments.unwrap_or(84));
            check(c, s)?;
            generate::bundle(c, s, a.seed)
        }
        Kind::Furball => {
            let (c, s) = (a.count.unwrap_or(10_000), a.segments.unwrap_or(78));
            check(c, s)?;
            generate::furball(c, s, a.seed)
        }
        Kind::Helix => {
            let s = a.segments.unwrap_or(200);
            check(1, s)?;
            generate::helix(s)
        }
        Kind::Neurons => return neurons(a),
    };
    Ok(io::write_polylines(&a.out, &lines)?)
}

fn neurons(a: &GenerateArgs) -> Res {
    if a.n == 0 || a.n > 40 {
        return Err(CliError::NeuronsPerSide);
    }
    if !a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("swc")) {
        return Err(CliError::NeuronsNeedSwc(a.out.clone()));
    }
    let bases = if a.base.is_empty() {
        vec![generate::base_neuron(a.seed)]
    } else {
        a.base.iter().map(|p| io::swc::load(p)).collect::<Result<Vec<_>, _>>()?
    };
    let nodes = generate::neurons(a.n, &bases, a.seed);
    Ok(io::write_bytes(&a.out, io::swc::write(&nodes).as_bytes())?)
}
