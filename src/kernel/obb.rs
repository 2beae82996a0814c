//! Oriented (and axis-aligned) bounding boxes of a quadratic sphere-swept segment (Russig §3.2).
//!
//! Orientation: `x̂` along the chord `b₂ − b₀`; `ŷ` the tangent `b₁ − b₀` with its `x̂`
//! component removed, normalised; `ẑ = x̂ × ŷ`. Degenerate cases: a zero chord uses the
//! tangent (or `b₂ − b₁`, or the world x axis) for `x̂`; a tangent (nearly) collinear with `x̂`
//! uses a fixed unit vector orthogonal to `x̂` (Duff et al. 2017's branch-free basis). The
//! frame is re-orthogonalised, so it is orthonormal to rounding in every case.
//!
//! Extents: along a unit axis `a`, the sweep's support is `max_t (a·p(t) + r(t))` (a sphere's
//! support is its centre's plus its radius), a quadratic Bézier in `t`: its maximum is at
//! `t = 0`, `t = 1` or the vertex (the root of the linear derivative). Likewise the minimum of
//! `a·p − r`. So every face of the box touches the tube (the box is the tightest one in
//! its frame) and the box is conservative up to the rounding of those few operations.

use crate::kernel::spline::QuadTube;
use crate::math::bezier::{bezier2_max, bezier2_min};
use crate::math::frame::orthonormal_basis;
use crate::real::Real;
use crate::vec::V3;

/// A box `{origin + Σ axesᵢ·cᵢ : loᵢ ≤ cᵢ ≤ hiᵢ}` with orthonormal `axes`.
///
/// ```
/// use tubecast::{Obb, QuadTube, V3};
/// let tube = QuadTube::new(
///     [V3::new(0.0f64, 0.0, 0.0), V3::new(1.0, 1.0, 0.0), V3::new(2.0, 0.0, 0.0)],
///     [0.1, 0.1, 0.1],
/// )?;
/// let obb = tube.obb(); // = Obb::fit(&tube): x̂ along the chord
/// assert!((obb.axes[0].x - 1.0).abs() < 1e-15);
/// assert!((obb.hi.x - 2.1).abs() < 1e-15 && (obb.lo.x + 0.1).abs() < 1e-15);
/// let c = obb.local(tube.point(0.5));
/// assert!(c.x >= obb.lo.x && c.x <= obb.hi.x && c.y <= obb.hi.y);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obb<T> {
    /// Frame origin (the segment's first control point: extents stay small numbers).
    pub origin: V3<T>,
    /// Orthonormal axes `x̂, ŷ, ẑ`.
    pub axes: [V3<T>; 3],
    /// Lower extents along the axes, relative to `origin`.
    pub lo: V3<T>,
    /// Upper extents.
    pub hi: V3<T>,
}

/// `v/|v|` with a scale-safe length (no overflow or underflow of `|v|²`); zero maps to zero.
#[inline(always)]
fn unit<T: Real>(v: V3<T>) -> V3<T> {
    let m = v.max_abs();
    let s = T::one() / T::select(m.gt(T::zero()), m, T::one());
    (v * s).normalize_or_zero()
}

/// A unit vector orthogonal to the unit vector `n` (Duff et al. 2017): the first vector of
/// [`crate::math::frame::orthonormal_basis`].
#[inline(always)]
pub fn orthogonal<T: Real>(n: V3<T>) -> V3<T> {
    orthonormal_basis(n).0
}

impl<T: Real> Obb<T> {
    /// Russig's oriented box of the segment.
    #[inline(always)]
    pub fn fit(tube: &QuadTube<T>) -> Self {
        let [b0, b1, b2] = tube.b;
        let ex = V3::new(T::one(), T::zero(), T::zero());
        let chord = unit(b2 - b0);
        let t0 = unit(b1 - b0);
        let t1 = unit(b2 - b1);
        let has = |v: V3<T>| v.length2().gt(T::zero());
        let x = V3::select(has(chord), chord, V3::select(has(t0), t0, V3::select(has(t1), t1, ex)));
        // Tangent with the x component removed; use it when it keeps ≥ 1% of its length
        // (then the re-orthogonalisation below is well conditioned).
        let tan = V3::select(has(t0), t0, t1);
        let v = tan - x * tan.dot(x);
        let use_v = v.length2().gt(T::cst(1e-4));
        let y0 = V3::select(use_v, unit(v), orthogonal(x));
        let z = unit(x.cross(y0));
        let y = z.cross(x);
        Self::with_axes(tube, [x, y, z])
    }

    /// The tightest box of the segment in a given orthonormal frame.
    #[inline(always)]
    pub fn with_axes(tube: &QuadTube<T>, axes: [V3<T>; 3]) -> Self {
        let origin = tube.b[0];
        let q = [V3::zero(), tube.b[1] - origin, tube.b[2] - origin];
        let r = tube.r;
        let ext = |a: V3<T>| {
            let c = [q[0].dot(a), q[1].dot(a), q[2].dot(a)];
            let lo = bezier2_min([c[0] - r[0], c[1] - r[1], c[2] - r[2]]);
            let hi = bezier2_max([c[0] + r[0], c[1] + r[1], c[2] + r[2]]);
            (lo, hi)
        };
        let (xl, xh) = ext(axes[0]);
        let (yl, yh) = ext(axes[1]);
        let (zl, zh) = ext(axes[2]);
        Self { origin, axes, lo: V3::new(xl, yl, zl), hi: V3::new(xh, yh, zh) }
    }

    /// Coordinates of `x` in the box frame.
    #[inline(always)]
    pub fn local(&self, x: V3<T>) -> V3<T> {
        let v = x - self.origin;
        V3::new(v.dot(self.axes[0]), v.dot(self.axes[1]), v.dot(self.axes[2]))
    }

    /// Volume.
    #[inline(always)]
    pub fn volume(&self) -> T {
        let e = self.hi - self.lo;
        e.x * e.y * e.z
    }

    /// The eight corners in world coordinates.
    pub fn corners(&self) -> [V3<T>; 8] {
        let mut c = [V3::zero(); 8];
        for (i, ci) in c.iter_mut().enumerate() {
            let px = if i & 1 == 0 { self.lo.x } else { self.hi.x };
            let py = if i & 2 == 0 { self.lo.y } else { self.hi.y };
            let pz = if i & 4 == 0 { self.lo.z } else { self.hi.z };
            *ci = self.origin + self.axes[0] * px + self.axes[1] * py + self.axes[2] * pz;
        }
        c
    }
}
