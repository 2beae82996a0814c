//! Acceleration structures: a binary BVH ([`Bvh`], with lane packets) and an 8-wide compressed
//! one ([`WideBvh`], what the CLI uses: fewer node visits and less memory), both built and
//! traversed by [`obvhs`] over the scene's primitives, with closest-hit, any-hit and
//! all-intervals queries in `f64` ray parameters ([`Tracer`]), and the `intersect` tables.
//!
//! # Conservative boxes
//! obvhs works in `f32`. Its boxes are stored relative to the scene's centre, and every
//! query first clips the ray's line to the scene box in `f64` and restarts it at the box
//! entry, so every `f32` quantity in a traversal is bounded by the scene size `D` (its box
//! diagonal). The `f32` errors of a traversal are then: the restarted origin, `≤ D·2⁻²⁴` per
//! component; the rounded direction, `≤ 2⁻²⁴` relative, i.e. `≤ 2D·2⁻²⁴` of displacement over
//! the `≤ 2D` of travel that matters; and the slab test's own subtract-and-multiply,
//! `≤ 2·2⁻²⁴` relative on slab distances `≤ 2D`. Each box is therefore padded outward by
//! `pad = D·2⁻¹⁶` (256 times the largest of these), after rounding its corners outward, so a
//! ray that grazes a primitive still enters every box on the way. The same margin covers
//! obvhs clamping `1/dᵢ` to `±2²³` for `|dᵢ| ≤ 2⁻²³` (its `safe_inverse`): the clamped slab of
//! a ray inside a padded slab still spans `±pad·2²³ = ±128·D`, far beyond the travel.
//! The returned hits are exact kernel results in `f64`; only culling uses `f32`.
//!
//! # obvhs's absolute entry bound
//! obvhs works in a frame scaled by a power of two so that the padded scene box's size is
//! `(D + 4·pad)·scale ∈ [2^-½, 2^½]`. Its 8-wide node test (`CwBvhNode::intersect_ray`) accepts a child
//! only where `max(t_entry, 10⁻⁴) ≤ t_exit` — an absolute `10⁻⁴` (obvhs's `EPSILON`, in its
//! units) — so a box that the obvhs ray leaves before `t = 10⁻⁴` is culled. Every hit we need
//! lies at a distance `s* ≥ a` along the unit direction (`a`: the clipped entry), and the ray
//! stays inside the hit primitive's padded box (and every box above it) for `s* ± pad`, so its
//! exit from them is at `t ≥ (a − s₀ + pad)·scale`, with `s₀` the restart. The restart therefore
//! lies `4·pad` (the rounding margin) plus `LEAD = 2⁻¹²` obvhs units (`2.4·10⁻⁴ > 10⁻⁴`,
//! with the slab errors above ≪ the remaining `1.4·10⁻⁴`) before `a`. Without the lead it lay
//! `4·pad·scale ≤ 8.6·10⁻⁵` before, and the wide tree missed hits within about `2·pad` of the
//! entry: a fuzz finding, `regression-long-link-epsilon` — six links near the origin and one
//! 7.26·10⁶ long (`pad = 110.8`, `scale = 2⁻²³`), a ray starting inside the scene box whose hit
//! link's padded box spans obvhs `t ∈ [3.8, 6.9]·10⁻⁵`. The lead lengthens the `f32` travel by
//! `2⁻¹²·scale⁻¹ ≤ 2⁻¹¹·D`, which leaves the error bounds above as they are.
//!
//! obvhs's quantisation of a wide node's child boxes (8 bits per axis, plane `p + q·2ᵏ`) rounds
//! outward (`floor`/`ceil` of `(child − p)·2⁻ᵏ`) after one `f32` subtraction of values
//! `≤ 2` apart, `≤ 2⁻²⁴·2` off, and its exponent `k` (an `f32` `log2`, a few ulps) can be one
//! too small where the node's extent is within those ulps of `255·2ᵏ`, clamping `q = 256` to
//! 255: a box a few `2⁻²⁴·2` short. Both are below `pad·scale ≥ 2⁻¹⁶·2^-½ = 1.08·10⁻⁵` by a
//! factor of 20 or more, so the padding covers them.
//!
//! # Lane packets
//! With the `wide` feature, the links (cylinders and cones) of each leaf are moved to the
//! leaf's front and gathered into packets of up to eight, tested by one call of the lane
//! kernel (`packet` module); each link's result is bit-identical to [`Prim::intersect`], so
//! every query returns what the scalar path returns. Spheres and spline sub-segments stay on
//! the scalar path.

use crate::scene::Prim;
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use tubecast::csg::Tagged;
use tubecast::Ray;
use tubecast::V3;

mod chunked;
mod cluster;
mod cwbuild;
pub mod grid;
#[cfg(feature = "wide")]
mod packet;
mod table;
mod tracer;
pub mod tree;
mod wide;

pub use chunked::{CHUNK, CHUNKS_AT_ONCE};
pub use table::{closest_rows, closest_table, crossings_table, hit_rows, hit_table, MISS_ROW};
pub use tracer::Tracer;
pub use wide::{TreeExport, WideBvh};

/// How far (in obvhs units, beyond the `4·pad` rounding margin) a clipped ray restarts before
/// its entry into the scene box: more than obvhs's absolute `10⁻⁴` below which its wide node
/// test culls boxes (see the module docs).
const LEAD: f64 = 1.0 / 4096.0;

/// `pack_at` entry of a primitive that starts no packet.
#[cfg(feature = "wide")]
const NO_PACK: u32 = u32::MAX;

/// One primitive test of a leaf visit.
enum Test {
    /// Test primitive `id` on the scalar path.
    Prim(usize),
    /// Link `id` was tested in a lane packet: its interval (a hit), as [`Prim::intersect`]
    /// gives it.
    #[cfg_attr(not(feature = "wide"), allow(dead_code))]
    Link(usize, tubecast::Interval<f64>),
}

/// The first surface crossing along a ray, as every tracer answers it: the kernel crate's
/// [`tubecast::Hit`], its `id` the primitive's index in the tracer ([`Tracer::prim`]; the scene
/// link is `tracer.prim(hit.id).link`). Equal `t` is decided by [`tubecast::Hit::closer`] in
/// every tracer, so all of them give the same answer bit for bit.
pub type Hit = tubecast::Hit<f64>;

/// A BVH over primitives.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::Bvh;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
///
/// // One tube of radius 0.5 along x from 0 to 4.
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let bvh = Bvh::build(scene.primitives());
/// let down = Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
/// let hit = bvh.closest_hit(&down).unwrap();
/// assert_eq!((hit.t, bvh.prims[hit.id as usize].link, hit.entering), (2.5, 0, true));
/// assert!(!bvh.any_hit(&Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, 1.0, 0.0))));
/// ```
pub struct Bvh {
    bvh: Bvh2,
    /// The primitives, in BVH leaf order.
    pub prims: Vec<Prim>,
    frame: Frame,
    /// Lane packets of links, each over consecutive primitives of one leaf.
    #[cfg(feature = "wide")]
    packs: Vec<packet::Packet>,
    /// Per primitive: the packet starting at it, or [`NO_PACK`].
    #[cfg(feature = "wide")]
    pack_at: Vec<u32>,
}

struct BoxOf(Aabb);
impl obvhs::Boundable for BoxOf {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// The scene box in `f64` (padded), its centre (the origin of the `f32` boxes) and the box
/// padding (see the module docs).
#[derive(Clone, Debug)]
struct Frame {
    centre: [f64; 3],
    lo: [f64; 3],
    hi: [f64; 3],
    pad: f64,
    /// obvhs coordinates are `(x − centre)·scale` (a power of two).
    scale: f64,
    /// False for an empty scene: every ray misses.
    any: bool,
}

impl Frame {
    /// The frame of `prims` and their padded `f32` boxes relative to the centre.
    fn new(prims: &[Prim]) -> (Self, Vec<BoxOf>) {
        Self::of_boxes(&prims.iter().map(|p| p.aabb()).collect::<Vec<_>>())
    }

    /// The frame of items with world boxes `boxes` and their padded `f32` boxes.
    fn of_boxes(boxes: &[([f64; 3], [f64; 3])]) -> (Self, Vec<BoxOf>) {
        let frame = Self::bounding(boxes.iter().copied());
        let aabbs = boxes.iter().map(|&b| BoxOf(frame.padded(b))).collect();
        (frame, aabbs)
    }

    /// The frame of items with world boxes `boxes` (without storing them).
    fn bounding(boxes: impl Iterator<Item = ([f64; 3], [f64; 3])>) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut any = false;
        for (a, b) in boxes {
            lo = std::array::from_fn(|i| lo[i].min(a[i]));
            hi = std::array::from_fn(|i| hi[i].max(b[i]));
            any = true;
        }
        if !any {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        let centre: [f64; 3] = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
        let diag = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
        // (Plus the f64 rounding of ray restart points near a scene far from the world origin,
        // ≤ ε·|p| per coordinate with |p| ≲ |centre| + diag: see `clip`.)
        let far = centre.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let pad = (diag.max(f64::MIN_POSITIVE) * 2f64.powi(-16)).max(64.0 * f64::EPSILON * far);
        // obvhs works in a frame scaled by a power of two so the scene is about unit size (exact,
        // and it keeps every f32 quantity of a traversal far from obvhs's absolute constants:
        // a scene 1e-6 across was missed by the wide BVH, a fuzz finding).
        // Scaled by the padded box's size, not the diagonal alone: a scene of one point away from
        // the origin has diag = 0 and pad = 64·ε·|centre| (a fuzz finding, regression-point-scene-
        // pad: scaled by 2¹⁰⁰⁰ from the diagonal, its padded box overflowed f32 to ±∞ and obvhs's
        // child ordering panicked on the NaN centre).
        let size = (diag + 4.0 * pad).max(f64::MIN_POSITIVE);
        let scale = 2f64.powi(-(size.log2().round() as i32).clamp(-1000, 1000));
        let lo = std::array::from_fn(|i| lo[i] - 2.0 * pad);
        let hi = std::array::from_fn(|i| hi[i] + 2.0 * pad);
        Self { centre, lo, hi, pad, scale, any }
    }

    /// The padded `f32` box, in obvhs coordinates, of an item with world box `(a, b)`.
    #[inline]
    fn padded(&self, (a, b): ([f64; 3], [f64; 3])) -> Aabb {
        let to32 = |v: [f64; 3], s: f64| {
            let f = |i: usize| ((v[i] - self.centre[i] + s) * self.scale) as f32;
            Vec3A::new(f(0), f(1), f(2))
        };
        Aabb::new(to32(a, -self.pad), to32(b, self.pad))
    }

    /// Clip the ray's line restricted to distances `[s_lo, s_hi]` along the unit direction to
    /// the scene box and restart it just before the box; `None` when it misses.
    #[inline]
    fn restart(&self, ray: &Ray<f64>, s_lo: f64, s_hi: f64) -> Option<Restart> {
        if !self.any {
            return None;
        }
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let (o, d) = (ray.o.to_array(), dn.to_array());
        let (mut a, mut b) = (s_lo, s_hi);
        for i in 0..3 {
            if d[i] == 0.0 {
                if o[i] < self.lo[i] || o[i] > self.hi[i] {
                    return None;
                }
            } else {
                let t1 = (self.lo[i] - o[i]) / d[i];
                let t2 = (self.hi[i] - o[i]) / d[i];
                a = a.max(t1.min(t2));
                b = b.min(t1.max(t2));
            }
        }
        // Also rejects NaN bounds (a ray the validators let through never has them).
        if a.is_nan() || b.is_nan() || a > b {
            return None;
        }
        // Start a little before the box so the entry is at t ≥ 0 despite rounding. The restart
        // point is formed with one rounding per coordinate (fused o + d·t₀), so it lies within
        // ε·|p| of the ray's line — not ε·|o|, which for an origin far from a small scene would
        // exceed the box padding (a fuzz finding: origin 1e18 away from a 1e-6 scene).
        // Also `LEAD` before it in tree units, past the walk's absolute entry bound (module docs).
        let s0 = a - 4.0 * self.pad - LEAD / self.scale;
        let t0 = s0 / len;
        let p = V3::new(ray.d.x.mul_add(t0, ray.o.x), ray.d.y.mul_add(t0, ray.o.y), ray.d.z.mul_add(t0, ray.o.z));
        let rel = [p.x - self.centre[0], p.y - self.centre[1], p.z - self.centre[2]];
        Some(Restart { rel, dir: d, t0, len, s_end: (b - s0) + 8.0 * self.pad })
    }

    /// [`Self::restart`] as an obvhs ray in the frame's scaled `f32` coordinates.
    #[inline]
    fn clip(&self, ray: &Ray<f64>, s_lo: f64, s_hi: f64) -> Option<Clipped> {
        let r = self.restart(ray, s_lo, s_hi)?;
        let sc = self.scale;
        let org = Vec3A::from(r.rel.map(|x| (x * sc) as f32));
        // `+ 0.0` turns a −0.0 component (e.g. −sin 0, or a tiny negative rounded to f32) into
        // +0.0: obvhs takes the octant from the sign bit but the slab order from `d < 0`, and the
        // two disagree on −0.0 (a fuzz/CLI finding: the wide BVH missed axis-parallel rays).
        let dir = Vec3A::from(r.dir.map(|x| x as f32 + 0.0));
        let tmax = (r.s_end * sc) as f32;
        Some(Clipped { ray: obvhs::ray::Ray::new(org, dir, 0.0, tmax), t0: r.t0, len: r.len, scale: sc })
    }
}

/// A ray restarted just before the scene box: what a walk of the tree takes, on the CPU or a
/// GPU ([`TreeExport::restart`]). Distances along it are world units along the unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Restart {
    /// The restart point minus the frame's centre (world units; scale, then round to `f32`).
    pub rel: [f64; 3],
    /// The unit direction.
    pub dir: [f64; 3],
    /// The user's ray parameter `t` at the restart point.
    pub t0: f64,
    /// Length of the user's direction (`s = (t − t0)·len`).
    pub len: f64,
    /// Distance from the restart point past which the ray meets no box (the clipped exit plus
    /// the padding margin).
    pub s_end: f64,
}

/// The scene-box-clipped form of a ray, ready for obvhs.
struct Clipped {
    ray: obvhs::ray::Ray,
    /// Ray parameter (in the user's `t`) where the obvhs ray starts.
    t0: f64,
    /// Length of the user's direction.
    len: f64,
    /// The frame's scale (obvhs distances are unit-direction distances times this).
    scale: f64,
}

impl Bvh {
    /// Build over `prims` (obvhs PLOC builder, medium quality). An empty list gives a BVH that
    /// every ray misses.
    pub fn build(prims: Vec<Prim>) -> Self {
        let (frame, aabbs) = Frame::new(&prims);
        let mut bvh = if prims.is_empty() {
            Bvh2::default()
        } else {
            obvhs::bvh2::builder::build_bvh2(
                &aabbs,
                obvhs::BvhBuildParams::medium_build(),
                &mut std::time::Duration::default(),
            )
        };
        bvh.nodes.shrink_to_fit();
        // Reorder primitives into leaf order so leaves index them directly.
        #[allow(unused_mut)]
        let mut prims: Vec<Prim> = bvh.primitive_indices.iter().map(|&i| prims[i as usize]).collect();
        for (k, i) in bvh.primitive_indices.iter_mut().enumerate() {
            *i = k as u32;
        }
        #[cfg(feature = "wide")]
        let (packs, pack_at) = Self::pack(&bvh, &mut prims);
        Self {
            bvh,
            prims,
            frame,
            #[cfg(feature = "wide")]
            packs,
            #[cfg(feature = "wide")]
            pack_at,
        }
    }

    /// Move each leaf's links to its front (a stable partition, within the leaf's range) and
    /// gather them into lane packets of up to [`packet::LANES`]; a lone link stays scalar.
    #[cfg(feature = "wide")]
    fn pack(bvh: &Bvh2, prims: &mut [Prim]) -> (Vec<packet::Packet>, Vec<u32>) {
        use crate::scene::Shape;
        let is_link = |p: &Prim| matches!(p.shape, Shape::Cylinder(_) | Shape::Cone(_));
        let mut packs = Vec::new();
        let mut pack_at = vec![NO_PACK; prims.len()];
        for node in bvh.nodes.iter().filter(|n| n.is_leaf() && n.prim_count > 0) {
            let (s, e) = (node.first_index as usize, (node.first_index + node.prim_count) as usize);
            let leaf = &mut prims[s..e];
            let (mut links, others): (Vec<Prim>, Vec<Prim>) = leaf.iter().partition(|p| is_link(p));
            let k = links.len();
            links.extend(others);
            leaf.copy_from_slice(&links);
            let mut j = 0;
            while k - j >= 2 {
                let n = (k - j).min(packet::LANES);
                pack_at[s + j] = packs.len() as u32;
                let cones: Vec<_> = leaf[j..j + n].iter().filter_map(Prim::round_cone).collect();
                packs.push(packet::Packet::new(&cones));
                j += n;
            }
        }
        packs.shrink_to_fit();
        (packs, pack_at)
    }

    /// Test the primitives of the leaf `first..first + count` against `ray` (whose unit
    /// direction and length are `dn`, `len`): links in packets by one lane call each, the
    /// rest one by one, handing each test to `f`; stops and returns false as soon as `f`
    /// returns false.
    #[inline(always)]
    #[cfg_attr(not(feature = "wide"), allow(unused_variables))]
    fn visit(
        &self,
        first: usize,
        count: usize,
        ray: &Ray<f64>,
        dn: V3<f64>,
        len: f64,
        mut f: impl FnMut(Test) -> bool,
    ) -> bool {
        let end = first + count;
        let mut j = first;
        while j < end {
            #[cfg(feature = "wide")]
            {
                let k = self.pack_at[j];
                if k != NO_PACK {
                    let pk = &self.packs[k as usize];
                    let mut go = true;
                    pk.intersect(&self.prims[j..j + pk.n], ray, dn, len, |i, iv| {
                        if go {
                            go = f(Test::Link(j + i, iv));
                        }
                    });
                    if !go {
                        return false;
                    }
                    j += pk.n;
                    continue;
                }
            }
            if !f(Test::Prim(j)) {
                return false;
            }
            j += 1;
        }
        true
    }

    /// Unit direction and length of a ray's direction, computed as [`Prim::intersect`] does.
    #[inline(always)]
    fn unit(ray: &Ray<f64>) -> (V3<f64>, f64) {
        let len = ray.d.length();
        (ray.d * (1.0 / len), len)
    }

    /// Bytes held by the BVH nodes and the primitives (allocated capacity).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.nodes.capacity() * std::mem::size_of::<obvhs::bvh2::node::Bvh2Node>()
            + self.bvh.primitive_indices.capacity() * 4
            + self.prims.capacity() * std::mem::size_of::<Prim>()
            + self.packet_bytes()
    }

    #[cfg(feature = "wide")]
    fn packet_bytes(&self) -> usize {
        self.packs.capacity() * packet::Packet::BYTES + self.pack_at.capacity() * 4
    }

    #[cfg(not(feature = "wide"))]
    fn packet_bytes(&self) -> usize {
        0
    }

    /// Number of BVH nodes.
    pub fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }

    /// Distances along the unit direction for a ray's `[t_min, t_max]`.
    fn range(ray: &Ray<f64>) -> (f64, f64) {
        let len = ray.d.length();
        (ray.t_min * len, ray.t_max * len)
    }

    /// The closest surface crossing in `[t_min, t_max]` (entry, or exit when the ray starts
    /// inside a primitive). The ray must be valid ([`Ray::validate`]).
    pub fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        let (a, b) = Self::range(ray);
        let c = self.frame.clip(ray, a, b)?;
        let mut best: Option<Hit> = None;
        let mut hit = obvhs::ray::RayHit::none();
        let margin = 8.0 * self.frame.pad;
        let (dn, len) = Self::unit(ray);
        obvhs::fast_stack!(u32, (96, 192), self.bvh.max_depth, stack, {
            self.bvh.ray_traverse_dynamic(&mut stack, c.ray, &mut hit, |node, r, _| {
                let first = node.first_index as usize;
                self.visit(first, node.prim_count as usize, ray, dn, len, |test| {
                    let (id, got) = match test {
                        Test::Prim(id) => (id, self.prims[id].first_hit_unit(ray, dn, len)),
                        Test::Link(id, iv) => (id, iv.first_hit(ray.t_min, ray.t_max)),
                    };
                    if let Some(h) = got {
                        Hit { id: id as u32, ..h }.keep_closer(&mut best);
                    }
                    true
                });
                // Cull by the best hit so far, loosened by the box margin (see the module docs).
                if let Some(h) = best {
                    let tb = (((h.t - c.t0) * c.len + margin) * c.scale) as f32;
                    if tb < r.tmax {
                        r.tmax = tb;
                    }
                }
                true
            })
        });
        best
    }

    /// True when any primitive's surface or interior meets the ray within `[t_min, t_max]`
    /// (shadow and ambient-occlusion rays).
    pub fn any_hit(&self, ray: &Ray<f64>) -> bool {
        let (a, b) = Self::range(ray);
        let Some(c) = self.frame.clip(ray, a, b) else {
            return false;
        };
        let (dn, len) = Self::unit(ray);
        let mut found = false;
        let mut hit = obvhs::ray::RayHit::none();
        obvhs::fast_stack!(u32, (96, 192), self.bvh.max_depth, stack, {
            self.bvh.ray_traverse_dynamic(&mut stack, c.ray, &mut hit, |node, _, _| {
                let first = node.first_index as usize;
                found = !self.visit(first, node.prim_count as usize, ray, dn, len, |test| match test {
                    Test::Prim(id) => !self.prims[id].meets_unit(ray, dn, len),
                    Test::Link(..) => false,
                });
                !found
            })
        });
        found
    }

    /// Every primitive's interval with the ray's whole **line** (not only `[t_min, t_max]`),
    /// appended to `out` tagged with the primitive index — the input of
    /// [`tubecast::csg::union`]. A spline sub-segment contributes one interval per
    /// connected piece ([`Prim::pieces`]), so the union is exact for bent segments too.
    pub fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        let Some(c) = self.frame.clip(ray, f64::NEG_INFINITY, f64::INFINITY) else {
            return;
        };
        let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
        let (dn, len) = Self::unit(&line);
        let mut hit = obvhs::ray::RayHit::none();
        obvhs::fast_stack!(u32, (96, 192), self.bvh.max_depth, stack, {
            self.bvh.ray_traverse_dynamic(&mut stack, c.ray, &mut hit, |node, _, _| {
                let first = node.first_index as usize;
                self.visit(first, node.prim_count as usize, &line, dn, len, |test| {
                    match test {
                        Test::Prim(id) => self.prims[id].pieces(&line, |iv| out.push(Tagged { iv, id: id as u32 })),
                        Test::Link(id, iv) => out.push(Tagged { iv, id: id as u32 }),
                    }
                    true
                })
            })
        });
    }
}

/// Columns of a [`hit_table`], [`closest_table`] or [`crossings_table`] row.
pub const HIT_COLUMNS: usize = 8;

/// The part of the scene's surface union that a ray meets first: the entry and exit
/// boundaries of the first component of the union (over the whole line) that overlaps
/// `[t_min, t_max]`. The entry lies before `t_min` when the ray starts inside.
pub fn first_component(bvh: &dyn Tracer, ray: &Ray<f64>) -> Option<(Hit, Hit)> {
    let mut ivs = Vec::new();
    bvh.line_intervals(ray, &mut ivs);
    let mut b = Vec::new();
    tubecast::csg::union(&mut ivs, f64::NEG_INFINITY, f64::INFINITY, |x| b.push(x));
    b.chunks_exact(2).find(|p| p[1].t >= ray.t_min && p[0].t <= ray.t_max).map(|p| (p[0], p[1]))
}
