//! Camera, shading, opaque and transparent compositing, PNG output.
//!
//! * Opaque: one closest-hit query per pixel ([`Bvh::closest_hit`]), Lambert + Blinn-Phong
//!   shading, an optional shadow ray and optional ambient occlusion.
//! * Transparent (`opacity < 1`): every primitive's interval along the pixel's line
//!   ([`Bvh::line_intervals`]) goes through the CSG union ([`union`]); only the exterior
//!   boundaries of the union are composited, front to back, each with opacity `α`, so
//!   surfaces inside other tubes (overlaps at joints and crossings) never show.
//! * Spline tubes ([`Scene::spline_primitives`]) go through the same paths: the closest hit is
//!   the spline kernel's exact first entry, and a spline sub-segment contributes one interval
//!   per connected piece to the union, so the joints between sub-segments and between
//!   segments (where neighbouring sweeps overlap in the joint sphere) add no boundary.
//!
//! Colours are linear RGB in `[0, 1]`; [`Image::to_srgb8`] encodes them for PNG.

use crate::accel::Bvh;
use crate::scene::{Prim, PrimKind, Scene};
use rayon::prelude::*;
use std::path::Path;
use tubecast::csg::{union, Boundary, Tagged};
use tubecast::Ray;
use tubecast::V3;

/// A perspective pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: V3<f64>,
    /// Unit forward direction.
    pub forward: V3<f64>,
    /// Unit right direction (image +x).
    pub right: V3<f64>,
    /// Unit up direction (image +y).
    pub up: V3<f64>,
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// A camera or option that cannot be used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderError(pub String);

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for RenderError {}

fn finite3(v: V3<f64>) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` roughly up and vertical field of view
    /// `fov_deg` (in `(0, 180)`). Errors: non-finite input, `eye == target`, `up` parallel to
    /// the view direction, a bad field of view, or a zero-sized image.
    pub fn look_at(
        eye: V3<f64>,
        target: V3<f64>,
        up: V3<f64>,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        if !finite3(eye) || !finite3(target) || !finite3(up) {
            return Err(RenderError("camera eye, target and up must be finite".into()));
        }
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(RenderError(format!("field of view {fov_deg} must be in (0, 180) degrees")));
        }
        if width == 0 || height == 0 || width > 1 << 15 || height > 1 << 15 {
            return Err(RenderError(format!("image size {width}x{height} must be 1..=32768 per side")));
        }
        let f = target - eye;
        if !(f.length() > 0.0) {
            return Err(RenderError("camera eye and look-at point coincide".into()));
        }
        let forward = f.normalize_or_zero();
        let right = forward.cross(up);
        if !(right.length() > 1e-9 * up.length()) {
            return Err(RenderError("camera up direction is zero or parallel to the view direction".into()));
        }
        let right = right.normalize_or_zero();
        let up = right.cross(forward);
        Ok(Self { eye, forward, right, up, fov_deg, width, height })
    }

    /// A camera that frames the box `(lo, hi)`: looking at its centre from the direction
    /// `(0.25, 0.35, 1)` (a three-quarter view from +z), just far enough (plus 5%) that all
    /// eight corners of the box project inside both the vertical and horizontal field of view.
    pub fn fit(lo: [f64; 3], hi: [f64; 3], fov_deg: f64, width: u32, height: u32) -> Result<Self, RenderError> {
        let c = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
        let r = 0.5 * (V3::from(hi) - V3::from(lo)).length();
        if !(r.is_finite() && r > 0.0) {
            return Err(RenderError("scene bounds are empty or not finite".into()));
        }
        let aspect = width.max(1) as f64 / height.max(1) as f64;
        let half_v = (fov_deg.clamp(1e-3, 179.0) * 0.5).to_radians();
        let half_h = (half_v.tan() * aspect).atan();
        let dir = V3::new(0.25, 0.35, 1.0).normalize_or_zero();
        // Orientation only (eye distance 1), to measure the corners in the camera frame.
        let probe = Self::look_at(c + dir, c, V3::new(0.0, 1.0, 0.0), fov_deg, width, height)?;
        let (tv, th) = (half_v.tan(), half_h.tan());
        let mut dist: f64 = 0.0;
        for k in 0..8 {
            let q = V3::new(
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ) - c;
            // A corner at depth (dist + z) is inside when |x| ≤ th·(dist + z) and |y| ≤ tv·(dist + z).
            let z = q.dot(probe.forward);
            dist = dist.max(q.dot(probe.right).abs() / th - z).max(q.dot(probe.up).abs() / tv - z);
        }
        // Keep the eye outside the box's bounding sphere as well.
        let dist = (1.05 * dist).max(1.05 * r);
        Self::look_at(c + dir * dist, c, V3::new(0.0, 1.0, 0.0), fov_deg, width, height)
    }

    /// The primary ray through the centre of pixel `(x, y)` (`y = 0` is the top row). Its
    /// direction is `forward + sx·right + sy·up` (not unit length); `t` is measured in it.
    pub fn ray(&self, x: u32, y: u32) -> Ray<f64> {
        let th = (self.fov_deg * 0.5).to_radians().tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = ((x as f64 + 0.5) / self.width as f64 * 2.0 - 1.0) * th * aspect;
        let sy = (1.0 - (y as f64 + 0.5) / self.height as f64 * 2.0) * th;
        Ray::new(self.eye, self.forward + self.right * sx + self.up * sy)
    }
}

/// How surfaces are coloured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorBy {
    /// Tractography convention: `|unit link direction|` as RGB (x red, y green, z blue); the
    /// curve's unit tangent at the hit for spline tubes.
    Direction,
    /// Radius at the hit (interpolated along the link, or the spline's radius curve), through
    /// a blue→yellow colour map over the scene's node radius range.
    Radius,
    /// SWC structure type (1 soma, 2 axon, 3 basal, 4 apical dendrite, others by palette).
    Type,
    /// One colour.
    Solid([f32; 3]),
}

/// Lighting model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// Ambient + Lambert diffuse + Blinn-Phong specular from a light at the camera's upper left.
    Lit,
    /// The surface colour itself (no lighting): what the compositing tests check.
    Flat,
}

/// Render settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Surface colouring.
    pub color: ColorBy,
    /// Lighting.
    pub shading: Shading,
    /// Surface opacity in `(0, 1]`; below 1 renders transparent tubes with CSG.
    pub opacity: f64,
    /// Ambient-occlusion rays per pixel (0: none). Opaque mode only.
    pub ao: u32,
    /// Trace a shadow ray toward the light. Opaque mode only.
    pub shadows: bool,
    /// Background colour (linear RGB).
    pub background: [f32; 3],
    /// Show a progress bar on stderr.
    pub progress: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            color: ColorBy::Direction,
            shading: Shading::Lit,
            opacity: 1.0,
            ao: 0,
            shadows: false,
            background: [1.0, 1.0, 1.0],
            progress: false,
        }
    }
}

impl Options {
    /// Check the settings: opacity in `(0, 1]`, AO rays ≤ 1024, finite background in `[0, 1]`.
    pub fn validate(&self) -> Result<(), RenderError> {
        if !(self.opacity > 0.0 && self.opacity <= 1.0) {
            return Err(RenderError(format!("opacity {} must be in (0, 1]", self.opacity)));
        }
        if self.ao > 1024 {
            return Err(RenderError(format!("ambient-occlusion rays {} exceed 1024", self.ao)));
        }
        if self.background.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(RenderError("background components must be in [0, 1]".into()));
        }
        if let ColorBy::Solid(c) = self.color {
            if c.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return Err(RenderError("colour components must be in [0, 1]".into()));
            }
        }
        Ok(())
    }
}

/// A rendered image: linear RGB and the depth (ray parameter of the first surface crossing,
/// `+∞` where the pixel sees nothing).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Row-major linear RGB.
    pub rgb: Vec<[f32; 3]>,
    /// Row-major depth in the camera ray's parameter ([`Camera::ray`]).
    pub depth: Vec<f64>,
}

impl Image {
    /// Pixel `(x, y)`.
    pub fn at(&self, x: u32, y: u32) -> [f32; 3] {
        self.rgb[(y * self.width + x) as usize]
    }
    /// 8-bit sRGB bytes, row-major RGB.
    pub fn to_srgb8(&self) -> Vec<u8> {
        let enc = |c: f32| {
            let c = c.clamp(0.0, 1.0);
            let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0 + 0.5) as u8
        };
        self.rgb.iter().flat_map(|p| p.map(enc)).collect()
    }
    /// Write an 8-bit RGB PNG.
    pub fn write_png(&self, path: &Path) -> Result<(), RenderError> {
        let err = |e: String| RenderError(format!("{}: {e}", path.display()));
        let f = std::fs::File::create(path).map_err(|e| err(format!("cannot create: {e}")))?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(f), self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc.write_header().map_err(|e| err(e.to_string()))?;
        w.write_image_data(&self.to_srgb8()).map_err(|e| err(e.to_string()))?;
        w.finish().map_err(|e| err(e.to_string()))
    }
}

/// Per-scene colour lookups.
struct Palette {
    r_lo: f64,
    r_hi: f64,
}

fn colormap(x: f64) -> [f32; 3] {
    // Blue → teal → yellow, piecewise linear in three stops.
    let stops = [[0.15, 0.2, 0.75], [0.1, 0.7, 0.6], [0.98, 0.85, 0.15]];
    let x = x.clamp(0.0, 1.0) * 2.0;
    let i = (x as usize).min(1);
    let f = (x - i as f64) as f32;
    std::array::from_fn(|k| stops[i][k] * (1.0 - f) + stops[i + 1][k] * f)
}

fn type_color(t: i32) -> [f32; 3] {
    match t {
        1 => [0.9, 0.9, 0.9],
        2 => [0.25, 0.45, 0.95],
        3 => [0.9, 0.25, 0.2],
        4 => [0.85, 0.25, 0.85],
        _ => {
            let pal = [[0.3, 0.75, 0.3], [0.95, 0.6, 0.1], [0.4, 0.8, 0.85], [0.6, 0.5, 0.3]];
            pal[t.unsigned_abs() as usize % pal.len()]
        }
    }
}

impl Palette {
    fn new(scene: &Scene) -> Self {
        let (mut r_lo, mut r_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for n in &scene.nodes {
            r_lo = r_lo.min(n.radius);
            r_hi = r_hi.max(n.radius);
        }
        Self { r_lo, r_hi }
    }
    /// Colour of primitive `prim` at its curve parameter `u`.
    fn color(&self, scene: &Scene, by: ColorBy, prim: &Prim, u: f64) -> [f32; 3] {
        let link = prim.link;
        let l = scene.links[link as usize];
        let spline = prim.kind == PrimKind::Spline;
        match by {
            ColorBy::Solid(c) => c,
            ColorBy::Direction => {
                // Spline: the curve's tangent at u; link: the link's direction.
                let d = if spline {
                    prim.quad().cast::<f64>().tangent(u).normalize_or_zero().to_array()
                } else {
                    scene.link_direction(link as usize)
                };
                if d == [0.0; 3] {
                    [0.6, 0.6, 0.6]
                } else {
                    d.map(|v| v.abs() as f32)
                }
            }
            ColorBy::Radius => {
                let r = if spline {
                    prim.quad().cast::<f64>().radius(u)
                } else {
                    let (a, b) = (scene.nodes[l[0] as usize].radius, scene.nodes[l[1] as usize].radius);
                    a + (b - a) * u
                };
                let span = self.r_hi - self.r_lo;
                colormap(if span > 0.0 { (r - self.r_lo) / span } else { 0.5 })
            }
            ColorBy::Type => type_color(scene.nodes[l[1] as usize].kind),
        }
    }
}

/// A small deterministic hash-based generator (per pixel), for AO directions.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        // splitmix64
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Everything the per-pixel work needs.
struct Ctx<'a> {
    scene: &'a Scene,
    bvh: &'a Bvh,
    cam: &'a Camera,
    opts: &'a Options,
    pal: Palette,
    light: V3<f64>,
    ao_dist: f64,
}

impl Ctx<'_> {
    /// Shade a surface point seen along `view` (unit, toward the surface).
    fn shade(&self, base: [f32; 3], n: V3<f64>, view: V3<f64>, lit: f64, ambient: f64) -> [f32; 3] {
        if self.opts.shading == Shading::Flat {
            return base;
        }
        // Face the viewer (exit surfaces of transparent tubes are seen from inside).
        let n = if n.dot(view) > 0.0 { -n } else { n };
        let diff = n.dot(self.light).max(0.0) * lit;
        let h = (self.light - view).normalize_or_zero();
        let spec = n.dot(h).max(0.0).powi(48) * lit;
        let k = (0.25 * ambient + 0.75 * diff) as f32;
        base.map(|c| c * k + 0.35 * spec as f32)
    }

    /// Offset for secondary rays: well above the `f32` kernel's hit error (≈ 2⁻²⁰ of the
    /// primitive's size) and the `f64` position error (≈ 2⁻⁵⁰ of |p|).
    fn eps(&self, prim: u32, p: V3<f64>) -> f64 {
        let pr = &self.bvh.prims[prim as usize];
        1e-3 * pr.max_radius() as f64 + 1e-12 * p.max_abs()
    }

    fn pixel(&self, x: u32, y: u32) -> ([f32; 3], f64) {
        let ray = self.cam.ray(x, y);
        let view = ray.d.normalize_or_zero();
        let bg = self.opts.background;
        if self.opts.opacity < 1.0 {
            return self.transparent(&ray, view);
        }
        let Some(hit) = self.bvh.closest_hit(&ray) else {
            return (bg, f64::INFINITY);
        };
        let base = self.pal.color(self.scene, self.opts.color, &self.bvh.prims[hit.prim as usize], hit.u);
        if self.opts.shading == Shading::Flat {
            return (base, hit.t);
        }
        let p = ray.at(hit.t);
        let nf = if hit.n.dot(view) > 0.0 { -hit.n } else { hit.n };
        let eps = self.eps(hit.prim, p);
        let q = p + nf * eps;
        let mut lit = 1.0;
        if self.opts.shadows && nf.dot(self.light) > 0.0 && self.bvh.any_hit(&Ray::new(q, self.light)) {
            lit = 0.0;
        }
        let mut ambient = 1.0;
        if self.opts.ao > 0 {
            let mut rng = Rng((y as u64) << 32 | x as u64);
            // Orthonormal frame around the normal.
            let t0 = if nf.x.abs() < 0.9 { V3::new(1.0, 0.0, 0.0) } else { V3::new(0.0, 1.0, 0.0) };
            let b1 = nf.cross(t0).normalize_or_zero();
            let b2 = nf.cross(b1);
            let mut occ = 0;
            for _ in 0..self.opts.ao {
                // Cosine-weighted hemisphere direction.
                let (u1, u2) = (rng.next(), rng.next());
                let (r, phi) = (u1.sqrt(), 2.0 * std::f64::consts::PI * u2);
                let d = b1 * (r * phi.cos()) + b2 * (r * phi.sin()) + nf * (1.0 - u1).sqrt();
                if self.bvh.any_hit(&Ray::with_range(q, d, 0.0, self.ao_dist)) {
                    occ += 1;
                }
            }
            ambient = 1.0 - occ as f64 / self.opts.ao as f64;
            lit *= 0.5 + 0.5 * ambient;
        }
        (self.shade(base, hit.n, view, lit, ambient), hit.t)
    }

    fn transparent(&self, ray: &Ray<f64>, view: V3<f64>) -> ([f32; 3], f64) {
        let mut ivs: Vec<Tagged<f64>> = Vec::new();
        self.bvh.line_intervals(ray, &mut ivs);
        let mut bounds: Vec<Boundary<f64>> = Vec::new();
        union(&mut ivs, ray.t_min, ray.t_max, |b| bounds.push(b));
        let a = self.opts.opacity as f32;
        let mut acc = [0.0f32; 3];
        let mut trans = 1.0f32;
        for b in &bounds {
            let base = self.pal.color(self.scene, self.opts.color, &self.bvh.prims[b.id as usize], b.u);
            let c = self.shade(base, b.n, view, 1.0, 1.0);
            for k in 0..3 {
                acc[k] += trans * a * c[k];
            }
            trans *= 1.0 - a;
        }
        let bg = self.opts.background;
        let depth = bounds.first().map_or(f64::INFINITY, |b| b.t);
        (std::array::from_fn(|k| acc[k] + trans * bg[k]), depth)
    }
}

/// Render `scene` (with its BVH `bvh`, built from [`Scene::primitives`] for links or
/// [`Scene::spline_primitives`] for spline tubes) through `cam`.
/// Rows run in parallel (rayon); `opts.progress` shows a progress bar on stderr.
pub fn render(scene: &Scene, bvh: &Bvh, cam: &Camera, opts: &Options) -> Result<Image, RenderError> {
    opts.validate()?;
    let (w, h) = (cam.width, cam.height);
    // Light from the camera's upper left, slightly behind it.
    let light = (cam.up * 0.6 - cam.right * 0.4 - cam.forward * 0.7).normalize_or_zero();
    let st = scene.stats();
    let diag = (V3::from(st.bounds.1) - V3::from(st.bounds.0)).length();
    let ctx = Ctx { scene, bvh, cam, opts, pal: Palette::new(scene), light, ao_dist: 0.1 * diag };
    let bar = if opts.progress { indicatif::ProgressBar::new(h as u64) } else { indicatif::ProgressBar::hidden() };
    let mut rgb = vec![[0.0f32; 3]; (w * h) as usize];
    let mut depth = vec![f64::INFINITY; (w * h) as usize];
    rgb.par_chunks_mut(w as usize).zip(depth.par_chunks_mut(w as usize)).enumerate().for_each(|(y, (row, drow))| {
        for x in 0..w {
            let (c, d) = ctx.pixel(x, y as u32);
            row[x as usize] = c;
            drow[x as usize] = d;
        }
        bar.inc(1);
    });
    bar.finish_and_clear();
    Ok(Image { width: w, height: h, rgb, depth })
}
