//! Peers: other ray–tube intersectors, for comparison in reports and benches only
//! (feature `embree`).
//!
//! [`embree`] is a minimal FFI to the system Embree 3 (`libembree3`, e.g. Debian's
//! `libembree-dev`), declared by hand (no bindgen) for the few calls the comparison needs.
//!
//! # Which surface
//! Embree's `ROUND_LINEAR_CURVE` segment is a cone tangent to the spheres at both vertices plus
//! the end sphere, plus the start sphere when the segment's flags say it has no left neighbour;
//! with a right neighbour, parts of the end sphere inside the next segment are clipped (Embree's
//! `kernels/geometry/roundline_intersector.h` and the `RTCCurveFlags` manual). Every link given to
//! [`embree::Scene::round_linear`] is its own segment with flags 0 (no neighbours), so each one is
//! exactly the convex hull of its two spheres — the same solid as [`tubecast::RoundCone`].
//! `ROUND_HERMITE_CURVE` and `ROUND_BEZIER_CURVE` sweep a *circle* of varying radius along the
//! curve (not a sphere), so they are a different surface and are used for speed only.

pub mod embree;
