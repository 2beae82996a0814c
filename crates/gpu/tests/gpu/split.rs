//! A scene split across several bindings per kind (`Gpu::SPLIT`: what a scene over the adapter's
//! storage buffer binding limit gets) answers every query bit for bit as the same scene in one
//! binding: the records are the same bytes and the kernels the same arithmetic, only the binding
//! each record is read from differs. The split is forced on a small scene by capping the
//! per-binding sizes (`Gpu::with_binding_limit`, `with_split_limits`), which also runs each query
//! over several dispatches of rays.

use tubecast::{Hit, Ray, V3};
use tubecast_gpu::{render_gpu, Gpu, GpuError, GpuScene, Walk};
use tubecast_render::accel::WideBvh;
use tubecast_render::render::{Camera, Options};
use tubecast_render::scene::generate::Rng;
use tubecast_render::scene::{Model, Scene};

/// Bytes of one tree node and one primitive record on the GPU (`crate::scene`'s `GpuNode`,
/// `GpuPrim`).
const NODE: u64 = 256;
const PRIM: u64 = 48;

/// The nodes' and the primitives' records of `bvh` as uploaded (a spline item takes two
/// primitive records).
fn records(bvh: &WideBvh, model: Model) -> (u64, u64) {
    let ex = bvh.export();
    let per_item = if model == Model::Splines { 2 } else { 1 };
    (ex.nodes.len() as u64, per_item * ex.item_prims.len() as u64)
}

/// A cap that splits `n` records of `size` bytes into three or four bindings, half a record
/// over a whole number of them (the split must round down to record boundaries).
fn cap(n: u64, size: u64) -> u64 {
    n.div_ceil(Gpu::SPLIT as u64) * size + size / 2
}

fn key(h: &Option<Hit<f64>>) -> Option<(u64, u32, [u64; 3], u64, bool)> {
    h.map(|h| (h.t.to_bits(), h.id, [h.n.x.to_bits(), h.n.y.to_bits(), h.n.z.to_bits()], h.u.to_bits(), h.entering))
}

/// Rays aimed near random nodes, from 40 away or from the node itself (inside the tubes).
fn rays(scene: &Scene, n: usize) -> Vec<Ray<f64>> {
    let mut rng = Rng::new(11);
    (0..n)
        .map(|k| {
            let p = crate::near_node(&mut rng, scene);
            let d = V3::from(rng.unit());
            let o = if k % 2 == 0 { p - d * 40.0 } else { p };
            Ray::with_range(o, d, 0.0, 60.0)
        })
        .collect()
}

/// The device with the scene's nodes and primitives capped into 3–4 bindings each, and every
/// binding (rays and outputs too) at most 16 KiB: a query of a few hundred rays runs in several
/// dispatches.
fn split_gpu(bvh: &WideBvh, model: Model) -> Option<Gpu> {
    let (nodes, prims) = records(bvh, model);
    let gpu = crate::gpu("split")?;
    let limit = (16 << 10).max(cap(nodes, NODE)).max(cap(prims, PRIM));
    Some(gpu.with_binding_limit(limit).with_split_limits(cap(nodes, NODE), cap(prims, PRIM)))
}

/// The tree walk's closest hits of the whole and the split upload, ray by ray bit for bit;
/// returns how many rays hit.
fn same_closest_hits(whole: &GpuScene, split: &GpuScene, rays: &[Ray<f64>]) -> usize {
    let (a, b) = (whole.closest_hits(rays, Walk::Tree).unwrap(), split.closest_hits(rays, Walk::Tree).unwrap());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(key(x), key(y), "ray {k}: closest hit, whole {x:?}, split {y:?}");
    }
    a.iter().filter(|h| h.is_some()).count()
}

#[test]
fn a_split_scene_answers_as_the_whole_one() {
    let scene = crate::fur();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let Some(whole_gpu) = crate::gpu("a_split_scene_answers_as_the_whole_one") else { return };
    let Some(split_gpu) = split_gpu(&bvh, Model::Links) else { return };
    let whole = GpuScene::upload(&whole_gpu, &bvh).unwrap();
    let split = GpuScene::upload(&split_gpu, &bvh).unwrap();
    assert_eq!(whole.bindings(), [1, 1]);
    let [nb, pb] = split.bindings();
    assert!(nb >= 3 && pb >= 3, "the split scene takes {nb} node and {pb} primitive bindings");
    assert_eq!(split.bytes(), whole.bytes());

    let rays = rays(&scene, 400);
    let hits = same_closest_hits(&whole, &split, &rays);
    assert!(hits > 100, "{hits} hits of {}: the test says little", rays.len());
    let n = 100;
    let (a, b) =
        (whole.closest_hits(&rays[..n], Walk::Brute).unwrap(), split.closest_hits(&rays[..n], Walk::Brute).unwrap());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(key(x), key(y), "ray {k}: brute force, whole {x:?}, split {y:?}");
    }
    assert_eq!(whole.any_hits(&rays).unwrap(), split.any_hits(&rays).unwrap(), "any hits");
    let (a, b) = (whole.first_pieces(&rays).unwrap(), split.first_pieces(&rays).unwrap());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        let pk = |p: &Option<tubecast_gpu::Piece>| p.map(|(e, x)| (key(&Some(e)), key(&Some(x))));
        assert_eq!(pk(x), pk(y), "ray {k}: first piece, whole {x:?}, split {y:?}");
    }
    let (a, b) = (whole.line_intervals(&rays).unwrap(), split.line_intervals(&rays).unwrap());
    let mut ivs = 0;
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        let bits = |l: &Vec<tubecast::csg::Tagged<f64>>| {
            let mut v: Vec<_> = l.iter().map(|t| (t.id, t.iv.entry.t.to_bits(), t.iv.exit.t.to_bits())).collect();
            v.sort_unstable();
            v
        };
        assert_eq!(bits(x), bits(y), "ray {k}: line intervals");
        ivs += x.len();
    }
    // More intervals than one 16 KiB output binding holds (an entry and an exit of 32 bytes each):
    // the list ran in several dispatches.
    assert!(ivs > 256, "{ivs} line intervals");

    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 64, 48).unwrap();
    let opts = Options::default();
    let (a, b) = (
        render_gpu(&whole, &scene, &bvh, &cam, &opts).unwrap(),
        render_gpu(&split, &scene, &bvh, &cam, &opts).unwrap(),
    );
    for (i, (x, y)) in a.rgb.iter().zip(&b.rgb).enumerate() {
        assert_eq!(x.map(f32::to_bits), y.map(f32::to_bits), "pixel {i}");
    }
    eprintln!(
        "split scene: {nb} node and {pb} primitive bindings of at most {} bytes; {hits} hits, {ivs} intervals of {} rays, {} pixels: all as in one binding",
        split_gpu.max_binding(),
        rays.len(),
        a.rgb.len()
    );
}

/// Spline pieces read their middle control point from a record past the items' (another
/// binding once split): the closest hits still equal the whole scene's. The only test where
/// that read crosses a binding, so it runs in CI although it compiles the spline module for two
/// scenes (some 20 s on lavapipe on a loaded 2-core machine).
#[test]
fn a_split_spline_scene_answers_as_the_whole_one() {
    let mut lines = tubecast_render::scene::generate::furball(12, 8, 2);
    lines.extend(tubecast_render::scene::generate::bundle(8, 8, 3));
    let scene = Scene::from_polylines(&lines, 0.05, "spline split").unwrap();
    let bvh = WideBvh::from_scene(&scene, Model::Splines).unwrap();
    let Some(whole_gpu) = crate::gpu("a_split_spline_scene_answers_as_the_whole_one") else { return };
    let Some(split_gpu) = split_gpu(&bvh, Model::Splines) else { return };
    let whole = GpuScene::upload(&whole_gpu, &bvh).unwrap();
    let split = GpuScene::upload(&split_gpu, &bvh).unwrap();
    let [nb, pb] = split.bindings();
    assert!(nb >= 3 && pb >= 3, "the split scene takes {nb} node and {pb} primitive bindings");
    let rays = rays(&scene, 100);
    let hits = same_closest_hits(&whole, &split, &rays);
    assert!(hits > 20, "{hits} hits of {}: the test says little", rays.len());
    eprintln!(
        "split spline scene: {nb} node and {pb} primitive bindings; {hits} hits of {} rays as in one binding",
        rays.len()
    );
}

/// A scene over `Gpu::SPLIT` bindings of the cap is refused with the figures: nodes and
/// primitives each.
#[test]
fn a_scene_over_its_bindings_is_too_large() {
    let scene = crate::fur();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let (nodes, prims) = records(&bvh, Model::Links);
    let Some(gpu) = crate::gpu("a_scene_over_its_bindings_is_too_large") else { return };
    let big = u64::MAX;
    // One record fewer per binding than four bindings need.
    let short = |n: u64, size: u64| (n.div_ceil(Gpu::SPLIT as u64) - 1) * size;
    let gpu = gpu.with_split_limits(short(nodes, NODE), big);
    match GpuScene::upload(&gpu, &bvh) {
        Err(GpuError::TooLarge { what, bytes, limit }) => {
            assert_eq!((what, bytes), ("tree nodes", nodes * NODE));
            assert_eq!(limit, Gpu::SPLIT as u64 * short(nodes, NODE));
        }
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("{nodes} nodes fit {} bindings of {} bytes", Gpu::SPLIT, short(nodes, NODE)),
    }
    let gpu = gpu.with_split_limits(big, short(prims, PRIM));
    match GpuScene::upload(&gpu, &bvh) {
        Err(e) => {
            let msg = e.to_string();
            let GpuError::TooLarge { what, bytes, limit } = e else { panic!("{msg}") };
            assert_eq!((what, bytes), ("primitives", prims * PRIM));
            assert_eq!(limit, Gpu::SPLIT as u64 * short(prims, PRIM));
            assert!(msg.contains(&bytes.to_string()) && msg.contains(&limit.to_string()), "{msg}");
        }
        Ok(_) => panic!("{prims} primitives fit {} bindings of {} bytes", Gpu::SPLIT, short(prims, PRIM)),
    }
}
