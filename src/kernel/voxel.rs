//! Voxel traversal of round cones and rays on a unit grid: Kraaijeveld et al.'s conservative
//! capsule voxelization (their Algorithm 1) generalised to two radii, the voxels of a box, and
//! the DDA ray walk a grid accelerator traverses with. The baselines the conservative
//! voxelization is measured against (the link's bounding box, a DDA along its axis and the
//! paper's Eq. 1 radius) are in [`crate::baseline::voxel`].
//!
//! Coordinates are **grid coordinates**: voxel `[i, j, k]` is the box `[i, i+1] × [j, j+1] ×
//! [k, k+1]`, the grid is `[0, n₀] × [0, n₁] × [0, n₂]`; voxels outside it are never visited.
//! No function allocates; voxels are handed to a closure.
//!
//! # Conservative round-cone voxelization
//! A round cone is the union of the spheres `B(p(u), r(u))`, `p`, `r` linear in `u ∈ [0, 1]`.
//! March the major axis `a₀` of `d = b − a` slab by slab (`[n, n+1]`, clipped to the solid's
//! extent `[min(a₀ − r_a, b₀ − r_b), max(a₀ + r_a, b₀ + r_b)]`). A point `x` of the solid in the
//! slab `[t₀, t₁]` lies in some sphere `u` with `|p_{a₀}(u) − x_{a₀}| ≤ r(u) ≤ r_max`, so `u`
//! lies in the `u`-range of `p_{a₀} ∈ [t₀ − r_max, t₁ + r_max]` and `r(u) ≤ R`, the larger
//! radius at that range's ends (`r` is linear). So `x` is within `R` of the line `L` through
//! `a`, `b`. In the plane `x_{a₀} = t`, the points within `R` of `L` reach along a minor axis
//! `i` at most `R·√(1 + (dᵢ/d_{a₀})²)` from `L(t)` (the offset `w ⊥ d` maps to
//! `w·(eᵢ − (dᵢ/d_{a₀}) e_{a₀})`, and that vector is itself `⊥ d`). `Lᵢ` is linear, so over the
//! slab `xᵢ ∈ [min(Lᵢ(t₀), Lᵢ(t₁)) − ρᵢ, max(…) + ρᵢ]`, `ρᵢ = R·√(1 + (dᵢ/d_{a₀})²)`: the 2-D
//! box of Algorithm 1. With equal radii this is Kraaijeveld's capsule box, except their
//! projected radius `r/√(1 − (dᵢ/|d|)²)` (Eq. 1), which is smaller than `ρᵢ` when all three
//! components of `d` are non-zero (for `d ∝ (1, 1, 1)`: `1.22·r` against `1.41·r`) and then
//! misses voxels the solid meets; `tests/kernels/voxel/conservative.rs` counts them
//! ([`crate::baseline::voxel::voxelize_capsule_eq1`]).
//!
//! # Rounding
//! Inputs (`f32` or `f64`) are converted to `f64` exactly and every bound is computed in `f64`.
//! With `M` the largest coordinate magnitude plus `r_max` plus 1 (grid units), each computed
//! bound (`Lᵢ(t) = aᵢ + (dᵢ/d_{a₀})(t − a_{a₀})`, `ρᵢ`, the `u`-range and `R`) is a handful of
//! roundings of quantities `≤ 2M`, so it is off by at most `~8·ε·M`; every bound is widened
//! outward by `δ = 32·ε·M` (4× that), so the visited set contains every voxel that the exact
//! solid of the given (rounded) input meets.

mod occupancy;

pub use occupancy::{clipped_sdf, occupancy, Clip};

use crate::kernel::link::RoundCone;
use crate::real::Scalar;
use crate::vec::V3;

/// Grid size in voxels along x, y, z.
pub type Dims = [u32; 3];

/// Outward rounding margin `δ = 32·ε·M` of the module docs, in grid units. The input is
/// converted to `f64` exactly and all bounds are computed in `f64`, so `ε = 2⁻⁵²` for either
/// precision of the input.
pub(crate) fn margin<T: Scalar>(l: &RoundCone<T>) -> f64 {
    let m = l.a.max_abs().to_f64().max(l.b.max_abs().to_f64()) + l.ra.to_f64().max(l.rb.to_f64()) + 1.0;
    32.0 * f64::EPSILON * m
}

/// True when every coordinate and radius is finite (the functions visit nothing otherwise).
pub(crate) fn finite<T: Scalar>(l: &RoundCone<T>) -> bool {
    [l.a.x, l.a.y, l.a.z, l.ra, l.b.x, l.b.y, l.b.z, l.rb].iter().all(|x| x.to_f64().is_finite())
}

/// The round cone's bounding box `(lo, hi)` in `f64`, widened by `delta`.
pub(crate) fn bounds<T: Scalar>(l: &RoundCone<T>, delta: f64) -> ([f64; 3], [f64; 3]) {
    let (a, b) = (l.a.cast::<f64>().to_array(), l.b.cast::<f64>().to_array());
    let (ra, rb) = (l.ra.to_f64(), l.rb.to_f64());
    let lo = std::array::from_fn(|i| (a[i] - ra).min(b[i] - rb) - delta);
    let hi = std::array::from_fn(|i| (a[i] + ra).max(b[i] + rb) + delta);
    (lo, hi)
}

/// Voxel index range `[lo, hi]` of the closed interval `[x0, x1]` on an axis of `n` voxels;
/// `None` when it misses the grid (or is NaN).
#[inline]
fn span(x0: f64, x1: f64, n: u32) -> Option<(u32, u32)> {
    if !(x1 >= 0.0 && x0 <= n as f64) || n == 0 {
        return None;
    }
    let lo = x0.floor().max(0.0) as u32;
    let hi = (x1.floor() as i64).min(n as i64 - 1).max(0) as u32;
    Some((lo.min(n - 1), hi))
}

/// Visit every voxel of the box `[lo, hi]` (grid coordinates, closed) inside the grid.
pub(crate) fn visit_box(lo: [f64; 3], hi: [f64; 3], dims: Dims, visit: &mut impl FnMut([u32; 3])) {
    let (Some(x), Some(y), Some(z)) =
        (span(lo[0], hi[0], dims[0]), span(lo[1], hi[1], dims[1]), span(lo[2], hi[2], dims[2]))
    else {
        return;
    };
    for k in z.0..=z.1 {
        for j in y.0..=y.1 {
            for i in x.0..=x.1 {
                visit([i, j, k]);
            }
        }
    }
}

/// The voxels of the closed box `[lo, hi]` (grid coordinates): voxel `[i, j, k]` for `i` from
/// `⌊lo.x⌋` to `⌊hi.x⌋` (and so on), clipped to the grid, so that every point of the box lies
/// in a visited voxel. The bounds are converted to `f64` exactly and only floored: nothing is
/// rounded, so no margin is added (widen the box first for a voxel that only touches it at a
/// face). A box with some `lo > hi`, or with a NaN bound, visits nothing.
///
/// ```
/// use tubecast::{voxel, V3};
/// let mut cells = Vec::new();
/// voxel::voxelize_box(V3::new(0.5f64, 0.5, 0.5), V3::new(2.0, 0.9, 0.9), [8, 8, 8], |c| cells.push(c));
/// assert_eq!(cells, [[0, 0, 0], [1, 0, 0], [2, 0, 0]]); // x = 2 is in voxel 2
/// ```
pub fn voxelize_box<T: Scalar>(lo: V3<T>, hi: V3<T>, dims: Dims, mut visit: impl FnMut([u32; 3])) {
    visit_box(lo.cast::<f64>().to_array(), hi.cast::<f64>().to_array(), dims, &mut visit);
}

/// Conservative voxelization of a round cone (Kraaijeveld Alg. 1 generalised to two radii,
/// derivation in the module docs): every voxel whose closed box meets the solid is visited,
/// each once, in `O(L·r²)` voxels for a link of length `L` whatever its orientation.
///
/// ```
/// use tubecast::{voxel, RoundCone, V3};
/// // A diagonal link: its bounding box holds 6³ voxels, Algorithm 1 a band around the diagonal.
/// let l = RoundCone { a: V3::new(1.0f64, 1.0, 1.0), ra: 0.3, b: V3::new(5.0, 5.0, 5.0), rb: 0.1 };
/// let (mut ours, mut boxed) = (0, 0);
/// voxel::voxelize_round_cone(&l, [8, 8, 8], |_| ours += 1);
/// voxel::voxelize_box(V3::new(0.7, 0.7, 0.7), V3::new(5.3, 5.3, 5.3), [8, 8, 8], |_| boxed += 1);
/// assert!(ours < boxed && boxed == 216);
/// ```
pub fn voxelize_round_cone<T: Scalar>(l: &RoundCone<T>, dims: Dims, visit: impl FnMut([u32; 3])) {
    march(l, dims, Projection::Exact, visit);
}

/// Which projected radius [`march`] widens the slab boxes by.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Projection {
    /// `R·√(1 + (dᵢ/d_{a₀})²)` (derived in the module docs).
    Exact,
    /// Kraaijeveld Eq. 1, `R/√(1 − (dᵢ/|d|)²)`.
    Eq1,
}

/// Algorithm 1: march the major axis slab by slab, visiting each slab's 2-D box.
pub(crate) fn march<T: Scalar>(l: &RoundCone<T>, dims: Dims, proj: Projection, mut visit: impl FnMut([u32; 3])) {
    if !finite(l) {
        return;
    }
    let delta = margin(l);
    let (box_lo, box_hi) = bounds(l, delta);
    let (mut a, mut b) = (l.a.cast::<f64>().to_array(), l.b.cast::<f64>().to_array());
    let (mut ra, mut rb) = (l.ra.to_f64(), l.rb.to_f64());
    let d: [f64; 3] = std::array::from_fn(|i| b[i] - a[i]);
    // Rank the axes: a0 the major one.
    let a0 = (0..3).fold(0, |m, i| if d[i].abs() > d[m].abs() { i } else { m });
    if d[a0] == 0.0 {
        return visit_box(box_lo, box_hi, dims, &mut visit); // a sphere
    }
    let (a1, a2) = ((a0 + 1) % 3, (a0 + 2) % 3);
    if d[a0] < 0.0 {
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut ra, &mut rb);
    }
    let d: [f64; 3] = std::array::from_fn(|i| b[i] - a[i]);
    let k = [d[a1] / d[a0], d[a2] / d[a0]];
    let len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let grow = match proj {
        Projection::Exact => [(1.0 + k[0] * k[0]).sqrt(), (1.0 + k[1] * k[1]).sqrt()],
        Projection::Eq1 => [1.0 / (1.0 - d[a1] * d[a1] / len2).sqrt(), 1.0 / (1.0 - d[a2] * d[a2] / len2).sqrt()],
    };
    let rmax = ra.max(rb);
    let line = |t: f64, i: usize| a[[a1, a2][i]] + k[i] * (t - a[a0]);
    let radius_at = |t: f64| {
        let u = ((t - a[a0]) / d[a0]).clamp(0.0, 1.0);
        ra + (rb - ra) * u
    };
    let (lo, hi) = (box_lo[a0], box_hi[a0]);
    let Some((s0, s1)) = span(lo, hi, dims[a0]) else {
        return;
    };
    for n in s0..=s1 {
        let (t0, t1) = (lo.max(n as f64), hi.min(n as f64 + 1.0));
        let big_r = radius_at(t0 - rmax).max(radius_at(t1 + rmax)) + delta;
        let mut bounds = [[0.0; 2]; 2];
        for (i, b) in bounds.iter_mut().enumerate() {
            let (p0, p1) = (line(t0, i), line(t1, i));
            let rho = big_r * grow[i] + delta;
            // Clipped to the bounding box: never more than the AABB method visits.
            let axis = [a1, a2][i];
            *b = [(p0.min(p1) - rho).max(box_lo[axis]), (p0.max(p1) + rho).min(box_hi[axis])];
        }
        let (Some(j), Some(kk)) =
            (span(bounds[0][0], bounds[0][1], dims[a1]), span(bounds[1][0], bounds[1][1], dims[a2]))
        else {
            continue;
        };
        for q in kk.0..=kk.1 {
            for p in j.0..=j.1 {
                let mut c = [0u32; 3];
                c[a0] = n;
                c[a1] = p;
                c[a2] = q;
                visit(c);
            }
        }
    }
}

/// Amanatides–Woo walk of the ray `o + t·d`, `t ∈ [t_lo, t_hi]`, through the grid: `visit(cell,
/// t_enter, t_exit)` for each voxel in order, until it returns false or the range or the grid
/// ends. The range is first clipped to the grid box. Each boundary `t` is computed directly
/// as `(plane − oᵢ)/dᵢ` (no running sums), so it is within a few roundings of the exact one;
/// a cell index is taken from the point at the entry `t`, clamped into the grid.
///
/// ```
/// use tubecast::{voxel, V3};
/// let mut cells = Vec::new();
/// voxel::dda(V3::new(-1.0f64, 0.5, 0.5), V3::new(1.0, 0.0, 0.0), 0.0, 10.0, [3, 1, 1], |c, t0, t1| {
///     cells.push((c[0], t0, t1));
///     true
/// });
/// assert_eq!(cells, [(0, 1.0, 2.0), (1, 2.0, 3.0), (2, 3.0, 4.0)]);
/// ```
pub fn dda<T: Scalar>(o: V3<T>, d: V3<T>, t_lo: T, t_hi: T, dims: Dims, mut visit: impl FnMut([u32; 3], T, T) -> bool) {
    let (o, d) = (o.cast::<f64>().to_array(), d.cast::<f64>().to_array());
    let (mut ta, mut tb) = (t_lo.to_f64(), t_hi.to_f64());
    for i in 0..3 {
        let n = dims[i] as f64;
        if d[i] == 0.0 {
            if !(o[i] >= 0.0 && o[i] <= n) {
                return;
            }
        } else {
            let (s, e) = ((0.0 - o[i]) / d[i], (n - o[i]) / d[i]);
            ta = ta.max(s.min(e));
            tb = tb.min(s.max(e));
        }
    }
    if ta.partial_cmp(&tb).map_or(true, |o| o.is_gt()) || dims.contains(&0) {
        return;
    }
    let mut cell = [0i64; 3];
    let mut next = [f64::INFINITY; 3];
    let step: [i64; 3] = std::array::from_fn(|i| {
        if d[i] > 0.0 {
            1
        } else if d[i] < 0.0 {
            -1
        } else {
            0
        }
    });
    for i in 0..3 {
        let x = o[i] + d[i] * ta;
        cell[i] = (x.floor() as i64).clamp(0, dims[i] as i64 - 1);
        if step[i] != 0 {
            let plane = (cell[i] + i64::from(step[i] > 0)) as f64;
            next[i] = (plane - o[i]) / d[i];
        }
    }
    let mut t_enter = ta;
    loop {
        let axis = if next[0] <= next[1] && next[0] <= next[2] {
            0
        } else if next[1] <= next[2] {
            1
        } else {
            2
        };
        let t_exit = next[axis].min(tb).max(t_enter);
        let c = [cell[0] as u32, cell[1] as u32, cell[2] as u32];
        if !visit(c, T::from_f64(t_enter), T::from_f64(t_exit)) || t_exit >= tb {
            return;
        }
        cell[axis] += step[axis];
        if cell[axis] < 0 || cell[axis] >= dims[axis] as i64 {
            return;
        }
        let plane = (cell[axis] + i64::from(step[axis] > 0)) as f64;
        next[axis] = (plane - o[axis]) / d[axis];
        t_enter = t_exit;
    }
}
