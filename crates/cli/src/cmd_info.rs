//! `tubecast info`: what a scene holds, as a table or one JSON object (the schema is in the
//! CLI's README): streamlines, points, links, bounds, voxel size and space, every data field
//! with its range, the model the renderer would use with these flags and its certified error,
//! and memory.

use crate::args::{Accel, InfoArgs, Surface};
use crate::error::CliError;
use crate::options::extension;
use crate::setup::{self, Plan};
use serde_json::{json, Value};
use std::path::Path;
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::io::{data::Field, stream::open, trk};
use tubecast_render::scene::{Model, PrimKind, Scene};

/// The coordinate units a format defines (by extension).
fn units(input: &Path) -> &'static str {
    match extension(input).as_str() {
        "trk" | "tck" | "trx" => "mm (RAS+ world space)",
        "swc" => "µm (the SWC convention; the file does not state it)",
        _ => "unknown (the format has no units)",
    }
}

/// The voxel grid and space a `.trk` header states (`None` for other formats, which have none,
/// or a header that cannot be read: the load reports that).
fn space(input: &Path) -> Option<Value> {
    if extension(input) != "trk" {
        return None;
    }
    let info = trk::read_info(open(input).ok()?.0, &input.display().to_string()).ok()?;
    let h = info.header;
    Some(json!({
        "voxel_size": h.voxel_size, "dimensions": h.dim,
        "voxel_order": String::from_utf8_lossy(&h.voxel_order).to_string(),
        "vox_to_ras": h.vox_to_ras, "affine": info.affine,
    }))
}

/// Each data field: name, items (per point or per streamline), columns, and the range of the
/// values `--color` would colour by (the Euclidean norm of a field of several columns).
fn fields(fields: &[Field], nodes: usize) -> Vec<Value> {
    fields
        .iter()
        .map(|f| {
            let norms = (0..f.len()).map(|i| (0..f.width).map(|c| f.get(i, c).powi(2)).sum::<f64>().sqrt());
            let finite = |v: f64| v.is_finite().then_some(v);
            let (lo, hi) = norms
                .zip(0..f.len())
                .map(|(n, i)| if f.width == 1 { f.get(i, 0) } else { n })
                .filter_map(finite)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
            let per = if f.len() == nodes && f.name.starts_with("scalar:") { "point" } else { "streamline" };
            let range = (lo <= hi).then(|| json!([lo, hi]));
            json!({"name": f.name, "per": per, "width": f.width, "range": range})
        })
        .collect()
}

/// The model `render` would trace with these flags and its certified error: the name, the
/// primitives' count, and the error in scene units and/or in tube radii (`null` where it does
/// not apply).
fn model(a: &InfoArgs, scene: &Scene) -> Result<Value, CliError> {
    let splines = a.splines;
    Ok(match a.model {
        Surface::Quantized => {
            let (_, s) = crate::quantized::quantize(scene, &a.quant)?;
            json!({"name": "quantized", "primitives": s.segments, "certified_error": s.bound,
                   "certified_error_radii": null, "bound": "derived Hausdorff distance to the exact lines"})
        }
        Surface::Mesh => {
            let eps = a.tolerance.ok_or_else(|| CliError::usage("info --model mesh needs --tolerance EPS"))?;
            let m = setup::with_threads(a.run.threads, || {
                tubecast_render::mesh::tessellate(scene, setup::model(splines), eps)
            })??;
            json!({"name": "mesh", "primitives": m.mesh.triangles.len(), "certified_error": m.mesh.certified,
                   "certified_error_radii": null, "bound": "two-sided Hausdorff distance to the exact tubes"})
        }
        Surface::Exact => match crate::choice::for_info(scene, a.tolerance, a.pixel_error)? {
            Some(c) => json!({
                "name": "choice", "primitives": c.prims.len(), "certified_error": c.worst,
                "certified_error_radii": null, "bound": "worst certified distance of a chosen primitive",
                "spheres": c.spheres, "cylinders": c.cylinders, "cones": c.cones, "spline_pieces": c.splines,
                "merged": c.merged, "fitted": c.fitted,
            }),
            None if splines => {
                let f = scene.spline_fidelity();
                json!({"name": "splines", "primitives": f.faithful_pieces, "certified_error": null,
                       "certified_error_radii": f.faithful_relative,
                       "bound": "distance of the quadratic pieces to the cubic Hermite sweep, in local radii",
                       "pair_certified_error": f.pair_distance, "pair_certified_error_radii": f.pair_relative})
            }
            None => json!({"name": "links", "primitives": scene.links.len(), "certified_error": 0.0,
                           "certified_error_radii": 0.0,
                           "bound": "exact sphere-sweep kernels: no modelling error, f32 rounding only"}),
        },
    })
}

/// `tubecast info`.
pub fn info(a: &InfoArgs) -> Result<(), CliError> {
    if a.model == Surface::Mesh && a.tolerance.is_none() {
        return Err(CliError::usage("info --model mesh needs --tolerance EPS (the mesh's certified bound)"));
    }
    let m = setup::model(a.splines);
    let plan = Plan { model: m, accel: Accel::Bvh, render: None, rays: None };
    let loaded = setup::load(&a.input, &a.radius, (&a.select, &a.run), plan, "counts are zero", true)?;
    let scene = loaded.scene;
    let prims = if a.splines { scene.model_primitives(Model::Splines)? } else { Vec::new() };
    let st = if a.splines { scene.stats_of(&prims) } else { scene.stats() };
    let pieces = prims.iter().filter(|p| p.kind() == PrimKind::Spline).count();
    let bvh = setup::with_threads(a.run.threads, || {
        if a.splines {
            Ok(crate::progress::step("building the 8-wide BVH", || WideBvh::build(prims)))
        } else {
            crate::progress::step("building the compact 8-wide BVH", || WideBvh::from_scene(&scene, Model::Links))
        }
    })??;
    // Streamlines (the trees of an SWC file) are the components of a forest: nodes minus the
    // links that join two of them (an isolated node's link joins none).
    let joining = scene.links.iter().filter(|l| l[0] != l[1]).count();
    let streamlines = scene.nodes.len().saturating_sub(joining);
    let j = json!({
        "file": a.input.display().to_string(),
        "format": extension(&a.input),
        "units": units(&a.input),
        "streamlines": streamlines, "points": scene.nodes.len(),
        "nodes": st.nodes, "links": st.links, "cylinders": st.cylinders, "cones": st.cones,
        "spheres": st.spheres, "splines": st.splines, "spline_pieces": pieces,
        "bounds": (!st.is_empty()).then(|| json!({"min": st.bounds.0, "max": st.bounds.1})),
        "space": space(&a.input),
        "fields": fields(&loaded.fields, scene.nodes.len()),
        "model": model(a, &scene)?,
        "memory": {"scene_bytes": scene.memory_bytes(), "primitives_bvh_bytes": bvh.memory_bytes(),
                   "bvh_nodes": bvh.node_count()},
    });
    if a.json {
        println!("{}", serde_json::to_string_pretty(&j).unwrap_or_default());
        return Ok(());
    }
    print_table(&j, &scene, a.splines);
    Ok(())
}

/// The table: every entry of the JSON object `j`, one per line.
fn print_table(j: &Value, scene: &Scene, splines: bool) {
    let s = |k: &str| match &j[k] {
        Value::String(t) => t.clone(),
        v => v.to_string(),
    };
    for (label, key) in [("file", "file"), ("units", "units"), ("streamlines", "streamlines"), ("nodes", "nodes")] {
        println!("{label:<10} {}", s(key));
    }
    for key in ["links", "cylinders", "cones", "spheres"] {
        println!("{key:<10} {}", s(key));
    }
    if splines {
        let f = scene.spline_fidelity();
        println!("splines    {} ({} quadratic sub-segments)", s("splines"), s("spline_pieces"));
        println!(
            "fidelity   traced: faithful split, {} pieces for ≤ {:.1e} radii from the cubic, certified; \
             Russig's pair would be ≤ {:.3e} radii ({:.3e} absolute)",
            f.faithful_pieces, f.faithful_relative, f.pair_relative, f.pair_distance
        );
    } else {
        println!("splines    {}", s("splines"));
    }
    match &j["bounds"] {
        Value::Null => println!("bounds     none (empty scene)"),
        b => {
            println!("bounds min {}", b["min"]);
            println!("bounds max {}", b["max"]);
        }
    }
    if let Some(sp) = j["space"].as_object() {
        println!("voxels     size {}, dimensions {}, order {}", sp["voxel_size"], sp["dimensions"], sp["voxel_order"]);
    }
    for f in j["fields"].as_array().into_iter().flatten() {
        let range = match f["range"].as_array() {
            Some(r) => format!("{} to {}", r[0], r[1]),
            None => "no finite values".into(),
        };
        println!(
            "field      {} (per {}, {} column(s)): {range}",
            f["name"].as_str().unwrap_or(""),
            f["per"].as_str().unwrap_or(""),
            f["width"]
        );
    }
    let m = &j["model"];
    if m["name"] == "choice" {
        println!(
            "choice     {} primitives: {} spheres, {} cylinders, {} cones, {} spline pieces ({} links merged away, {} fitted away into spline pieces), worst certified error {:e}",
            m["primitives"], m["spheres"], m["cylinders"], m["cones"], m["spline_pieces"], m["merged"], m["fitted"],
            m["certified_error"].as_f64().unwrap_or(f64::NAN)
        );
    }
    let err = |k: &str| m[k].as_f64().map_or("-".to_string(), |v| format!("{v:e}"));
    println!(
        "model      {} ({} primitives): certified error {} (scene units), {} (radii); {}",
        m["name"].as_str().unwrap_or(""),
        m["primitives"],
        err("certified_error"),
        err("certified_error_radii"),
        m["bound"].as_str().unwrap_or("")
    );
    let mem = &j["memory"];
    let (scene_b, bvh_b) =
        (mem["scene_bytes"].as_f64().unwrap_or(0.0), mem["primitives_bvh_bytes"].as_f64().unwrap_or(0.0));
    println!("memory     scene {scene_b} B, primitives + BVH {bvh_b} B ({} 8-wide BVH nodes)", mem["bvh_nodes"]);
    let per = |b: f64| b / j["links"].as_f64().unwrap_or(0.0).max(1.0);
    println!(
        "per link   {:.1} B: scene {:.1} B + primitives and BVH {:.1} B",
        per(scene_b + bvh_b),
        per(scene_b),
        per(bvh_b)
    );
}
