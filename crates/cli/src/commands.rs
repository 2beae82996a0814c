//! Each command: arguments into library calls, results to files or stdout.

use crate::args::{Color, GenerateArgs, InfoArgs, IntersectArgs, Kind, RenderArgs};
use crate::error::CliError;
use std::path::Path;
use tubecast_render::accel::{hit_table, Bvh};
use tubecast_render::io::{self, npy::Array2};
use tubecast_render::render::{self, ColorBy, Options, Shading, View};
use tubecast_render::scene::{generate, LoadOptions, Model, Scene};

type Res = Result<(), CliError>;

/// Print `tubecast: warning: {msg}` on stderr.
fn warn(msg: &str) {
    eprintln!("tubecast: warning: {msg}");
}

/// Load the scene at `input`; warn about radii raised to `min_radius` and, with `empty`
/// (what the command does then), about a scene without nodes.
fn load(input: &Path, radius: f64, min_radius: Option<f64>, empty: &str) -> Result<Scene, CliError> {
    let (scene, rep) = Scene::load_with(input, &LoadOptions { default_radius: radius, min_radius })?;
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

fn model(splines: bool) -> Model {
    if splines {
        Model::Splines
    } else {
        Model::Links
    }
}

pub fn render(a: &RenderArgs) -> Res {
    let scene = load(&a.input, a.radius, a.min_radius, "the image shows the background only")?;
    let prims = scene.model_primitives(model(a.splines))?;
    // Bounds of the primitives in use (a spline can bulge beyond its links' boxes); an empty
    // scene is viewed as if it were the box [-1, 1]³.
    let st = scene.stats_of(&prims);
    let bounds = if st.is_empty() { ([-1.0; 3], [1.0; 3]) } else { st.bounds };
    let bvh = Bvh::build(prims);
    let view = View { eye: a.eye, look_at: a.look_at, up: a.up, fov_deg: a.fov, width: a.width, height: a.height };
    let cam = view.camera(bounds)?;
    let opts = Options {
        color: match a.color {
            Color::Direction => ColorBy::Direction,
            Color::Radius => ColorBy::Radius,
            Color::Type => ColorBy::Type,
        },
        shading: Shading::Lit,
        opacity: a.opacity,
        ao: a.ao,
        shadows: a.shadows,
        progress: !a.quiet && (a.width as u64 * a.height as u64) >= 256 * 256,
        ..Options::default()
    };
    Ok(render::render(&scene, &bvh, &cam, &opts)?.write_png(&a.out)?)
}

pub fn info(a: &InfoArgs) -> Res {
    let scene = load(&a.input, a.radius, a.min_radius, "counts are zero")?;
    let prims = scene.model_primitives(model(a.splines))?;
    let st = if a.splines { scene.stats_of(&prims) } else { scene.stats() };
    let pieces = prims.iter().filter(|p| p.kind() == tubecast_render::scene::PrimKind::Spline).count();
    let bvh = Bvh::build(prims);
    println!("file       {}", a.input.display());
    println!("nodes      {}", st.nodes);
    println!("links      {}", st.links);
    println!("cylinders  {}", st.cylinders);
    println!("cones      {}", st.cones);
    println!("spheres    {}", st.spheres);
    if a.splines {
        let f = scene.spline_fidelity();
        println!("splines    {} ({pieces} quadratic sub-segments)", st.splines);
        println!(
            "fidelity   traced pair ≤ {:.3e} radii ({:.3e} absolute) from the cubic, certified; \
             faithful split: {} pieces for ≤ {:.1e} radii",
            f.pair_relative, f.pair_distance, f.faithful_pieces, f.faithful_relative
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
    println!(
        "memory     scene {} B, primitives + BVH {} B ({} BVH nodes)",
        scene.memory_bytes(),
        bvh.memory_bytes(),
        bvh.node_count()
    );
    Ok(())
}

pub fn intersect(a: &IntersectArgs) -> Res {
    let scene = load(&a.input, a.radius, a.min_radius, "every ray misses")?;
    let name = a.rays.display().to_string();
    let rays = io::npy::read(&io::read_bytes(&a.rays)?, &name, Some(6))?.rays(&name)?;
    let bvh = Bvh::build(scene.model_primitives(model(a.splines))?);
    let hits = Array2::from_rows(&hit_table(&bvh, &rays));
    Ok(io::write_bytes(&a.out, &io::npy::write(&hits))?)
}

pub fn generate(a: &GenerateArgs) -> Res {
    const MAX: usize = 50_000_000;
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
