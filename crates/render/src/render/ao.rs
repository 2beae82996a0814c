//! Ambient occlusion: the fraction of cosine-weighted hemisphere directions from a shaded
//! point `q` (normal `n`) that meet a tube within the distance `D`, estimated either by rays
//! through the [`Tracer`] ([`ray_occlusion`], the reference) or by voxel cone tracing through
//! the occupancy pyramid ([`ConeAo`], Crassin et al.'s voxel cone tracing on Kraaijeveld et
//! al.'s occupancy, [`Pyramid`]), or through Kanzler et al.'s LoD opacities of the quantized
//! lines ([`ConeAo::build_lod`], the same cones).
//!
//! # Cone tracing
//! `N` cones with axes `aᵢ` from a Vogel spiral on the unit disc lifted to the hemisphere
//! (Malley's method: equal cosine-weighted measure `1/N` per axis) and half-angle `θ` with
//! `cos θ = 1 − 1/N` (the `N` cones' solid angles add up to the hemisphere's `2π`). Each cone
//! starts at the apex `q′ = q + s₀·n` and samples its axis points `x(t) = q′ + t·aᵢ`,
//! `t = 0, …, ≤ D`: at `t` it reads the one voxel containing `x(t)` of the finest level `L`
//! whose side `w = 2ᴸh` has `√3·w ≤ t·tan θ` (level 0 when none has), turns its occupancy
//! `o` into the step's opacity ("Opacity" below), multiplies the cone's transmittance by
//! the step's and advances `t` by `w`. The cone's occlusion is `1 −` its transmittance; the point's is the mean
//! over the cones.
//!
//! # What a sample can see (the footprint contract the tests check)
//! Every point of the voxel read at `x(t)` is within `√3·w ≤ max(t·tan θ, √3·h)` of `x(t)`,
//! and a voxel is non-zero only if a base voxel centre inside it has non-zero occupancy, i.e.
//! lies within `h/2` of a tube (radii clamped up to `r_min`, the PWAA clamp, see
//! [`tubecast::voxel::occupancy`]). So a sample reads 0 unless a (clamped) tube comes within
//! `reach(t) = max(t·tan θ, √3·h) + h/2` of `x(t)`.
//!
//! *The normal offset* `s₀ = start·h` (default 2.5 voxels) is what keeps a surface from
//! occluding itself: for a convex tube, the tube lies below the tangent plane at `q`, `x(t)` is
//! `s₀ + t·(aᵢ·n)` above it, and `s₀ ≥ √3·h + h/2` makes the near samples blind to it; far
//! samples are blind to it when `aᵢ·n ≥ tan θ − (s₀ − h/2)/D` (the two sides are linear in
//! `t`). So on a convex tube only the cones near the horizon can report occlusion, and their
//! share shrinks to 0 as `N` grows (`tan θ ~ √(2/N)`); `tests/render/ao_cone.rs` checks the bound.
//! The price is contact occlusion: tubes within `s₀` of `q` are seen only through coarse
//! samples. *Full voxels:* a base voxel whose centre is at least `h/2` inside one tube reads
//! 1, so a cone whose sample lies `(√3 + 1)·h/2` inside a tube is fully occluded.
//!
//! # Opacity
//! A sample of occupancy `o` read with step `Δt = w` multiplies the transmittance by
//! `(1 − o)^(w/ℓ)`, `ℓ = min(w, 2r̄)`. For tubes at least half a voxel thick (`2r̄ ≥ w`) this is
//! the volume fraction as the step's opacity. Thin tubes block more rays than their volume:
//! random lines of radius `r` and volume fraction `o` have `o/(πr²)` length per volume, each
//! unit of which blocks a cross-section `2r·π/4` on average over directions, so rays are
//! stopped at the rate `o/(2r)` and a step of `w` lets `≈ e^{−o·w/(2r)} ≈ (1 − o)^{w/(2r)}`
//! through. With mixed radii the rate is `o/(2r̄)`, `r̄ = Σ L r²/Σ L r` (length-weighted);
//! one `r̄` per scene. Either way `o = 0` stays fully open and `o = 1` fully opaque, so the
//! contract above holds for both. `ConeParams::lines = false` keeps the plain volume model.
//!
//! # Cost and error
//! Per cone, `t` grows geometrically once the levels rise (`Δt = w ≥ t·tan θ/(2√3)`), so a cone
//! takes `O(D/h)` samples at level 0 for narrow cones and `O(log(D/h)/tan θ)` beyond. The occupancy is a density, not
//! the lines: the estimate ignores where in a voxel the tubes lie, and misses contact
//! occlusion within the apex offset, so it is biased low where neighbours are close;
//! `tubecast-lab voxel-ao` charts the error against the ray reference against the cost.

use crate::accel::grid::Pyramid;
use crate::accel::Tracer;
use crate::scene::generate::Rng;
use crate::scene::Scene;
use tubecast::{Ray, V3};

mod lod;

/// How [`super::render`] estimates ambient occlusion (with [`super::Options::ao`] samples).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AoMethod {
    /// `ao` cosine-weighted rays per pixel through the tracer ([`ray_occlusion`]).
    #[default]
    Rays,
    /// `ao` cones per pixel through the occupancy pyramid ([`ConeAo`]).
    Cone,
    /// `ao` cones per pixel through Kanzler's LoD opacities of the scene's quantized lines
    /// ([`ConeAo::build_lod`]).
    Lod,
}

/// An orthonormal pair `(b₁, b₂)` completing the unit `n` to a frame.
fn frame(n: V3<f64>) -> (V3<f64>, V3<f64>) {
    let t0 = if n.x.abs() < 0.9 { V3::new(1.0, 0.0, 0.0) } else { V3::new(0.0, 1.0, 0.0) };
    let b1 = n.cross(t0).normalize_or_zero();
    (b1, n.cross(b1))
}

/// The fraction of `rays` cosine-weighted random directions around the unit normal `n` from
/// `q` whose ray meets a primitive within `dist` ([`Tracer::any_hit`]), seeded by `seed`.
/// Its standard error is at most `1/(2√rays)`.
///
/// ```
/// use tubecast::V3;
/// use tubecast_render::accel::Bvh;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::render::ray_occlusion;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[-5.0, 0.0, 0.0], [5.0, 0.0, 0.0]], radii: vec![] };
/// let bvh = Bvh::build(Scene::from_polylines(&[line], 1.0, "t").unwrap().primitives());
/// // On top of a lone tube nothing is above: a convex solid never occludes itself.
/// let up = V3::new(0.0, 1.0, 0.0);
/// assert_eq!(ray_occlusion(&bvh, V3::new(0.0, 1.001, 0.0), up, 3.0, 256, 1), 0.0);
/// ```
pub fn ray_occlusion(tracer: &dyn Tracer, q: V3<f64>, n: V3<f64>, dist: f64, rays: u32, seed: u64) -> f64 {
    if rays == 0 {
        return 0.0;
    }
    let mut rng = Rng::new(seed);
    let (b1, b2) = frame(n);
    let mut occ = 0;
    for _ in 0..rays {
        let (u1, u2) = (rng.uniform(), rng.uniform());
        let (r, phi) = (u1.sqrt(), 2.0 * std::f64::consts::PI * u2);
        let d = b1 * (r * phi.cos()) + b2 * (r * phi.sin()) + n * (1.0 - u1).sqrt();
        if tracer.any_hit(&Ray::with_range(q, d, 0.0, dist)) {
            occ += 1;
        }
    }
    occ as f64 / rays as f64
}

/// Cone-tracing settings ([`ConeAo::build`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeParams {
    /// Cones per shaded point (1…1024).
    pub cones: u32,
    /// Base voxels across the occlusion distance `D` (the voxel side is `h = D/voxels`,
    /// coarsened if the scene box would need more than `max_cells`).
    pub voxels: f64,
    /// Normal offset of the cones' apex, in base voxels (module docs; ≥ `√3 + ½` keeps a
    /// convex surface from occluding itself near the apex).
    pub start: f64,
    /// PWAA radius clamp `r_min`, in base voxels.
    pub r_min: f64,
    /// Most base cells.
    pub max_cells: usize,
    /// Opacity model of a sample (module docs, "Opacity"): `true` for lines (extinction
    /// `o/(2r̄)`), `false` for the plain volume fraction.
    pub lines: bool,
}

impl Default for ConeParams {
    fn default() -> Self {
        Self { cones: 16, voxels: 16.0, start: 2.5, r_min: 0.5, max_cells: 1 << 24, lines: true }
    }
}

/// Cone-traced ambient occlusion over a scene's occupancy pyramid (module docs).
///
/// ```
/// use tubecast::V3;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::render::{ConeAo, ConeParams};
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[-5.0, 0.0, 0.0], [5.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 1.0, "t").unwrap();
/// let ao = ConeAo::build(&scene, 3.0, &ConeParams { cones: 64, ..ConeParams::default() });
/// let up = V3::new(0.0, 1.0, 0.0);
/// assert_eq!(ao.occlusion(V3::new(0.0, 1.001, 0.0), up), 0.0); // on top: open
/// assert_eq!(ao.occlusion(V3::new(0.0, 0.0, 0.0), up), 1.0); // on the axis: buried
/// ```
#[derive(Clone, Debug)]
pub struct ConeAo {
    pyramid: Pyramid,
    lo: [f64; 3],
    h: f64,
    dist: f64,
    start: f64,
    tan: f64,
    axes: Vec<[f64; 3]>,
    /// The mean free path scale `2r̄` of the line model (0: a zero-radius scene), or
    /// infinity for the volume-fraction model.
    two_r: f64,
}

/// The `n` cone axes in the frame `(b₁, b₂, normal)` and the half-angle's tangent.
///
/// ```
/// let (axes, tan) = tubecast_render::render::cone_axes(4);
/// assert_eq!(axes.len(), 4);
/// assert!(axes.iter().all(|a| a[2] > 0.0)); // all above the surface
/// assert!((tan - (1.0f64 - 0.75 * 0.75).sqrt() / 0.75).abs() < 1e-15); // cos θ = 1 − 1/4
/// ```
pub fn cone_axes(n: u32) -> (Vec<[f64; 3]>, f64) {
    let n = n.max(1);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let axes = (0..n)
        .map(|i| {
            let r2 = (i as f64 + 0.5) / n as f64;
            let (r, phi) = (r2.sqrt(), golden * i as f64);
            [r * phi.cos(), r * phi.sin(), (1.0 - r2).sqrt()]
        })
        .collect();
    let c = 1.0 - 1.0 / n as f64;
    let tan = if n == 1 { f64::INFINITY } else { (1.0 - c * c).sqrt() / c };
    (axes, tan)
}

/// `r̄ = Σ Lₖ r̄ₖ² / Σ Lₖ r̄ₖ` over the links (length `Lₖ`, mean radius `r̄ₖ`; spheres count
/// with `Lₖ = 2r`): the radius for which a volume fraction `o` of random lines stops rays at the
/// rate `o/(2r̄)` (module docs, "Opacity"); 0 when every radius is 0.
fn effective_radius(scene: &Scene) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..scene.links.len() {
        let l = scene.link(k);
        let r = 0.5 * (l.ra + l.rb);
        let len = (l.b - l.a).length().max(2.0 * r);
        num += len * r * r;
        den += len * r;
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// The base grid of [`ConeAo::build`] for `scene` and distance `dist`: whether there is one
/// (links, a finite positive `dist`), its corner, voxel side (`dist/voxels`, coarsened by 1.1×
/// steps until at most `max_cells` cells) and voxels.
fn grid(scene: &Scene, dist: f64, p: &ConeParams) -> (bool, [f64; 3], f64, [u32; 3]) {
    let st = scene.stats();
    let ok = dist.is_finite() && dist > 0.0 && !scene.links.is_empty() && p.voxels > 0.0;
    let mut h = if ok { dist / p.voxels } else { 1.0 };
    let (mut lo, mut dims) = ([0.0; 3], [1, 1, 1]);
    for _ in 0..200 {
        if !ok {
            break;
        }
        // Non-zero occupancy reaches r_min + ½ voxels beyond a tube: pad by that and one more.
        let pad = (p.r_min.max(0.0) + 1.5) * h;
        lo = st.bounds.0.map(|x| x - pad);
        dims = std::array::from_fn(|i| ((st.bounds.1[i] + pad - lo[i]) / h).ceil().clamp(1.0, 1e9) as u32);
        if dims.iter().map(|&d| d as f64).product::<f64>() <= p.max_cells.max(1) as f64 {
            break;
        }
        h *= 1.1;
    }
    (ok, lo, h, dims)
}

impl ConeAo {
    /// The pyramid of `scene`'s links for occlusion distance `dist` (world units). A scene
    /// without links, or a `dist` that is not finite and positive, gives occlusion 0.
    pub fn build(scene: &Scene, dist: f64, p: &ConeParams) -> Self {
        let (axes, tan) = cone_axes(p.cones.clamp(1, 1024));
        let (ok, lo, h, dims) = grid(scene, dist, p);
        let two_r = if p.lines { 2.0 * effective_radius(scene) } else { f64::INFINITY };
        let r_min = p.r_min.max(0.0) * h;
        let pyramid = if ok { Pyramid::build(scene, lo, h, dims, r_min) } else { Pyramid { levels: Vec::new() } };
        Self { pyramid, lo, h, dist: if ok { dist } else { 0.0 }, start: p.start.max(0.0) * h, tan, axes, two_r }
    }

    /// Base voxel side `h` (world units).
    pub fn voxel_size(&self) -> f64 {
        self.h
    }

    /// The cones' half-angle tangent.
    pub fn tan_half_angle(&self) -> f64 {
        self.tan
    }

    /// The normal offset `s₀` of the apex (world units).
    pub fn apex_offset(&self) -> f64 {
        self.start
    }

    /// Bytes held by the pyramid.
    pub fn memory_bytes(&self) -> usize {
        self.pyramid.levels.iter().map(|l| l.values.len() * 4).sum()
    }

    /// Occlusion in `[0, 1]` at `q` with normal `n` (normalised here); 0 for a zero or
    /// non-finite `n` or `q`.
    pub fn occlusion(&self, q: V3<f64>, n: V3<f64>) -> f64 {
        let n = n.normalize_or_zero();
        let finite = [q.x, q.y, q.z, n.x, n.y, n.z].iter().all(|v| v.is_finite());
        if !finite || n.length2() == 0.0 || self.pyramid.levels.is_empty() {
            return 0.0;
        }
        let (b1, b2) = frame(n);
        let apex = q + n * self.start;
        let sum: f64 = self.axes.iter().map(|a| self.cone(apex, b1 * a[0] + b2 * a[1] + n * a[2])).sum();
        (sum / self.axes.len() as f64).clamp(0.0, 1.0)
    }

    /// One cone's occlusion from `apex` along the unit `d`.
    fn cone(&self, apex: V3<f64>, d: V3<f64>) -> f64 {
        let top = self.pyramid.levels.len() - 1;
        let mut vis = 1.0f64;
        let mut t = 0.0;
        while t <= self.dist && vis > 0.0 {
            // The finest level whose voxel diagonal fits the cone's radius t·tanθ.
            let mut l = 0;
            while l < top && 3f64.sqrt() * self.h * f64::from(2u32 << l) <= t * self.tan {
                l += 1;
            }
            let w = self.h * f64::from(1u32 << l);
            let o = self.sample(l, apex + d * t, w) as f64;
            if o > 0.0 {
                vis *= (1.0 - o).powf(w / w.min(self.two_r));
            }
            t += w;
        }
        1.0 - vis
    }

    /// Occupancy of the level-`l` voxel (side `w`) containing `x`; 0 outside the grid.
    #[inline]
    fn sample(&self, l: usize, x: V3<f64>, w: f64) -> f32 {
        let g = [(x.x - self.lo[0]) / w, (x.y - self.lo[1]) / w, (x.z - self.lo[2]) / w];
        if g.iter().any(|&v| !(v >= 0.0 && v < u32::MAX as f64)) {
            return 0.0;
        }
        self.pyramid.levels[l].get(g.map(|v| v as u32))
    }
}
