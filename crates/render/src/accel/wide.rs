//! An 8-wide compressed BVH (obvhs's CWBVH: 8 children per node, child boxes quantised to
//! 8 bits per plane, rounded outward, so every child box contains the `f32` box it quantises)
//! over the same padded `f32` boxes and the same scene-box clipping as [`Bvh`] (see the parent
//! module's bound), so the culling is as conservative; leaves hold up to three primitives,
//! each answered by the scalar [`Prim`] path. Answers equal [`Bvh`]'s: the same exact kernel
//! results, only visited in another order.

use super::{Bvh, Frame, Hit, Tracer};
use crate::scene::Prim;
#[allow(unused_imports)] // named by obvhs::traverse!
use glam::UVec2;
use obvhs::cwbvh::CwBvh;
use tubecast::csg::Tagged;
use tubecast::Ray;

/// A CWBVH over primitives.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::{Tracer, WideBvh};
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
///
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let wide = WideBvh::build(Scene::from_polylines(&[line], 0.5, "tube").unwrap().primitives());
/// let hit = wide.closest_hit(&Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0))).unwrap();
/// assert_eq!((hit.t, hit.link, hit.entering), (2.5, 0, true));
/// ```
pub struct WideBvh {
    bvh: CwBvh,
    prims: Vec<Prim>,
    frame: Frame,
}

impl WideBvh {
    /// Build over `prims` (obvhs PLOC, medium quality, then collapsed to 8 wide). An empty
    /// list gives a tree that every ray misses.
    pub fn build(prims: Vec<Prim>) -> Self {
        let (frame, aabbs) = Frame::new(&prims);
        if prims.is_empty() {
            return Self { bvh: CwBvh::default(), prims, frame };
        }
        // obvhs PLOC, medium quality, with a depth guard for degenerate scenes (cwbuild.rs).
        let mut bvh = super::cwbuild::build(&aabbs);
        let prims: Vec<Prim> = bvh.primitive_indices.iter().map(|&i| prims[i as usize]).collect();
        for (k, i) in bvh.primitive_indices.iter_mut().enumerate() {
            *i = k as u32;
        }
        Self { bvh, prims, frame }
    }

    /// Number of nodes (each of up to eight children).
    pub fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }
}

/// Walk the tree along `$ray` (an obvhs ray, `tmax` updated by the caller's block), running
/// `$prim` with `$id` bound to each primitive whose box is entered; `break` stops the walk.
macro_rules! walk {
    ($self:expr, $ray:ident, $id:ident, $prim:block) => {{
        let mut state = $self.bvh.new_traversal($ray.direction);
        let mut node;
        obvhs::traverse!($self.bvh, node, state, node.intersect_ray(&$ray, state.oct_inv4), {
            let $id = state.primitive_id as usize;
            $prim
        });
    }};
}

impl Tracer for WideBvh {
    fn prims(&self) -> &[Prim] {
        &self.prims
    }

    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        let (a, b) = Bvh::range(ray);
        let c = self.frame.clip(ray, a, b)?;
        let mut r = c.ray;
        let margin = 8.0 * self.frame.pad;
        let (dn, len) = Bvh::unit(ray);
        let mut best: Option<Hit> = None;
        walk!(self, r, id, {
            if let Some((t, n, u, entering)) = self.prims[id].first_hit_unit(ray, dn, len) {
                if best.map_or(true, |h| t < h.t) {
                    best = Some(Hit { t, n, u, prim: id as u32, link: self.prims[id].link, entering });
                    // Cull by the best hit so far, loosened by the box margin (module docs).
                    let tb = (((t - c.t0) * c.len + margin) * c.scale) as f32;
                    if tb < r.tmax {
                        r.tmax = tb;
                    }
                }
            }
        });
        best
    }

    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        let (a, b) = Bvh::range(ray);
        let Some(c) = self.frame.clip(ray, a, b) else {
            return false;
        };
        let r = c.ray;
        let (dn, len) = Bvh::unit(ray);
        let mut found = false;
        walk!(self, r, id, {
            if self.prims[id].meets_unit(ray, dn, len) {
                found = true;
                break;
            }
        });
        found
    }

    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        let Some(c) = self.frame.clip(ray, f64::NEG_INFINITY, f64::INFINITY) else {
            return;
        };
        let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
        let r = c.ray;
        walk!(self, r, id, {
            self.prims[id].pieces(&line, |iv| out.push(Tagged { iv, id: id as u32 }));
        });
    }

    fn memory_bytes(&self) -> usize {
        self.bvh.nodes.len() * std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.len() * 4
            + self.prims.len() * std::mem::size_of::<Prim>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::generate::{self, Rng};
    use crate::scene::{Model, Scene};
    use tubecast::csg::union;
    use tubecast::V3;

    /// The union boundaries of a ray's line intervals (their order in the list is the
    /// traversal's; the union sorts them).
    fn boundaries(t: &dyn Tracer, ray: &Ray<f64>) -> Vec<(u64, u64)> {
        let mut ivs = Vec::new();
        t.line_intervals(ray, &mut ivs);
        let mut b = Vec::new();
        union(&mut ivs, f64::NEG_INFINITY, f64::INFINITY, |x| b.push((x.t.to_bits(), x.n.x.to_bits())));
        b
    }

    /// Both trees answer with the same exact kernel results (lane packets are bit-identical to
    /// the scalar path), so every query agrees bit for bit: the closest `t` (the primitive
    /// only up to ties), any-hit, and the union of the line intervals. Links, spheres and spline
    /// sub-segments; rays from outside and from inside the tubes (secondary rays).
    #[test]
    fn wide_answers_equal_the_binary_bvh() {
        let mut lines = generate::furball(150, 12, 2);
        lines.extend(generate::helix(30));
        let scene = Scene::from_polylines(&lines, 0.05, "mix").unwrap();
        let mut rng = Rng::new(9);
        for model in [Model::Links, Model::Splines] {
            let prims = scene.model_primitives(model).unwrap();
            let (bvh, wide) = (Bvh::build(prims.clone()), WideBvh::build(prims));
            assert_eq!(wide.prims().len(), bvh.prims.len());
            let mut hits = 0;
            for k in 0..2000 {
                // Aim near a random node: from 40 away, or from the node itself (inside).
                let node = scene.nodes[(rng.uniform() * scene.nodes.len() as f64) as usize].pos;
                let p = V3::from(node) + V3::from(rng.unit()) * rng.range(0.0, 0.1);
                let d = V3::from(rng.unit()) * rng.range(0.5, 2.0);
                let o = if k % 2 == 0 { p - d * (40.0 / d.length()) } else { p };
                let ray = Ray::with_range(o, d, 0.0, 60.0);
                let (a, b) = (bvh.closest_hit(&ray), wide.closest_hit(&ray));
                assert_eq!(a.map(|h| h.t.to_bits()), b.map(|h| h.t.to_bits()), "ray {k}: {ray:?}");
                hits += usize::from(a.is_some());
                assert_eq!(bvh.any_hit(&ray), wide.any_hit(&ray), "ray {k}");
                assert_eq!(boundaries(&bvh, &ray), boundaries(&wide, &ray), "ray {k}");
            }
            assert!(hits > 200, "{hits} hits of 2000");
        }
    }

    #[test]
    fn an_empty_wide_tree_misses() {
        let wide = WideBvh::build(Vec::new());
        let ray = Ray::new(V3::zero(), V3::new(1.0, 0.0, 0.0));
        assert!(wide.closest_hit(&ray).is_none() && !wide.any_hit(&ray));
        let mut out = Vec::new();
        wide.line_intervals(&ray, &mut out);
        assert!(out.is_empty() && wide.node_count() == 0);
    }
}
