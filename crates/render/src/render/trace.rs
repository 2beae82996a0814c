//! Per-pixel work: opaque shading with shadows and ambient occlusion, transparent CSG
//! compositing.

use super::shade::Palette;
use super::{Camera, Options, Shading};
use crate::accel::Tracer;
use crate::scene::Scene;
use tubecast::csg::{union, Tagged};
use tubecast::Hit;
use tubecast::Ray;
use tubecast::V3;

/// Everything the per-pixel work needs.
pub(super) struct Ctx<'a> {
    pub(super) scene: &'a Scene,
    pub(super) bvh: &'a dyn Tracer,
    pub(super) cam: &'a Camera,
    pub(super) opts: &'a Options,
    pub(super) pal: Palette,
    pub(super) light: V3<f64>,
    pub(super) ao_dist: f64,
    pub(super) cone: Option<super::ConeAo>,
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
        let pr = self.bvh.prim(prim);
        1e-3 * pr.max_radius() as f64 + 1e-12 * p.max_abs()
    }

    /// The pixel's colour premultiplied by its alpha (composited over transparent black), its
    /// alpha (accumulated opacity) and its depth.
    pub(super) fn pixel(&self, x: u32, y: u32) -> Px {
        let ray = self.cam.ray(x, y);
        let view = ray.d.normalize_or_zero();
        if self.opts.opacity < 1.0 {
            return self.transparent(&ray, view);
        }
        let Some(hit) = self.bvh.closest_hit(&ray) else {
            return Px { premul: [0.0; 3], alpha: 0.0, depth: f64::INFINITY };
        };
        let (base, cov) = self.pal.color(self.scene, self.opts.color, &self.bvh.prim(hit.id), hit.u);
        if cov < 1.0 {
            return self.faded(x, y, &ray, view);
        }
        Px { premul: self.surface(x, y, &ray, view, (hit.id, hit.t, hit.n), base), alpha: 1.0, depth: hit.t }
    }

    /// The shaded colour of an opaque surface point `(prim, t, n)` of `ray` with base colour
    /// `base`: lighting, shadow and ambient occlusion.
    fn surface(
        &self,
        x: u32,
        y: u32,
        ray: &Ray<f64>,
        view: V3<f64>,
        hit: (u32, f64, V3<f64>),
        base: [f32; 3],
    ) -> [f32; 3] {
        let (prim, t, n) = hit;
        if self.opts.shading == Shading::Flat {
            return base;
        }
        let p = ray.at(t);
        let nf = if n.dot(view) > 0.0 { -n } else { n };
        let eps = self.eps(prim, p);
        let q = p + nf * eps;
        let mut lit = 1.0;
        if self.opts.shadows && nf.dot(self.light) > 0.0 && self.bvh.any_hit(&Ray::new(q, self.light)) {
            lit = 0.0;
        }
        let mut ambient = 1.0;
        if self.opts.ao > 0 {
            ambient = self.ambient(x, y, q, nf);
            lit *= 0.5 + 0.5 * ambient;
        }
        self.shade(base, n, view, lit, ambient)
    }

    /// An opaque render whose nearest surface is a faded thin tube (coverage `α < 1`,
    /// [`super::clamp_thin`]): the exterior entries of the union along the ray are composited
    /// front to back, each shaded as an opaque surface and weighted by its coverage, until a
    /// fully covered surface (or transmittance below 2⁻¹², under half an 8-bit step) ends
    /// the walk. So a faded wire in front of another tube shows that tube through it, in the
    /// share `1 − α` it leaves uncovered, exactly as over the background.
    fn faded(&self, x: u32, y: u32, ray: &Ray<f64>, view: V3<f64>) -> Px {
        let mut entries = self.boundaries(ray);
        entries.retain(|b| b.entering);
        let (mut acc, mut trans) = ([0.0f32; 3], 1.0f32);
        for b in &entries {
            let (base, cov) = self.pal.color(self.scene, self.opts.color, &self.bvh.prim(b.id), b.u);
            over(&mut acc, &mut trans, cov, self.surface(x, y, ray, view, (b.id, b.t, b.n), base));
            if trans < 1.0 / 4096.0 {
                break;
            }
        }
        let depth = entries.first().map_or(f64::INFINITY, |b| b.t);
        Px { premul: acc, alpha: 1.0 - trans, depth }
    }

    /// The unoccluded fraction of the hemisphere around the unit normal `nf` at `q`: by cones
    /// when built, else by `self.opts.ao` cosine-weighted rays seeded by the pixel `(x, y)`.
    fn ambient(&self, x: u32, y: u32, q: V3<f64>, nf: V3<f64>) -> f64 {
        if let Some(cone) = &self.cone {
            return 1.0 - cone.occlusion(q, nf);
        }
        1.0 - super::ray_occlusion(self.bvh, q, nf, self.ao_dist, self.opts.ao, (y as u64) << 32 | x as u64)
    }

    /// Front-to-back compositing of the union's exterior boundaries, each of opacity
    /// `opacity · coverage`: premultiplied colour `Σ Tᵢ·aᵢ·cᵢ` and alpha `1 − Π(1 − aᵢ)`, with
    /// `Tᵢ = Π_{j<i}(1 − aⱼ)` the transmittance in front of boundary `i`.
    fn transparent(&self, ray: &Ray<f64>, view: V3<f64>) -> Px {
        let bounds = self.boundaries(ray);
        let (mut acc, mut trans) = ([0.0f32; 3], 1.0f32);
        for b in &bounds {
            let (base, cov) = self.pal.color(self.scene, self.opts.color, &self.bvh.prim(b.id), b.u);
            over(&mut acc, &mut trans, self.opts.opacity as f32 * cov, self.shade(base, b.n, view, 1.0, 1.0));
        }
        let depth = bounds.first().map_or(f64::INFINITY, |b| b.t);
        Px { premul: acc, alpha: 1.0 - trans, depth }
    }

    /// The exterior boundaries of the union of every primitive's intervals along `ray`, in
    /// increasing `t` within the ray's range.
    fn boundaries(&self, ray: &Ray<f64>) -> Vec<Hit<f64>> {
        let mut ivs: Vec<Tagged<f64>> = Vec::new();
        self.bvh.line_intervals(ray, &mut ivs);
        let mut bounds = Vec::new();
        union(&mut ivs, ray.t_min, ray.t_max, |b| bounds.push(b));
        bounds
    }
}

/// Front-to-back "over": a layer of opacity `a` and colour `c` behind what `acc`
/// (premultiplied colour) and `trans` (transmittance) hold so far.
fn over(acc: &mut [f32; 3], trans: &mut f32, a: f32, c: [f32; 3]) {
    for (acc, c) in acc.iter_mut().zip(c) {
        *acc += *trans * a * c;
    }
    *trans *= 1.0 - a;
}

/// One pixel's result: colour premultiplied by alpha, alpha, depth.
pub(super) struct Px {
    pub(super) premul: [f32; 3],
    pub(super) alpha: f32,
    pub(super) depth: f64,
}
