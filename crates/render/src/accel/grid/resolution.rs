//! The grid's resolution: a fixed number of cells per primitive, or (the default) the voxel
//! side that minimises a per-ray cost model of the scene (module docs of `accel::grid`,
//! "Resolution").

use super::frame::{frame_voxel_size_for, BUILD_COST};
use super::GridParams;
use crate::scene::{Prim, Shape};

/// `ρ = C_T / C_I`: the cost of one DDA step over a voxel (with its list fetch and the
/// block-level skip test) relative to one primitive test (mailbox check and `f32` link
/// kernel), used by [`voxel_size_for`]. Set from an operation count, not fitted: a step is a
/// compare, an add and a load; a link test a few dozen flops and a square root, about four
/// steps. Short links then get `π/(3ρ) ≈ 4.2` cells each. `tubecast-lab voxel` ("Grid
/// resolution") checks the choice against a sweep of fixed λ.
pub const STEP_COST: f64 = 0.25;

/// The sums over a scene's primitives that the cost model needs (cheap: one pass).
///
/// ```
/// use tubecast_render::accel::grid::SceneSums;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [3.0, 4.0, 0.0]], radii: vec![] };
/// let s = SceneSums::of(&Scene::from_polylines(&[line], 0.5, "tube").unwrap().primitives());
/// assert_eq!((s.count, s.length, s.radius, s.cross), (1, 5.0, 0.5, 0.5 * (0.5 + 2.5)));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneSums {
    /// Number of primitives `N`.
    pub count: usize,
    /// `Λ = Σ lᵢ`: total axis length (a link's centre line, a spline piece's chord).
    pub length: f64,
    /// `R = Σ rᵢ`: total mean radius (a link's `(r_a + r_b)/2`).
    pub radius: f64,
    /// `X = Σ rᵢ·(rᵢ + lᵢ/2)` (the build's reference count, [`super::expected_references`]).
    pub cross: f64,
    /// `W = Σ (π·rᵢ²·lᵢ + 4π·rᵢ³/3)`: total solid volume of the capsules.
    pub solid: f64,
}

impl SceneSums {
    /// The sums over `prims`.
    pub fn of(prims: &[Prim]) -> Self {
        let mut s = Self { count: prims.len(), ..Self::default() };
        for p in prims {
            let (l, r) = match (p.round_cone(), p.shape) {
                // Lengths in f64: an f32 square underflows for links under ~10⁻¹⁹ (and
                // overflows over ~10¹⁹), and the resolution is asked of such scenes too.
                (Some(c), _) => ((c.b.cast::<f64>() - c.a.cast()).length(), 0.5 * (c.ra as f64 + c.rb as f64)),
                (None, Shape::Spline { quad, .. }) => {
                    ((quad.b[2].cast::<f64>() - quad.b[0].cast()).length(), p.max_radius() as f64)
                }
                (None, _) => (0.0, p.max_radius() as f64),
            };
            s.length += l;
            s.radius += r;
            s.cross += r * (r + 0.5 * l);
            s.solid += std::f64::consts::PI * r * r * (l + 4.0 / 3.0 * r);
        }
        s
    }
}

/// The voxel side `h > 0` that minimises the per-ray cost model for a grid box of volume
/// `volume` over primitives with sums `s`, with step cost `rho` ([`STEP_COST`]); the root of
/// `N·h³ + (2R + Λ/2)·h² = (3/π)·ρ·V` (derivation in the module docs of `accel::grid`).
/// `None` without primitives or volume.
///
/// ```
/// use tubecast_render::accel::grid::{voxel_size_for, SceneSums};
/// // One point-like primitive in a box of volume 8π/3 at ρ = 1: h³ = 8, h = 2.
/// let s = SceneSums { count: 1, ..SceneSums::default() };
/// let h = voxel_size_for(&s, 8.0 * std::f64::consts::PI / 3.0, 1.0).unwrap();
/// assert!((h - 2.0).abs() < 1e-12);
/// ```
pub fn voxel_size_for(s: &SceneSums, volume: f64, rho: f64) -> Option<f64> {
    let (n, b) = (s.count as f64, 2.0 * s.radius + 0.5 * s.length);
    let k = 3.0 / std::f64::consts::PI * rho * volume;
    if s.count == 0 || !(k > 0.0 && k.is_finite() && b.is_finite()) {
        return None;
    }
    // f(h) = n·h³ + b·h² − k is increasing and convex on h > 0, and each term alone bounds the
    // root from above: Newton from the smaller bound decreases monotonically onto the root.
    let mut h = (k / n).cbrt().min(if b > 0.0 { (k / b).sqrt() } else { f64::INFINITY });
    for _ in 0..100 {
        let f = (n * h + b) * h * h - k;
        let step = f / ((3.0 * n * h + 2.0 * b) * h);
        h -= step;
        if step <= h * 1e-15 {
            break;
        }
    }
    (h.is_normal() && h > 0.0).then_some(h)
}

/// Voxel side and counts over the box `ext` (extents) for `prims` (module docs,
/// "Resolution"): from [`GridParams::cells_per_prim`] when set, else [`voxel_size_for`] or,
/// with [`GridParams::rays_per_build`], [`frame_voxel_size_for`]; at
/// most [`GridParams::max_cells`] cells. Computed in units of the box diagonal `D` (exact for a
/// power-of-two `D`, and free of under- and overflow for scenes 10⁻³⁰ or 10³⁰ across); a box
/// without extent (no primitives) gets one voxel of side 1.
pub(super) fn resolution(ext: [f64; 3], prims: &[Prim], p: &GridParams) -> (f64, [u32; 3]) {
    resolution_for(ext, prims.len(), || SceneSums::of(prims), p)
}

/// [`resolution`] for `count` primitives whose sums `sums` gives (asked only by the cost
/// models): what the build would choose, known from the scene's statistics alone (the memory
/// estimate's [`GridParams::footprint`]).
pub(super) fn resolution_for(
    ext: [f64; 3],
    count: usize,
    sums: impl FnOnce() -> SceneSums,
    p: &GridParams,
) -> (f64, [u32; 3]) {
    let diag = (ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]).sqrt();
    if count == 0 || !diag.is_normal() {
        return (1.0, [1, 1, 1]);
    }
    let e = ext.map(|x| (x / diag).max(1e-3));
    let volume = e[0] * e[1] * e[2];
    let max_cells = p.max_cells.max(1) as f64;
    let fixed = |lambda: f64| (volume / (lambda * count as f64).clamp(1.0, max_cells)).cbrt();
    let area = 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
    let auto = || {
        let s = sums();
        let (l, r, x, w) = (s.length / diag, s.radius / diag, s.cross / diag / diag, s.solid / diag / diag / diag);
        let unit = SceneSums { length: l, radius: r, cross: x, solid: w, ..s };
        match p.rays_per_build {
            Some(n) if n.is_finite() => frame_voxel_size_for(&unit, volume, area, STEP_COST, &BUILD_COST, n),
            _ => voxel_size_for(&unit, volume, STEP_COST),
        }
    };
    let mut h = match p.cells_per_prim {
        Some(lambda) => fixed(lambda),
        None => auto().map_or(f64::NAN, |h| h.max((volume / max_cells).cbrt())),
    };
    if !h.is_normal() {
        h = e.iter().fold(0.0, |m: f64, &x| m.max(x)); // one voxel over the box
    }
    loop {
        let dims = e.map(|x| ((x / h).ceil().max(1.0)).min(u32::MAX as f64 / 4.0) as u32);
        if dims.iter().map(|&d| d as f64).product::<f64>() <= max_cells {
            return (h * diag, dims);
        }
        h *= 1.05; // rounding up each axis can overshoot the cap by a little
    }
}
