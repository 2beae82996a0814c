//! Counts and bounds of a scene and of its primitives (what `tubecast info` prints).

use super::{Prim, PrimKind, Scene};
use tubecast::LinkShape;
use tubecast::Primitive;

/// Counts and extents of a scene's primitives (what `tubecast info` prints).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Nodes.
    pub nodes: usize,
    /// Links (including zero-length links of isolated nodes).
    pub links: usize,
    /// Cylinder links (equal radii).
    pub cylinders: usize,
    /// Tangent-cone links (different radii).
    pub cones: usize,
    /// Links that are a sphere (one end inside the other, or an isolated node).
    pub spheres: usize,
    /// Spline segments: cubic Hermite segments, each two [`PrimKind::Spline`] primitives
    /// (zero for the link model, [`Scene::stats`]).
    pub splines: usize,
    /// Axis-aligned bounds of the surface `(min, max)`; `([0; 3], [0; 3])` for a scene
    /// without primitives (check [`Stats::is_empty`]), so bounds are always finite.
    pub bounds: ([f64; 3], [f64; 3]),
}

impl Stats {
    /// True when the scene has no nodes (so no primitives and no bounds).
    pub fn is_empty(&self) -> bool {
        self.nodes == 0
    }
}

/// `(lo, hi)`, or zeros when nothing was accumulated (`lo > hi`).
fn finite_bounds(lo: [f64; 3], hi: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    if lo[0] > hi[0] {
        ([0.0; 3], [0.0; 3])
    } else {
        (lo, hi)
    }
}

impl Scene {
    /// Counts and bounds of a primitive list built from this scene ([`Self::primitives`] or
    /// [`Self::spline_primitives`]): link primitives by kind, spline segments (pairs of
    /// sub-segments), and the union of the primitives' boxes.
    pub fn stats_of(&self, prims: &[Prim]) -> Stats {
        self.stats_over(prims.iter().copied())
    }

    /// [`Self::stats_of`] the link model's primitives ([`Self::primitives`]), each computed in
    /// turn and not kept: the same counts and bit for bit the same bounds, without the list's
    /// [`std::mem::size_of::<Prim>()`] bytes per link (`render`'s bounds at 10⁸ links).
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::scene::Scene;
    /// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0], [8.0, 1.0, 0.0]], radii: vec![] };
    /// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
    /// assert_eq!(scene.primitive_stats(), scene.stats_of(&scene.primitives()));
    /// ```
    pub fn primitive_stats(&self) -> Stats {
        self.stats_over((0..self.links.len()).map(|k| Prim::from_link(&self.link(k), k as u32)))
    }

    /// Counts and bounds of `prims` (see [`Self::stats_of`]).
    fn stats_over(&self, prims: impl Iterator<Item = Prim>) -> Stats {
        let mut s = Stats { nodes: self.nodes.len(), links: self.links.len(), ..Default::default() };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in prims {
            match p.kind() {
                PrimKind::Cylinder => s.cylinders += 1,
                PrimKind::Cone => s.cones += 1,
                PrimKind::Sphere => s.spheres += 1,
                PrimKind::Spline => s.splines += (p.half() == 0) as usize,
            }
            let (a, b) = p.aabb();
            for i in 0..3 {
                lo[i] = lo[i].min(a[i]);
                hi[i] = hi[i].max(b[i]);
            }
        }
        s.bounds = finite_bounds(lo, hi);
        s
    }

    /// Counts and bounds.
    pub fn stats(&self) -> Stats {
        let mut s = Stats { nodes: self.nodes.len(), links: self.links.len(), ..Default::default() };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for k in 0..self.links.len() {
            let l = self.link(k);
            match l.shape() {
                LinkShape::Cylinder => s.cylinders += 1,
                LinkShape::Cone => s.cones += 1,
                LinkShape::Sphere => s.spheres += 1,
            }
            let b = l.aabb();
            for (i, (x, y)) in b.min.to_array().iter().zip(b.max.to_array()).enumerate() {
                lo[i] = lo[i].min(*x);
                hi[i] = hi[i].max(y);
            }
        }
        s.bounds = finite_bounds(lo, hi);
        s
    }
}
