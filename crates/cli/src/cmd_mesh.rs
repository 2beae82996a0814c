//! `tubecast mesh`: a scene tessellated within a certified tolerance, written as PLY, OBJ or
//! binary glTF; and the tracer `render --model mesh` uses.

use crate::args::MeshArgs;
use crate::error::CliError;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::mesh::{export, tessellate, tessellate_union_with, Bodies, MeshTracer, UnionOptions, UnionReport};
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
    // The union is refused before it is built when its estimated peak exceeds --memory-limit
    // or, without it, the memory available.
    let memory_limit = a.select.memory_limit.or_else(|| tubecast_render::estimate::available().map(|(b, _)| b));
    let bodies = match (a.runs, a.hulls) {
        (true, _) => Bodies::Runs,
        (_, true) => Bodies::Hulls,
        _ => Bodies::Auto,
    };
    let (m, report) = crate::setup::with_threads(a.run.threads, || -> Result<_, CliError> {
        Ok(if shells {
            (tessellate(&scene, model, a.tolerance)?, None)
        } else {
            let (m, r) = tessellate_union_with(&scene, a.tolerance, &UnionOptions { memory_limit, bodies })?;
            (m, Some(r))
        })
    })??;
    export::write(&a.out, &m)?;
    let (vertices, triangles, parts) = (m.mesh.positions.len(), m.mesh.triangles.len(), m.mesh.parts.len());
    let surface = if shells { "shells" } else { "union" };
    if a.json {
        let mut j = serde_json::json!({
            "file": a.out.display().to_string(), "vertices": vertices, "triangles": triangles,
            "closed_parts": parts, "certified": m.mesh.certified, "tolerance": a.tolerance,
            "surface": surface,
        });
        if let Some(r) = &report {
            j["union"] = union_json(r);
        }
        println!("{j}");
    } else {
        println!(
            "{}: {surface}, {vertices} vertices, {triangles} triangles, {parts} closed parts, certified Hausdorff bound {:e} (asked {:e})",
            a.out.display(),
            m.mesh.certified,
            a.tolerance
        );
    }
    // Warnings go to stderr with `--json` too: the summary holds the numbers, not the why.
    // A bound that is not a number is over the tolerance as well.
    if m.mesh.certified > a.tolerance || m.mesh.certified.is_nan() {
        let why = match &report {
            Some(r) => format!(
                "{} triangles where tubes meet stay over it (at a narrow crease the bound is the sagitta over sin(β/2), least {:.2e} in this mesh; where three tubes meet, their channel magnifies it; see docs/design/union-mesh.md)",
                r.outside, r.min_sin_half
            ),
            None => "see docs/design/union-mesh.md".to_string(),
        };
        eprintln!("warning: the certified bound {:e} exceeds the tolerance: {why}", m.mesh.certified);
    }
    if let Some(e) = report.as_ref().and_then(|r| r.refused_estimate) {
        let limit = memory_limit.map_or_else(String::new, |l| format!(", {}", bytes(l)));
        eprintln!(
            "warning: the refinement stopped: the next build's estimated peak, {}, exceeds the memory limit{limit} (raise --memory-limit, or the tolerance)",
            bytes(e)
        );
    }
    Ok(())
}

/// The union's certificate in the JSON summary.
fn union_json(r: &UnionReport) -> serde_json::Value {
    serde_json::json!({
        "tries": r.tries, "sagitta": r.sagitta, "depth": r.depth, "out": r.out,
        "over_tolerance": r.outside, "min_sin_half": r.min_sin_half,
        "subdivisions": [r.subdiv.0, r.subdiv.1], "runs": r.runs, "ring": [r.ring.0, r.ring.1],
        "input_triangles": r.hull_triangles, "refused_estimate": r.refused_estimate,
    })
}

/// A byte count for a message: GB from 1 GB, MB below.
fn bytes(b: u64) -> String {
    if b >= 1_000_000_000 {
        format!("{:.1} GB", b as f64 / 1e9)
    } else {
        format!("{:.0} MB", b as f64 / 1e6)
    }
}
