//! `tubecast mesh`: a scene tessellated within a certified tolerance, written as PLY, OBJ or
//! binary glTF; and the tracer `render --model mesh` uses.

use crate::args::MeshArgs;
use crate::error::CliError;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::mesh::{export, tessellate, MeshTracer};
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
    let scene = crate::commands::load(&a.input, a.radius, a.min_radius, "the mesh is empty")?;
    let model = if a.splines { Model::Splines } else { Model::Links };
    let m = tessellate(&scene, model, a.tolerance)?;
    export::write(&a.out, &m)?;
    println!(
        "{}: {} vertices, {} triangles, {} closed parts, certified Hausdorff bound {:e} (asked {:e})",
        a.out.display(),
        m.mesh.positions.len(),
        m.mesh.triangles.len(),
        m.mesh.parts.len(),
        m.mesh.certified,
        a.tolerance
    );
    Ok(())
}
