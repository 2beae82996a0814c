//! `render` on the GPU against the CPU render, pixel by pixel, on the shipped tractogram and a
//! generated neuron assembly.
//!
//! Tolerance. Both renders shade with the same code (the GPU only answers the rays), so a
//! pixel's colours differ only through its hit. Where the CPU and the GPU hit the same
//! primitive, the colour `base·(0.25 + 0.75·n·l) + 0.35·(n·h)⁴⁸` (`Shading::Lit`, no shadow or AO)
//! moves by at most `(0.75 + 0.35·48)·|Δn| < 18·|Δn|` per channel, and the two normals, taken
//! on one primitive (surface curvature at most `1/ρ`, [`crate::curvature_radius`]) at hit points `|Δx| ≤ (E_gpu + E_cpu + 2δ)/γ` apart
//! (the tree test's analysis; `γ` the incidence cosine), differ by `|Δx|/r` plus the kernels'
//! own few-`ε` rounding of a unit vector: the per-pixel tolerance is
//! `18·((E_gpu + E_cpu + 2δ)/(γ·ρ) + 64ε)`. Where the two hit different primitives or only one
//! hits, the primary ray must graze (the tree test's band); those pixels are counted.
//!
//! Transparent renders composite every union boundary along the ray, `Σ Tᵢ·aᵢ·cᵢ` with
//! `Σ Tᵢ·aᵢ ≤ 1` and `aᵢ` the layer's opacity (its primitive's, not its hit point's). Where the
//! GPU's boundaries pair up with the CPU's (same count, link and direction, each `t` within
//! `(E_gpu + E_cpu + 2δ)/(γ·|d|)`: the `--query all` test's pairing), the `aᵢ` and so the `Tᵢ`
//! are the same and the pixel differs by at most the largest layer's tolerance above. Pixels
//! whose boundaries do not pair up (a graze or near-touch: that test explains each) are counted.

use crate::{bound32, ov};
use std::collections::HashMap;
use std::path::Path;
use tubecast::V3;
use tubecast_gpu::{render_gpu, GpuScene, Walk};
use tubecast_oracle::Line;
use tubecast_render::accel::{crossings_table, Tracer, WideBvh};
use tubecast_render::render::{clamp_thin, render, Camera, Options};
use tubecast_render::scene::generate;
use tubecast_render::scene::{Model, Scene};

fn check(scene: &Scene, name: &str) {
    check_model(scene, Model::Links, true, name);
}

/// [`check`] of the primitives of `model` (`E` for spline pieces: [`crate::bound`]), with or
/// without the shadow/AO and transparent renders (`full`).
pub(crate) fn check_model(scene: &Scene, model: Model, full: bool, name: &str) {
    let Some(gpu) = crate::gpu(name) else { return };
    let bvh = WideBvh::from_scene(scene, model).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    let delta = gs.band();
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 160, 120).unwrap();
    let opts = Options::default();
    let cpu = render(scene, &bvh, &cam, &opts).unwrap();
    let img = render_gpu(&gs, scene, &bvh, &cam, &opts).unwrap();
    let rays: Vec<_> = (0..cam.height).flat_map(|y| (0..cam.width).map(move |x| cam.ray(x, y))).collect();
    let hits = gs.closest_hits(&rays, Walk::Tree).unwrap();
    let (mut worst, mut grazes, mut covered) = (0.0f64, 0, 0);
    for (i, ray) in rays.iter().enumerate() {
        let (g, c) = (hits[i], bvh.closest_hit(ray));
        let diff = (0..3).map(|k| (img.rgb[i][k] - cpu.rgb[i][k]).abs()).fold(0.0f32, f32::max) as f64;
        match (g, c) {
            (Some(g), Some(c)) if g.id == c.id => {
                let p = bvh.prim(g.id);
                let gamma = c.n.dot(ray.d * (1.0 / ray.d.length())).abs();
                let e = 2.0 * bound32(&p, ray) + 2.0 * delta;
                let tol = 18.0 * (e / (gamma * crate::curvature_radius(&p)) + 64.0 * f64::from(f32::EPSILON));
                assert!(diff <= tol, "{name} pixel {i}: colour differs by {diff:e} > {tol:e} (γ {gamma:e})");
                worst = worst.max(diff);
                covered += 1;
            }
            (None, None) => assert!(diff == 0.0, "{name} pixel {i}: background differs by {diff:e}"),
            (g, c) => {
                // Only a graze may change what the pixel sees: one of the hits' primitives is
                // passed within the band.
                let line = Line { o: ov(ray.o), d: ov(ray.d) };
                let grazed = [g, c].iter().flatten().any(|h| {
                    let p = bvh.prim(h.id);
                    crate::gap(&p, &line).abs() <= 2.0 * bound32(&p, ray) + delta
                });
                let same_t = matches!((g, c), (Some(g), Some(c)) if (g.t - c.t).abs() * ray.d.length()
                    <= 2.0 * (bound32(&bvh.prim(g.id), ray) + bound32(&bvh.prim(c.id), ray) + delta)
                        / c.n.dot(ray.d * (1.0 / ray.d.length())).abs().max(1e-12));
                assert!(grazed || same_t, "{name} pixel {i}: GPU {g:?} CPU {c:?} outside the band");
                grazes += 1;
            }
        }
    }
    assert!(covered > 100, "{name}: {covered} pixels on tubes");
    eprintln!("{name}: {covered} tube pixels, max colour difference {worst:e} (linear); {grazes} graze pixels");
    if !full {
        return;
    }
    // Shadows and AO go through the GPU too: the image must come back, and mostly agree.
    let full = Options { shadows: true, ao: 4, ..opts };
    let cpu = render(scene, &bvh, &cam, &full).unwrap();
    let img = render_gpu(&gs, scene, &bvh, &cam, &full).unwrap();
    let off = cpu.rgb.iter().zip(&img.rgb).filter(|(a, b)| (0..3).any(|k| (a[k] - b[k]).abs() > 1.0 / 255.0)).count();
    eprintln!("{name} with a shadow ray and 4 AO rays: {off} of {} pixels differ by over 1/255", cpu.rgb.len());

    // Transparent: every union boundary of the primary rays, from the GPU's line intervals.
    let clear = Options { opacity: 0.4, ..opts };
    layers(&gs, scene, &bvh, &cam, &clear, &format!("{name} transparent"));
}

/// A render whose pixels composite union boundaries (transparent, or faded thin tubes) on the
/// GPU against the CPU's, by the module docs' layered tolerance where the boundaries pair up.
fn layers(gs: &GpuScene<'_>, scene: &Scene, bvh: &WideBvh, cam: &Camera, opts: &Options, name: &str) {
    let cpu = render(scene, bvh, cam, opts).unwrap();
    let img = render_gpu(gs, scene, bvh, cam, opts).unwrap();
    let rays: Vec<_> = (0..cam.height).flat_map(|y| (0..cam.width).map(move |x| cam.ray(x, y))).collect();
    let delta = gs.band();
    let (g_rows, c_rows) = (tubecast_gpu::crossings_table_gpu(gs, bvh, &rays).unwrap(), crossings_table(bvh, &rays));
    let per_ray = |rows: &[[f64; 8]]| {
        let mut m: HashMap<usize, Vec<[f64; 8]>> = HashMap::new();
        for r in rows {
            m.entry(r[0] as usize).or_default().push(*r);
        }
        m
    };
    let (g_rows, c_rows) = (per_ray(&g_rows), per_ray(&c_rows));
    let prim_of: HashMap<u32, u32> = (0..bvh.prim_count() as u32).map(|i| (bvh.prim(i).link, i)).collect();
    let (mut layered, mut unpaired, mut worst) = (0, 0, 0.0f64);
    for (i, ray) in rays.iter().enumerate() {
        let diff = (0..3).map(|k| (img.rgb[i][k] - cpu.rgb[i][k]).abs()).fold(0.0f32, f32::max) as f64;
        let none = Vec::new();
        let (g, c) = (g_rows.get(&i).unwrap_or(&none), c_rows.get(&i).unwrap_or(&none));
        let len = ray.d.length();
        // Each pair's tolerance, or None where the boundaries do not pair up.
        let tols: Option<Vec<f64>> = (g.len() == c.len())
            .then(|| {
                g.iter()
                    .zip(c)
                    .map(|(a, b)| {
                        let p = bvh.prim(prim_of[&(b[5] as u32)]);
                        let e = 2.0 * bound32(&p, ray) + 2.0 * delta;
                        let gamma = V3::new(b[2], b[3], b[4]).dot(ray.d * (1.0 / len)).abs().max(1e-12);
                        let paired = a[5] == b[5] && a[7] == b[7] && (a[1] - b[1]).abs() * len * gamma <= e;
                        paired.then(|| {
                            18.0 * (e / (gamma * crate::curvature_radius(&p)) + 64.0 * f64::from(f32::EPSILON))
                        })
                    })
                    .collect()
            })
            .flatten();
        match tols {
            Some(t) if t.is_empty() => {
                assert!(diff == 0.0, "{name} pixel {i}: background differs by {diff:e}")
            }
            Some(t) => {
                let tol = t.iter().fold(0.0f64, |m, &x| m.max(x));
                assert!(diff <= tol, "{name} pixel {i}: colour differs by {diff:e} > {tol:e}");
                worst = worst.max(diff);
                layered += 1;
            }
            None => unpaired += 1,
        }
    }
    assert!(layered > 100, "{name}: {layered} pixels on tubes");
    eprintln!(
        "{name}: {layered} pixels with paired boundaries, max colour difference {worst:e}; {unpaired} \
         unpaired (graze or near-touch)"
    );
}

#[test]
fn gpu_render_matches_the_cpu_on_standard_trk() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = Scene::load(&root.join("reference/readers/nibabel/standard.trk"), 0.2).unwrap();
    check(&scene, "standard.trk");
}

#[test]
fn gpu_render_matches_the_cpu_on_neurons() {
    let bases: Vec<_> = (0..2).map(generate::base_neuron).collect();
    let scene = Scene::from_swc(&generate::neurons(2, &bases, 5), "neurons").unwrap();
    check(&scene, "neurons");
}

/// Thin tubes widened to a pixel and faded (`clamp_thin`): an opaque render composites the
/// union's entries behind a faded tube, from the GPU's line intervals.
#[test]
fn gpu_render_fades_thin_tubes_as_the_cpu() {
    let Some(gpu) = crate::gpu("gpu_render_fades_thin_tubes_as_the_cpu") else { return };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut scene = Scene::load(&root.join("reference/readers/nibabel/standard.trk"), 0.02).unwrap();
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 160, 120).unwrap();
    let faded = clamp_thin(&mut scene, &cam, 1.5);
    assert!(faded > 0, "no tube was thin enough to fade");
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    layers(&gs, &scene, &bvh, &cam, &Options::default(), &format!("standard.trk, {faded} faded"));
}
