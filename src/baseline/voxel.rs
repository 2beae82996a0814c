//! The voxelizations the conservative round-cone voxelization ([`crate::voxel`]) is measured
//! against, in `tests/kernels/voxel/conservative.rs` and the voxel timing report: every voxel
//! of the link's bounding box (conservative, `O(L³)` for a diagonal link), the voxels its
//! centre segment passes through (not conservative), and Kraaijeveld's Algorithm 1 with the
//! paper's Eq. 1 radius (not conservative for links with three non-zero direction components).
//! Same grid conventions as [`crate::voxel`].

use crate::kernel::link::RoundCone;
use crate::kernel::voxel::{bounds, dda, finite, march, margin, visit_box, Dims, Projection};
use crate::real::Scalar;

/// The AABB baseline: every voxel of the round cone's bounding box (widened by the rounding
/// margin). Conservative, but visits up to `O(L³)` voxels for a diagonal link of length `L`.
///
/// ```
/// use tubecast::baseline::voxel;
/// use tubecast::{RoundCone, V3};
/// let l = RoundCone { a: V3::new(0.5f64, 0.5, 0.5), ra: 0.2, b: V3::new(3.5, 3.5, 0.5), rb: 0.2 };
/// let mut n = 0;
/// voxel::voxelize_aabb(&l, [8, 8, 8], |_| n += 1);
/// assert_eq!(n, 16); // the 4 × 4 × 1 voxels of the box [0.3, 3.7]² × [0.3, 0.7]
/// ```
pub fn voxelize_aabb<T: Scalar>(l: &RoundCone<T>, dims: Dims, mut visit: impl FnMut([u32; 3])) {
    if finite(l) {
        let (lo, hi) = bounds(l, margin(l));
        visit_box(lo, hi, dims, &mut visit);
    }
}

/// The DDA baseline: the voxels the centre segment `a → b` passes through (Amanatides & Woo),
/// ignoring the radii. Not conservative for a tube of positive radius.
///
/// ```
/// use tubecast::baseline::voxel;
/// use tubecast::{RoundCone, V3};
/// let l = RoundCone { a: V3::new(0.5f64, 0.5, 0.5), ra: 0.4, b: V3::new(3.5, 0.5, 0.5), rb: 0.4 };
/// let mut cells = Vec::new();
/// voxel::voxelize_dda(&l, [8, 8, 8], |c| cells.push(c));
/// assert_eq!(cells, [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]);
/// ```
pub fn voxelize_dda<T: Scalar>(l: &RoundCone<T>, dims: Dims, mut visit: impl FnMut([u32; 3])) {
    if !finite(l) {
        return;
    }
    dda(l.a, l.b - l.a, T::zero(), T::one(), dims, |c, _, _| {
        visit(c);
        true
    });
}

/// Algorithm 1 with the paper's projected radii (Kraaijeveld Eq. 1, `R/√(1 − (dᵢ/|d|)²)`)
/// in place of `R·√(1 + (dᵢ/d_{a₀})²)`: kept to show, by test, that it misses voxels of
/// links with three non-zero direction components. Not conservative; do not build on it.
///
/// ```
/// use tubecast::baseline::voxel;
/// use tubecast::{RoundCone, V3};
/// let l = RoundCone { a: V3::new(1.0f64, 1.0, 1.0), ra: 0.3, b: V3::new(5.0, 5.0, 5.0), rb: 0.3 };
/// let (mut eq1, mut ours) = (0, 0);
/// voxel::voxelize_capsule_eq1(&l, [8, 8, 8], |_| eq1 += 1);
/// tubecast::voxel::voxelize_round_cone(&l, [8, 8, 8], |_| ours += 1);
/// assert!(eq1 <= ours);
/// ```
pub fn voxelize_capsule_eq1<T: Scalar>(l: &RoundCone<T>, dims: Dims, visit: impl FnMut([u32; 3])) {
    march(l, dims, Projection::Eq1, visit);
}
