//! `tubecast mesh`: a scene tessellated within a certified tolerance, written as PLY, OBJ or
//! binary glTF; and the tracer `render --model mesh` uses.

use crate::args::MeshArgs;
use crate::error::CliError;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::mesh::{export, tessellate, tessellate_union, MeshTracer};
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
    crate::options::mesh(a)?;
    let model = crate::setup::model(a.splines);
    let plan = crate::setup::Plan { model, accel: crate::args::Accel::Bvh, render: None, rays: None };
    let run = (&a.select, &a.run);
    let scene = crate::setup::load(&a.input, &a.radius, run, plan, "the mesh is empty", false)?.scene;
    // The union's surface by default; the spline model is meshed as shells only.
    let shells = a.shells || a.splines;
    let m = crate::setup::with_threads(a.run.threads, || -> Result<_, CliError> {
        Ok(if shells { tessellate(&scene, model, a.tolerance)? } else { tessellate_union(&scene, a.tolerance)?.0 })
    })??;
    export::write(&a.out, &m)?;
    let (vertices, triangles, parts) = (m.mesh.positions.len(), m.mesh.triangles.len(), m.mesh.parts.len());
    let surface = if shells { "shells" } else { "union" };
    if a.json {
        let j = serde_json::json!({
            "file": a.out.display().to_string(), "vertices": vertices, "triangles": triangles,
            "closed_parts": parts, "certified": m.mesh.certified, "tolerance": a.tolerance,
            "surface": surface,
        });
        println!("{j}");
        return Ok(());
    }
    println!(
        "{}: {surface}, {vertices} vertices, {triangles} triangles, {parts} closed parts, certified Hausdorff bound {:e} (asked {:e})",
        a.out.display(),
        m.mesh.certified,
        a.tolerance
    );
    if m.mesh.certified > a.tolerance {
        eprintln!(
            "warning: the certified bound {:e} exceeds the tolerance: tubes closer than the finest grid tried without meeting (see docs/design/union-mesh.md)",
            m.mesh.certified
        );
    }
    Ok(())
}
