//! The report's reference: the independent `f64` oracles and seeded case generators of
//! [`tubecast_oracle`] (which shares no code with the kernels measured), and the conversions of
//! its plain cases into tubecast's types.

use tubecast::QuadTube;
use tubecast::{Ray, RoundCone, V3};
pub use tubecast_oracle::{
    link_bound, link_case, link_truth, report_spline_case, spline_case, spline_truth, LinkCase, LinkRegion, LinkTruth,
    SplineCase, SplineRegion, SplineTruth, LINK_REGIONS, SPLINE_REGIONS,
};
use tubecast_oracle::{Line, Link, Quad, Vec3};

/// The oracle's vector as tubecast's.
pub fn v3(v: Vec3) -> V3<f64> {
    V3::new(v.x, v.y, v.z)
}

/// The oracle's link as a [`RoundCone`] (the generated links are valid: radii ≥ 0, finite).
pub fn round_cone(l: &Link) -> RoundCone<f64> {
    RoundCone { a: v3(l.a), ra: l.ra, b: v3(l.b), rb: l.rb }
}

/// The oracle's line as a [`Ray`] with range `[0, ∞)`.
pub fn ray(l: &Line) -> Ray<f64> {
    Ray::new(v3(l.o), v3(l.d))
}

/// The oracle's quadratic tube as a [`QuadTube`] (the generated tubes are valid: finite
/// control points, positive control radii).
pub fn quad_tube(q: &Quad) -> QuadTube<f64> {
    QuadTube { b: q.b.map(v3), r: q.r }
}
