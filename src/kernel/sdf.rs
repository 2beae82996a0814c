//! Exact signed distances: sphere and round cone (link).
//!
//! Used by the tests (hit points must lie on the surface) and by voxelization.

use crate::kernel::link::RoundCone;
use crate::real::Real;
use crate::vec::V3;

/// Signed distance to the sphere `|x − c| = r` (negative inside).
#[inline(always)]
pub fn sphere<T: Real>(x: V3<T>, c: V3<T>, r: T) -> T {
    (x - c).length() - r
}

/// Signed distance to a round cone (convex hull of two spheres), exact outside and on the
/// surface; inside it is the negated distance to the nearest of the cone side and the two
/// sphere surfaces, which equals the exact inside distance of the hull.
///
/// In the plane through the axis with coordinates `z` (along the axis from `a`) and `ρ`
/// (distance from the axis), the cone side is the line `s·z + c·ρ = ra` with
/// `s = (ra − rb)/L`, `c = √(1 − s²)`; the normals to it through the two tangent points split
/// the plane into the region nearest sphere `a`, the cone side, and sphere `b`.
#[inline(always)]
pub fn round_cone<T: Real>(x: V3<T>, l: &RoundCone<T>) -> T {
    let one = T::one();
    let v = l.b - l.a;
    let len = v.length();
    let dr = l.ra - l.rb;
    let has_cone = dr.abs().lt(len);
    let len_s = T::select(has_cone, len, one);
    let axis = v * (one / len_s);
    let s = T::select(has_cone, dr / len_s, T::zero());
    let c = ((one - s) * (one + s)).sqrt();
    let y = x - l.a;
    let z = y.dot(axis);
    let rho = y.cross(axis).length();
    // k = c·z − s·ρ: 0 at the tangent point on sphere a, c·L at the one on sphere b.
    let k = c * z - s * rho;
    let da = y.length() - l.ra;
    let db = (x - l.b).length() - l.rb;
    let dc = s * z + c * rho - l.ra;
    let cone = T::select(k.lt(T::zero()), da, T::select(k.gt(c * len_s), db, dc));
    // No cone (one sphere inside the other): the larger sphere.
    let big = T::select(l.ra.ge(l.rb), da, db);
    T::select(has_cone, cone, big)
}
