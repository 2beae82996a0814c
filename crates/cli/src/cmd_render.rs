//! `tubecast render`: a scene to a PNG (and optionally its depth).

use crate::args::{Accel, Device, RenderArgs, Surface, Thin};
use crate::error::CliError;
use crate::setup::{self, Plan, RenderPlan};
use crate::values::{Background, Color};
use tubecast_render::io::{self, npy::Array2};
use tubecast_render::render::{self, contrasting_ink, Camera, ColorBy, Options, Shading, View};
use tubecast_render::scene::{Model, Prim, Scene};

/// `tubecast render`.
pub fn render(a: &RenderArgs) -> Result<(), CliError> {
    crate::options::render(a)?;
    let field = match &a.color {
        Color::Data(key) => Some(key.as_str()),
        _ => None,
    };
    let m = setup::model(a.splines);
    // Faded thin tubes composite every union boundary: the GPU answers those too
    // (`GpuScene::line_intervals`).
    let thin = a.thin == Thin::On;
    let exact = a.model != Surface::Mesh && a.tolerance.is_none() && a.pixel_error.is_none();
    // The compact tree over links builds from the scene alone: no list of primitives (80 B per
    // link) is held for the bounds or beside the clamped scene.
    let compact = exact && matches!(a.accel, Accel::Bvh) && m == Model::Links;
    let image = RenderPlan { thin, pixels: a.width as u64 * a.height as u64, list: !compact };
    // Camera rays (N² per pixel with --aa N), plus the AO rays when AO traces rays (cones
    // trace none).
    let (ao, ao_method) = a.ao.resolve(a.ao_samples);
    let ao_rays = if ao_method == render::AoMethod::Rays { ao as f64 } else { 0.0 };
    let samples = (a.aa * a.aa) as f64;
    let rays = Some(a.width as f64 * a.height as f64 * samples * (1.0 + ao_rays));
    let plan = Plan { model: m, accel: a.accel, render: Some(image), rays };
    let empty = "the image shows the background only";
    let loaded = setup::load(&a.input, &a.radius, (&a.select, &a.run), plan, empty, field.is_some())?;
    let mut scene = loaded.scene;
    if let Some(key) = field {
        scene.select_values(&loaded.fields, key)?;
    }
    drop(loaded.fields);
    scene = crate::quantized::model_scene(a.model, scene, &a.quant, a.run.quiet)?;
    let list = |scene: &Scene| if compact { Ok(None) } else { scene.model_primitives(m).map(Some) };
    let mut prims = list(&scene)?;
    // Bounds of the primitives in use (a spline can bulge beyond its links' boxes); an empty
    // scene is viewed as if it were the box [-1, 1]³.
    let st = prims.as_deref().map_or_else(|| scene.primitive_stats(), |p| scene.stats_of(p));
    let bounds = if st.is_empty() { ([-1.0; 3], [1.0; 3]) } else { st.bounds };
    let cam = camera(a, bounds, &scene)?;
    if thin && render::clamp_thin(&mut scene, &cam, a.min_pixels) > 0 {
        drop(prims.take()); // not two lists at once
        prims = list(&scene)?;
    }
    let (prims, tol) = match a.model {
        Surface::Exact | Surface::Quantized => {
            (prims.map(|p| crate::choice::chosen(&scene, p, a.tolerance, a.pixel_error, &cam)), None)
        }
        Surface::Mesh => (prims, a.tolerance),
    };
    let owned = |p: Option<Vec<Prim>>| p.map_or_else(|| scene.model_primitives(m), Ok);
    // --device gpu builds its own tree (the same compact one) and needs no CPU tracer.
    let bvh = (a.device == Device::Cpu).then(|| {
        setup::with_threads(a.run.threads, || match tol {
            None if exact => setup::scene_tracer(a.accel, &scene, m, prims, rays),
            None => Ok(setup::tracer(a.accel, owned(prims)?, rays)),
            Some(_) => crate::cmd_mesh::tracer(&scene, m, owned(prims)?, tol),
        })
    });
    let bvh = bvh.transpose()?.transpose()?;
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
        aa: a.aa,
        progress: crate::progress::enabled() && (a.width as u64 * a.height as u64) >= 256 * 256,
    };
    let mut img = match &bvh {
        Some(bvh) => setup::with_threads(a.run.threads, || render::render(&scene, bvh.as_ref(), &cam, &opts))??,
        None => crate::gpu::render(&scene, m, &cam, &opts)?,
    };
    if a.legend {
        match (&a.color, render::value_range(&scene.values)) {
            (Color::Data(_), Some((lo, hi))) => img.draw_legend(a.colormap, lo, hi, contrasting_ink(background)),
            (Color::Data(key), None) => setup::warn(&format!("{key} has no finite values: no legend drawn")),
            _ => setup::warn("--legend needs --color scalar:NAME or property:NAME: no legend drawn"),
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

/// `render`'s camera: with `--eye` or `--look-at`, that view (a missing eye fitted to the
/// primitives' bounds `bounds`, a missing target their centre); otherwise the `--view` preset
/// or the default three-quarter view, framing the scene's nodes and radii
/// ([`Camera::framed`]). Orthographic with `--ortho`.
fn camera(a: &RenderArgs, bounds: ([f64; 3], [f64; 3]), scene: &Scene) -> Result<Camera, CliError> {
    let view = View { eye: a.eye, look_at: a.look_at, up: a.up, fov_deg: a.fov, width: a.width, height: a.height };
    let centre = std::array::from_fn(|k| 0.5 * (bounds.0[k] + bounds.1[k]));
    if a.eye.is_some() || a.look_at.is_some() {
        let cam = view.camera(bounds)?;
        return Ok(if a.ortho { cam.orthographic(a.look_at.unwrap_or(centre)) } else { cam });
    }
    let fitted = match a.view {
        Some(p) => Camera::fit_preset(bounds.0, bounds.1, p, a.fov, a.width, a.height)?,
        None => view.camera(bounds)?,
    };
    let cam = if a.ortho { fitted.orthographic(centre) } else { fitted };
    let spheres = (0..scene.nodes.len()).map(|i| (scene.nodes[i].pos, scene.radius(i)));
    Ok(cam.framed(spheres).unwrap_or(cam))
}
