//! [`MeshTracer`]: a scene's triangles in an obvhs BVH, answering the [`Tracer`] queries.
//!
//! Triangles are stored in `f32` relative to the scene's centre (what a GPU mesh path holds),
//! so they add a storage rounding of at most `2⁻²⁴·√3·max|v − centre|` to the tessellation's
//! certified bound ([`MeshTracer::error`]). obvhs finds the triangle (Möller–Trumbore in
//! `f32`); the hit's `t` is then recomputed in `f64` from that triangle's plane.

use super::SceneMesh;
use crate::accel::{Hit, Tracer};
use crate::scene::Prim;
use glam::Vec3A;
use obvhs::bvh2::Bvh2;
use obvhs::triangle::Triangle;
use tubecast::csg::Tagged;
use tubecast::{Crossing, Interval, Ray, V3};

/// A triangle BVH over a [`SceneMesh`]; hits index the scene's exact primitives (the first
/// primitive of the triangle's link), so colouring by link, radius or type works unchanged.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::Tracer;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::mesh::{tessellate, MeshTracer};
/// use tubecast_render::scene::{Model, Scene};
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let mesh = tessellate(&scene, Model::Links, 1e-3).unwrap();
/// let tracer = MeshTracer::build(&mesh, scene.primitives());
/// let hit = tracer.closest_hit(&Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0))).unwrap();
/// assert!((hit.t - 2.5).abs() <= tracer.error()); // exact: 3 − 0.5
/// assert_eq!(tracer.prim(hit.id).link, 0);
/// ```
pub struct MeshTracer {
    bvh: Bvh2,
    /// Triangles in BVH leaf order, relative to `centre`.
    tris: Vec<Triangle>,
    /// Per triangle (leaf order): index into `prims`, and closed part.
    prim: Vec<u32>,
    part: Vec<u32>,
    prims: Vec<Prim>,
    centre: V3<f64>,
    lo: V3<f64>,
    hi: V3<f64>,
    error: f64,
}

impl MeshTracer {
    /// Bytes of one stored triangle (three `f32` vertices, SIMD-padded); the build also holds
    /// an unordered copy of the triangles for the BVH builder.
    pub const TRIANGLE_BYTES: usize = std::mem::size_of::<Triangle>();

    /// Builds the BVH (obvhs PLOC, medium quality) over the mesh; `prims` are the scene's
    /// primitives that hits name (every tagged link must have one).
    pub fn build(m: &SceneMesh, prims: Vec<Prim>) -> Self {
        let pos = &m.mesh.positions;
        let inf = f64::INFINITY;
        let (mut lo, mut hi) = (V3::new(inf, inf, inf), V3::new(-inf, -inf, -inf));
        for p in pos {
            lo = V3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = V3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        let centre = if pos.is_empty() { V3::zero() } else { (lo + hi) * 0.5 };
        let rel = |p: V3<f64>| Vec3A::new((p.x - centre.x) as f32, (p.y - centre.y) as f32, (p.z - centre.z) as f32);
        let tris: Vec<Triangle> = m
            .mesh
            .triangles
            .iter()
            .map(|t| Triangle { v0: rel(pos[t[0] as usize]), v1: rel(pos[t[1] as usize]), v2: rel(pos[t[2] as usize]) })
            .collect();
        let extent = if pos.is_empty() { 0.0 } else { (hi - lo).max_abs() * 0.5 };
        let error = m.mesh.certified + 2f64.powi(-24) * 3f64.sqrt() * extent;
        let bvh = if tris.is_empty() {
            Bvh2::default()
        } else {
            obvhs::bvh2::builder::build_bvh2(&tris, obvhs::BvhBuildParams::medium_build(), &mut Default::default())
        };
        let mut first = vec![u32::MAX; prims.iter().map(|p| p.link as usize + 1).max().unwrap_or(0)];
        for (i, p) in prims.iter().enumerate().rev() {
            first[p.link as usize] = i as u32;
        }
        let order = &bvh.primitive_indices;
        let prim = order.iter().map(|&i| first.get(m.mesh.tags[i as usize] as usize).copied().unwrap_or(0)).collect();
        let part = order.iter().map(|&i| m.part[i as usize]).collect();
        let tris = order.iter().map(|&i| tris[i as usize]).collect();
        let mut bvh = bvh;
        bvh.primitive_indices.iter_mut().enumerate().for_each(|(k, i)| *i = k as u32);
        Self { bvh, tris, prim, part, prims, centre, lo, hi, error }
    }

    /// The bound on the distance between the traced triangles and the exact surface: the
    /// tessellation's certified bound plus the `f32` storage rounding.
    pub fn error(&self) -> f64 {
        self.error
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The obvhs ray for `[s_lo, s_hi]` along the unit direction, the distance it starts at
    /// and the direction's length; `None` when the line misses the scene box.
    fn clip(&self, ray: &Ray<f64>, s_lo: f64, s_hi: f64) -> Option<(obvhs::ray::Ray, f64, f64)> {
        if self.tris.is_empty() {
            return None;
        }
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let pad = 1e-6 * (self.hi - self.lo).max_abs().max(f64::MIN_POSITIVE);
        let (o, d, lo, hi) = (ray.o.to_array(), dn.to_array(), self.lo.to_array(), self.hi.to_array());
        let (mut a, mut b) = (s_lo, s_hi);
        for i in 0..3 {
            if d[i] == 0.0 {
                if o[i] < lo[i] - pad || o[i] > hi[i] + pad {
                    return None;
                }
            } else {
                let (t1, t2) = ((lo[i] - pad - o[i]) / d[i], (hi[i] + pad - o[i]) / d[i]);
                a = a.max(t1.min(t2));
                b = b.min(t1.max(t2));
            }
        }
        if a.is_nan() || b.is_nan() || a > b {
            return None;
        }
        let p = ray.o + dn * a - self.centre;
        let org = Vec3A::new(p.x as f32, p.y as f32, p.z as f32);
        let dir = Vec3A::new(d[0] as f32, d[1] as f32, d[2] as f32);
        Some((obvhs::ray::Ray::new(org, dir, 0.0, (b - a) as f32), a, len))
    }

    /// `t` (user units) and the outward unit normal of triangle `k` on the ray, in `f64`.
    fn refine(&self, k: usize, ray: &Ray<f64>) -> (f64, V3<f64>) {
        let tri = &self.tris[k];
        let w = |v: Vec3A| V3::new(v.x as f64, v.y as f64, v.z as f64) + self.centre;
        let (a, b, c) = (w(tri.v0), w(tri.v1), w(tri.v2));
        let n = (b - a).cross(c - a).normalize_or_zero();
        (n.dot(a - ray.o) / n.dot(ray.d), n)
    }
}

impl Tracer for MeshTracer {
    fn prim(&self, id: u32) -> Prim {
        self.prims[id as usize]
    }
    fn prim_count(&self) -> usize {
        self.prims.len()
    }
    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        let len = ray.d.length();
        let (r, s0, len) = self.clip(ray, ray.t_min * len, ray.t_max * len)?;
        let mut hit = obvhs::ray::RayHit::none();
        self.bvh.ray_traverse(r, &mut hit, |r, id| self.tris[id].intersect(r));
        if hit.primitive_id == obvhs::ray::INVALID_ID {
            return None;
        }
        let k = hit.primitive_id as usize;
        let (t, n) = self.refine(k, ray);
        let t = if t.is_finite() { t } else { (s0 + hit.t as f64) / len };
        Some(Hit { t, n, u: 0.0, id: self.prim[k], entering: n.dot(ray.d) < 0.0 })
    }
    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        let len = ray.d.length();
        let Some((r, _, _)) = self.clip(ray, ray.t_min * len, ray.t_max * len) else { return false };
        !self.bvh.ray_traverse_miss(r, |r, id| self.tris[id].intersect(r))
    }
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        let Some((r, _, _)) = self.clip(ray, f64::NEG_INFINITY, f64::INFINITY) else { return };
        let mut xs: Vec<(u32, f64, usize)> = Vec::new();
        self.bvh.ray_traverse_anyhit(r, |r, id| {
            if self.tris[id].intersect(r) < f32::INFINITY {
                xs.push((self.part[id], self.refine(id, ray).0, id));
            }
        });
        xs.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        // Each part is closed: its crossings along the line alternate entry, exit.
        for pair in xs.chunk_by(|a, b| a.0 == b.0).flat_map(|c| c.chunks_exact(2)) {
            let ((_, t_in, a), (_, t_out, b)) = (pair[0], pair[1]);
            let (n_in, n_out) = (self.refine(a, ray).1, self.refine(b, ray).1);
            let iv =
                Interval::new(Crossing { t: t_in, n: n_in, u: 0.0 }, Crossing { t: t_out, n: n_out, u: 0.0 }, true);
            out.push(Tagged { iv, id: self.prim[a] });
        }
    }
    fn memory_bytes(&self) -> usize {
        self.tris.len() * (std::mem::size_of::<Triangle>() + 8)
            + self.bvh.nodes.len() * std::mem::size_of::<obvhs::bvh2::node::Bvh2Node>()
            + self.bvh.primitive_indices.len() * 4
            + self.prims.len() * std::mem::size_of::<Prim>()
    }
}
