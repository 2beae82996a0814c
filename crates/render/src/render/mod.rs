//! Camera, shading, opaque and transparent compositing, PNG output.
//!
//! * Opaque: one closest-hit query per pixel ([`Tracer::closest_hit`]), Lambert + Blinn-Phong
//!   shading, an optional shadow ray and optional ambient occlusion.
//! * Transparent (`opacity < 1`): every primitive's interval along the pixel's line
//!   ([`Tracer::line_intervals`]) goes through the CSG union ([`union`]); only the exterior
//!   boundaries of the union are composited, front to back, each with opacity `α`, so
//!   surfaces inside other tubes (overlaps at joints and crossings) never show.
//! * Spline tubes ([`Scene::spline_primitives`]) go through the same paths: the closest hit is
//!   the spline kernel's exact first entry, and a spline sub-segment contributes one interval
//!   per connected piece to the union, so the joints between sub-segments and between
//!   segments (where neighbouring sweeps overlap in the joint sphere) add no boundary.
//!
//! * Antialiasing (`Options::aa = N > 1`): `N²` samples per pixel, one per cell of an `N × N`
//!   grid, jittered within the cell; their premultiplied colours and alphas are averaged and
//!   the depth is the nearest any sample sees.
//!
//! Every pixel is composited front to back over transparent black (premultiplied colour and an
//! alpha: the accumulated opacity, including the coverage of faded thin tubes), then over
//! `Options::background` into [`Image::rgb`]; [`Image::alpha`] keeps the alpha for an RGBA PNG
//! with a transparent background ([`Image::write_png_rgba`], straight alpha).
//!
//! Colours are linear RGB in `[0, 1]`; [`Image::to_srgb8`] encodes them for PNG.

mod ao;
mod camera;
mod colormap;
mod error;
mod image;
mod legend;
mod options;
mod shade;
mod thin;
mod trace;

pub use ao::{cone_axes, ray_occlusion, AoMethod, ConeAo, ConeParams};
pub use camera::{Camera, Preset, View};
pub use colormap::{value_range, Colormap};
pub use error::RenderError;
pub use image::Image;
pub use legend::{contrasting_ink, label as legend_label};
pub use options::{ColorBy, Options, Shading};
pub use thin::clamp_thin;

#[allow(unused_imports)] // documentation links
use crate::accel::Bvh;
use crate::accel::Tracer;
use crate::scene::Scene;
use rayon::prelude::*;
use shade::Palette;
use trace::Ctx;
#[allow(unused_imports)] // documentation links
use tubecast::csg::union;
use tubecast::V3;

/// Render `scene` through any [`Tracer`] over its primitives (e.g. its BVH `bvh`, built from [`Scene::primitives`] for links or
/// [`Scene::spline_primitives`] for spline tubes) through `cam`.
/// Rows run in parallel (rayon); `opts.progress` shows a progress bar on stderr.
pub fn render(scene: &Scene, bvh: &dyn Tracer, cam: &Camera, opts: &Options) -> Result<Image, RenderError> {
    opts.validate()?;
    let (w, h) = (cam.width, cam.height);
    // Light from the camera's upper left, slightly behind it.
    let light = (cam.up * 0.6 - cam.right * 0.4 - cam.forward * 0.7).normalize_or_zero();
    let st = scene.stats();
    let diag = (V3::from(st.bounds.1) - V3::from(st.bounds.0)).length();
    let ao_dist = 0.1 * diag;
    let cp = ConeParams { cones: opts.ao, ..ConeParams::default() };
    let cone = match opts.ao_method {
        _ if opts.ao == 0 => None,
        AoMethod::Rays => None,
        AoMethod::Cone => Some(ConeAo::build(scene, ao_dist, &cp)),
        AoMethod::Lod => Some(ConeAo::build_lod(scene, ao_dist, &cp)),
    };
    let cams = sample_cameras(cam, opts.aa);
    let bar = match opts.progress {
        true => indicatif::ProgressBar::new(h as u64 * cams.len() as u64),
        false => indicatif::ProgressBar::hidden(),
    };
    let n = (w * h) as usize;
    // Per pixel, summed over the samples: premultiplied colour, alpha; the nearest depth.
    let (mut premul, mut alpha, mut depth) = (vec![[0.0f32; 3]; n], vec![0.0f32; n], vec![f64::INFINITY; n]);
    let (mut pal, mut cone) = (Palette::new(scene), cone);
    for c in &cams {
        let ctx = Ctx { scene, bvh, cam: c, opts, pal, light, ao_dist, cone };
        let rows = premul
            .par_chunks_mut(w as usize)
            .zip(alpha.par_chunks_mut(w as usize))
            .zip(depth.par_chunks_mut(w as usize));
        rows.enumerate().for_each(|(y, ((row, arow), drow))| {
            for x in 0..w as usize {
                let p = ctx.pixel(x as u32, y as u32);
                row[x] = std::array::from_fn(|k| row[x][k] + p.premul[k]);
                arow[x] += p.alpha;
                drow[x] = drow[x].min(p.depth);
            }
            bar.inc(1);
        });
        (pal, cone) = (ctx.pal, ctx.cone);
    }
    bar.finish_and_clear();
    let bg = opts.background;
    let share = 1.0 / cams.len() as f32;
    let rgb = premul
        .iter()
        .zip(alpha.iter_mut())
        .map(|(p, a)| {
            *a *= share;
            // Over the background: premultiplied colour + (1 − α)·background.
            std::array::from_fn(|k| p[k] * share + (1.0 - *a) * bg[k])
        })
        .collect();
    Ok(Image { width: w, height: h, rgb, alpha, depth, background: bg })
}

/// The cameras of the `aa × aa` samples of every pixel: one per cell of an `aa × aa` grid over
/// the pixel, at a point of the cell drawn by SplitMix64 (the same for every pixel, so the
/// image is deterministic and free of per-pixel noise); `aa = 1`: the camera itself (pixel
/// centres).
fn sample_cameras(cam: &Camera, aa: u32) -> Vec<Camera> {
    use rand_xoshiro::rand_core::{RngCore, SeedableRng};
    if aa <= 1 {
        return vec![*cam];
    }
    let mut rng = rand_xoshiro::SplitMix64::seed_from_u64(u64::from(aa));
    // 53 random bits as a number in [0, 1).
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let n = aa as f64;
    (0..aa * aa)
        .map(|s| {
            let (i, j) = ((s % aa) as f64, (s / aa) as f64);
            let (dx, dy) = ((i + unit()) / n - 0.5, (j + unit()) / n - 0.5);
            cam.offset(dx, dy)
        })
        .collect()
}
