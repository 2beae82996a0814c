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
pub mod embree_tracer;

use tubecast::{Ray, RoundCone, V3};
use tubecast_render::render::Camera;
use tubecast_render::scene::Scene;

/// What both sides of a scene comparison take: the camera rays rounded to `f32` (as Embree
/// takes them), the same `f32` values widened to `f64` rays (for our BVH), and the scene's links
/// in `f32`.
pub struct SceneInputs {
    /// `(origin, direction)` of each pixel's ray, row by row, in `f32`.
    pub rays32: Vec<([f32; 3], [f32; 3])>,
    /// The same rays as `f64` [`Ray`]s.
    pub rays64: Vec<Ray<f64>>,
    /// The scene's links in `f32`.
    pub links32: Vec<RoundCone<f32>>,
}

/// The [`SceneInputs`] of `scene` seen by `cam` at `side × side` pixels.
pub fn scene_inputs(scene: &Scene, cam: &Camera, side: u32) -> SceneInputs {
    let rays32: Vec<([f32; 3], [f32; 3])> = (0..side * side)
        .map(|i| {
            let r = cam.ray(i % side, i / side);
            (r.o.cast::<f32>().to_array(), r.d.cast::<f32>().to_array())
        })
        .collect();
    let rays64 = rays32.iter().map(|(o, d)| Ray::new(V3::from(*o).cast(), V3::from(*d).cast())).collect();
    let links32 = (0..scene.links.len()).map(|k| scene.link(k).cast()).collect();
    SceneInputs { rays32, rays64, links32 }
}
