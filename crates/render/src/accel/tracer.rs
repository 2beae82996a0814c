//! The one interface the renderer and `tubecast intersect` trace through, so that every
//! accelerator (the BVH today; a voxel grid, a mesh or a wide BVH beside it) plugs into the
//! same per-pixel code and the same hit tables.

use super::Hit;
use crate::scene::Prim;
use tubecast::csg::Tagged;
use tubecast::Ray;

/// Ray queries over a scene's primitives, answered with exact kernel results in `f64`.
///
/// Every implementation must give the same answers as [`Bvh`](super::Bvh) on the same
/// primitives (the hit's `id` names [`Tracer::prim`]); only the culling differs.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::{Bvh, Tracer};
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
///
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let tracer: Box<dyn Tracer> = Box::new(Bvh::build(scene.primitives()));
/// let hit = tracer.closest_hit(&Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0))).unwrap();
/// assert_eq!(tracer.prim(hit.id).link, 0);
/// ```
pub trait Tracer: Send + Sync {
    /// The primitive with id `id` (a [`Hit::id`] or [`Tagged::id`]), `id < prim_count()`.
    /// Every tracer answers every id, whether it stores the primitive whole or, as a compact
    /// [`WideBvh::from_scene`](super::WideBvh::from_scene) does, in a cluster.
    fn prim(&self, id: u32) -> Prim;
    /// Number of primitive ids: ids run over `0..prim_count()`.
    fn prim_count(&self) -> usize;
    /// The closest surface crossing in `[t_min, t_max]` (entry, or exit when the ray starts
    /// inside a primitive). The ray must be valid ([`Ray::validate`]).
    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit>;
    /// [`Self::closest_hit`] and the exit `t` of the hit primitive's own interval (that of
    /// [`Prim::intersect`] of [`Self::prim`]), for tables that report both; a tracer that knows
    /// the exit from its search gives it without a second kernel call.
    fn closest_hit_exit(&self, ray: &Ray<f64>) -> Option<(Hit, f64)> {
        let h = self.closest_hit(ray)?;
        Some((h, self.prim(h.id).intersect(ray).exit.t))
    }
    /// True when any primitive's surface or interior meets the ray within `[t_min, t_max]`.
    fn any_hit(&self, ray: &Ray<f64>) -> bool;
    /// Every primitive's interval (one per connected piece) with the ray's whole line,
    /// appended to `out`: the input of [`tubecast::csg::union`].
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>);
    /// Bytes held by the structure and its primitives.
    fn memory_bytes(&self) -> usize;
}

impl Tracer for super::Bvh {
    fn prim(&self, id: u32) -> Prim {
        self.prims[id as usize]
    }
    fn prim_count(&self) -> usize {
        self.prims.len()
    }
    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        super::Bvh::closest_hit(self, ray)
    }
    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        super::Bvh::any_hit(self, ray)
    }
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        super::Bvh::line_intervals(self, ray, out)
    }
    fn memory_bytes(&self) -> usize {
        super::Bvh::memory_bytes(self)
    }
}
