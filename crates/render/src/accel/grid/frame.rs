//! The frame-cost resolution: build + rays × per-ray cost (module docs of `accel::grid`,
//! "Resolution with a build").

use super::SceneSums;
use std::f64::consts::PI;

/// The grid build's costs relative to one primitive test `C_I` (module docs of `accel::grid`,
/// "Resolution with a build"): per cell of the grid and per (voxel, primitive) reference.
///
/// ```
/// use tubecast_render::accel::grid::{BuildCost, BUILD_COST};
/// let free = BuildCost { per_cell: 0.0, per_reference: 0.0 };
/// assert!(BUILD_COST.per_cell > free.per_cell && BUILD_COST.per_reference > free.per_reference);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildCost {
    /// `β_C`: zeroing a counter, one prefix-sum step, a cursor store and the occupancy test of
    /// the block level, per cell.
    pub per_cell: f64,
    /// `β_E`: emitting a (voxel, primitive) pair, counting it and scattering it (two random
    /// atomic updates and a random store), per reference.
    pub per_reference: f64,
}

/// The build costs used by the default grid ([`super::GridParams::rays_per_build`]): from the
/// operation count in the module docs (per cell about a dozen streaming operations, a tenth of a
/// primitive test; per reference two random atomic read-modify-writes and three stores, half a
/// test), not fitted; `tubecast-lab voxel` fits them to measured builds and prints the fit.
/// Its one `--big` run on the report machine gave 0.019 and 0.172 (CPU ns per cell and per
/// reference over the ns of one `Prim::first_hit`): the operation count overrates both, but
/// the fitted values would choose finer grids, and the per-ray side already overrates opaque
/// rays (it counts every ray's full chord), so the counted values are kept.
pub const BUILD_COST: BuildCost = BuildCost { per_cell: 0.1, per_reference: 0.5 };

/// Expected (voxel, primitive) references at voxel side `h`: the Steiner formula of each
/// primitive (a capsule of length `lᵢ`, radius `rᵢ`) grown by a randomly turned voxel cube,
/// over `h³`: `N + (6R + 1.5Λ)/h + 3π·X/h² + W/h³` (module docs).
///
/// ```
/// use tubecast_render::accel::grid::{expected_references, SceneSums};
/// // One point: exactly one voxel. One segment of length 2 at h = 1: 1 + 1.5·2 = 4.
/// let point = SceneSums { count: 1, ..SceneSums::default() };
/// assert_eq!(expected_references(&point, 1.0), 1.0);
/// let segment = SceneSums { count: 1, length: 2.0, ..SceneSums::default() };
/// assert_eq!(expected_references(&segment, 1.0), 4.0);
/// ```
pub fn expected_references(s: &SceneSums, h: f64) -> f64 {
    s.count as f64 + (6.0 * s.radius + 1.5 * s.length) / h + 3.0 * PI * s.cross / (h * h) + s.solid / (h * h * h)
}

/// `dF/dh` of the frame cost `F(h) = β_C·V/h³ + β_E·E(h) + n·c̄·[1.5ρ/h + (π/V)·Σ(rᵢ + h/2)(rᵢ +
/// lᵢ/2 + h/2)]` (the per-primitive constant of the build has no derivative), `c̄ = 4V/S`.
fn slope(s: &SceneSums, volume: f64, chord: f64, rho: f64, b: &BuildCost, rays: f64, h: f64) -> f64 {
    let (h2, h4) = (h * h, h * h * h * h);
    let refs = -(6.0 * s.radius + 1.5 * s.length) / h2 - 6.0 * PI * s.cross / (h2 * h) - 3.0 * s.solid / h4;
    let ray = -1.5 * rho / h2 + PI / volume * (s.radius + 0.25 * s.length + 0.5 * s.count as f64 * h);
    -3.0 * b.per_cell * volume / h4 + b.per_reference * refs + rays * chord * ray
}

/// The voxel side `h > 0` that minimises the frame cost (build plus `rays` rays; module docs,
/// "Resolution with a build") for a grid box of volume `volume` and surface area `area` over
/// primitives with sums `s`, step cost `rho` ([`super::STEP_COST`]) and build costs `build`
/// ([`BUILD_COST`]). The cost is strictly convex in `h`, so the root of its slope is unique;
/// it is found by bisection in `log h` over `[10⁻⁹, 10³]·∛V` (the ends when the root is
/// outside). As `rays → ∞` it tends to [`super::voxel_size_for`]'s side; fewer rays give a
/// larger side. `None` without primitives, volume or area, or with `rays` not positive.
///
/// ```
/// use tubecast_render::accel::grid::{frame_voxel_size_for, BuildCost, SceneSums};
/// // A point in the unit cube (mean chord 2/3), no step cost, only a cell cost of 1:
/// // −3/h⁴ + n·(2/3)·πh/2 = 0 gives h⁵ = 9/(nπ); n = 9/(32π) rays give h = 2.
/// let s = SceneSums { count: 1, ..SceneSums::default() };
/// let cells = BuildCost { per_cell: 1.0, per_reference: 0.0 };
/// let n = 9.0 / (32.0 * std::f64::consts::PI);
/// let h = frame_voxel_size_for(&s, 1.0, 6.0, 0.0, &cells, n).unwrap();
/// assert!((h - 2.0).abs() < 1e-12);
/// ```
pub fn frame_voxel_size_for(
    s: &SceneSums,
    volume: f64,
    area: f64,
    rho: f64,
    build: &BuildCost,
    rays: f64,
) -> Option<f64> {
    let sums = [s.length, s.radius, s.cross, s.solid, rho, build.per_cell, build.per_reference];
    if s.count == 0 || !(volume > 0.0 && area > 0.0 && rays > 0.0) || !sums.iter().all(|x| x.is_finite()) {
        return None;
    }
    let chord = 4.0 * volume / area;
    let f = |h: f64| slope(s, volume, chord, rho, build, rays, h);
    let unit = volume.cbrt();
    let (mut lo, mut hi) = (unit * 1e-9, unit * 1e3);
    let at_lo = f(lo);
    if at_lo.is_nan() || at_lo >= 0.0 {
        return (lo.is_normal()).then_some(lo);
    }
    if f(hi) <= 0.0 {
        return hi.is_finite().then_some(hi);
    }
    // Bisection on the geometric mean: ~40 halvings of log(hi/lo) reach the f64 resolution.
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let h = 0.5 * (lo + hi);
    (h.is_normal() && h > 0.0).then_some(h)
}
