//! `tubecast mesh`: a scene tessellated within a certified tolerance, written as PLY, OBJ or
//! binary glTF; and the tracer `render --model mesh` uses.

use crate::args::MeshArgs;
use crate::error::CliError;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::mesh::{export, tessellate, MeshTracer};
use tubecast_render::render::{Camera, View};
use tubecast_render::scene::choice::{choose_with, Choice, Tolerance};
use tubecast_render::scene::{Model, Prim, Scene};

/// The tracer for `render`: the exact BVH, or with `tolerance` the certified mesh of the
/// same model (hits still name the model's primitives, so colouring is unchanged).
pub fn tracer(
    scene: &Scene,
    model: Model,
    prims: Vec<Prim>,
    tolerance: Option<f64>,
) -> Result<Box<dyn Tracer>, CliError> {
    Ok(match tolerance {
        None => Box::new(Bvh::build(prims)),
        Some(eps) => Box::new(MeshTracer::build(&tessellate(scene, model, eps)?, prims)),
    })
}

pub fn mesh(a: &MeshArgs) -> Result<(), CliError> {
    let plan = crate::cmd_load::Plan {
        model: crate::commands::model(a.splines),
        accel: crate::args::Accel::Bvh,
        render: None,
        rays: None,
    };
    let radius = (crate::render_opts::Radius::Absolute(a.io.radius), a.min_radius);
    let args = crate::cmd_load::LoadArgs::default();
    let scene = crate::commands::load(&a.io.input, radius, &args, plan, "the mesh is empty", None)?;
    let model = if a.splines { Model::Splines } else { Model::Links };
    let m = tessellate(&scene, model, a.io.tolerance)?;
    export::write(&a.io.out, &m)?;
    println!(
        "{}: {} vertices, {} triangles, {} closed parts, certified Hausdorff bound {:e} (asked {:e})",
        a.io.out.display(),
        m.mesh.positions.len(),
        m.mesh.triangles.len(),
        m.mesh.parts.len(),
        m.mesh.certified,
        a.io.tolerance
    );
    Ok(())
}

/// The automatic choice's tolerance from `--tolerance` or `--pixel-error` and a camera.
fn tolerance(eps: Option<f64>, pixels: Option<f64>, cam: &Camera) -> Option<Tolerance> {
    match (eps, pixels) {
        (Some(e), _) => Some(Tolerance::Absolute(e)),
        (None, Some(p)) => {
            Some(Tolerance::Pixels { eye: cam.eye.to_array(), fov_deg: cam.fov_deg, height: cam.height, pixels: p })
        }
        _ => None,
    }
}

/// `render` with the exact model: the chosen primitives when a tolerance is given, else `prims`.
pub fn chosen(scene: &Scene, prims: Vec<Prim>, eps: Option<f64>, pixels: Option<f64>, cam: &Camera) -> Vec<Prim> {
    match tolerance(eps, pixels, cam) {
        Some(t) => choose_with(scene, &t, true).prims,
        None => prims,
    }
}

/// `info --tolerance` / `--pixel-error`: counts of the automatic choice and its worst error.
pub fn info_choice(scene: &Scene, eps: Option<f64>, pixels: Option<f64>) -> Result<(), CliError> {
    if eps.is_none() && pixels.is_none() {
        return Ok(());
    }
    let st = scene.stats();
    let bounds = if st.is_empty() { ([-1.0; 3], [1.0; 3]) } else { st.bounds };
    let cam = View::default().camera(bounds)?;
    let Some(t) = tolerance(eps, pixels, &cam) else { return Ok(()) };
    let c: Choice = choose_with(scene, &t, true);
    println!(
        "choice     {} primitives: {} spheres, {} cylinders, {} cones, {} spline pieces ({} links merged away, {} fitted away into spline pieces), worst certified error {:e}",
        c.prims.len(),
        c.spheres,
        c.cylinders,
        c.cones,
        c.splines,
        c.merged,
        c.fitted,
        c.worst
    );
    Ok(())
}
