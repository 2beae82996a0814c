//! Kanzler et al.'s ambient occlusion from the LoD (2018, Sec. 3.4–3.5): the same cones as
//! [`ConeAo::build`], reading the per-level opacities of the quantized lines' [`Lod`] instead
//! of the occupancy pyramid.
//!
//! # Opacity of a sample
//! A level-0 voxel of side `h` holding quantized segments of lengths `lᵢ` of tubes of radius `r`
//! has `α = min(1, Σ 2r·lᵢ/h²)`: the share of a face the tubes cover when light crosses them
//! side-on, i.e. the light a step of `h` through the voxel blocks. A level-`L` voxel averages its
//! 2³ children, so it stands for a step of its own side `w = 2ᴸh`. A cone sample of level `L`
//! (chosen as in [`ConeAo`]) therefore multiplies the cone's transmittance by `1 − α` and
//! advances `t` by `w`: the module's volume model with `α` in place of the occupancy (no
//! thin-line exponent; Kanzler's opacity is already a projected area).
//!
//! # What a sample can see
//! A voxel's `α` is non-zero only if a quantized segment of positive length lies in it (or, at a
//! coarser level, in one of its descendants), and every quantized segment is within the
//! Hausdorff bound `ε` ([`QuantizedLines::max_bound`]) of the exact lines. So a sample at
//! `x(t)` reads 0 unless an exact line comes within `√3·w + ε` of `x(t)`; one reads 1 at level 0
//! when its voxel holds quantized length `≥ h²/(2r)`.

use super::{cone_axes, effective_radius, grid, ConeAo, ConeParams};
use crate::accel::grid::{Level, Pyramid};
use crate::quantized::{scene_lines, Lod, QuantizedLines};
use crate::scene::Scene;

/// Bins per face side of the quantization [`ConeAo::build_lod`] uses (Kanzler's default).
const LOD_BINS: u32 = 16;

impl ConeAo {
    /// Cones over the opacities of `lod` (module docs) for occlusion distance `dist`; the apex
    /// offset is `p.start` voxels of `lod`'s level 0, `p.voxels`, `p.r_min`, `p.max_cells` and
    /// `p.lines` are not used (the LoD fixes its grid and opacity model). An empty `lod` or a
    /// `dist` that is not finite and positive gives occlusion 0.
    ///
    /// ```
    /// use tubecast::V3;
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::quantized::{Lod, QuantizedLines};
    /// use tubecast_render::render::{ConeAo, ConeParams};
    /// // A layer of lines 0.05 apart at height 1: every level-0 voxel of side 0.25 it
    /// // crosses is opaque (5 lines × 2·0.05·0.25 / 0.25² = 2 ≥ 1).
    /// let lines: Vec<Polyline> = (0..=160)
    ///     .map(|k| { let y = -4.0 + 0.05 * k as f64; Polyline { points: vec![[-4.0, y, 1.0], [4.0, y, 1.0]], radii: vec![] } })
    ///     .collect();
    /// let q = QuantizedLines::new(&lines, [-4.125, -4.125, -0.125], 0.25, [33, 33, 6], 16);
    /// let ao = ConeAo::from_lod(&Lod::build(&q, 0.05), 4.0, &ConeParams { cones: 64, ..ConeParams::default() });
    /// let up = V3::new(0.0, 0.0, 1.0);
    /// assert!(ao.occlusion(V3::new(0.0, 0.0, 0.0), up) > 0.8); // under the layer: mostly shut
    /// assert_eq!(ao.occlusion(V3::new(0.0, 0.0, 1.5), up), 0.0); // above it: open
    /// ```
    pub fn from_lod(lod: &Lod, dist: f64, p: &ConeParams) -> Self {
        let (axes, tan) = cone_axes(p.cones.clamp(1, 1024));
        let ok = dist.is_finite() && dist > 0.0 && !lod.levels.is_empty();
        let levels = if ok {
            lod.levels.iter().map(|l| Level { dims: l.dims, values: l.opacity.clone() }).collect()
        } else {
            Vec::new()
        };
        let h = lod.levels.first().map_or(1.0, |l| l.h);
        Self {
            pyramid: Pyramid { levels },
            lo: lod.lo,
            h,
            dist: if ok { dist } else { 0.0 },
            start: p.start.max(0.0) * h,
            tan,
            axes,
            two_r: f64::INFINITY,
        }
    }

    /// Kanzler's AO for `scene`: its chains quantized ([`scene_lines`], 16 bins per face side) on
    /// the grid [`ConeAo::build`] would use (`dist/p.voxels`, at most `p.max_cells` cells),
    /// their [`Lod`] with the scene's effective line radius, and [`ConeAo::from_lod`].
    ///
    /// ```
    /// use tubecast::V3;
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::render::{ConeAo, ConeParams};
    /// use tubecast_render::scene::Scene;
    /// let line = Polyline { points: vec![[-5.0, 0.0, 0.0], [5.0, 0.0, 0.0]], radii: vec![] };
    /// let scene = Scene::from_polylines(&[line], 0.1, "t").unwrap();
    /// let ao = ConeAo::build_lod(&scene, 3.0, &ConeParams::default());
    /// let up = V3::new(0.0, 1.0, 0.0);
    /// assert_eq!(ao.occlusion(V3::new(0.0, 2.0, 0.0), up), 0.0); // above the line: open
    /// assert!(ao.occlusion(V3::new(0.0, -1.0, 0.0), up) > 0.0); // below it: partly shut
    /// ```
    pub fn build_lod(scene: &Scene, dist: f64, p: &ConeParams) -> Self {
        let (ok, lo, h, dims) = grid(scene, dist, p);
        if !ok {
            return Self::from_lod(&Lod { lo, q: LOD_BINS, levels: Vec::new() }, dist, p);
        }
        let (lines, _) = scene_lines(scene);
        let q = QuantizedLines::new(&lines, lo, h, dims, LOD_BINS);
        drop(lines);
        Self::from_lod(&Lod::build(&q, effective_radius(scene)), dist, p)
    }
}
