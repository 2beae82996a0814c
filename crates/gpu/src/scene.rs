//! The CPU's wide BVH on the GPU: its nodes uploaded as they are ([`WideBvh::export`]), its
//! items' primitives in leaf order, and closest-hit / any-hit queries for batches of `f64` rays.
//!
//! # Rays
//! Each ray is clipped to the scene box and restarted before it in `f64` on the CPU, exactly as
//! the CPU tracer does (`Frame::clip` in `tubecast_render::accel`), so the tree walk sees the
//! same `f32` ray, the same padded boxes and the same culling margin: its culling is as
//! conservative as the CPU's (the accel module's bound).
//!
//! # Where the GPU's answers differ from the CPU's, and by how much
//! The CPU moves a ray to each primitive's local origin in `f64` and rounds the local origin to
//! `f32` once. The GPU does the same move in `f32`, from the restart point `p` relative to the
//! tree centre (`o = fl(p − centre)`, `|o| ≤ R`: the scene box's half diagonal plus the restart
//! lead) and the primitive's origin relative to the centre (`g = fl(origin − centre)`,
//! `|g| ≤ R`): `tc = (g − o)·d̂`, `o_local = o + d̂·tc − g`. Each of `o`, `g` is off by at most
//! `ε/2` of its size per component; `g − o` and the dot product by a few `ε·2R`; the products
//! and the two sums by `ε·2R` each, and `d̂`'s own rounding (`≤ ε/2` per component, shared with
//! the CPU's kernel) moves the foot point by `ε/2·|tc| ≤ ε·R`. Altogether the GPU's local line is
//! the CPU's moved by `δ ≤ 16·ε·R` (`ε = 2⁻²⁴`, a factor of about two to spare), and its distance
//! `s = tc + τ` carries `ε·2R` more. A hit point therefore lies within `E + δ` of the exact
//! surface, where `E` is the kernel's bound ([`crate::kernel`]'s tests use it), and hit/miss can
//! differ from the CPU's only where the line passes within `2E + δ` of the surface. [`band`]
//! returns `δ` for a scene.

use crate::compute::Kernel;
use crate::device::{Gpu, GpuError};
use crate::kernel::LINK_WGSL;
use bytemuck::{Pod, Zeroable};
use tubecast::{Hit, Ray, V3};
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::scene::Shape;

const TREE_WGSL: &str = include_str!("../shaders/tree.wgsl");

/// How far (in tree units, beyond the `4·pad` margin) a ray restarts before the scene box: the
/// CPU tracer's `LEAD` (`tubecast_render::accel`), past obvhs's absolute `10⁻⁴` entry bound, which
/// the tree's planes inherit from the obvhs build.
const LEAD: f64 = 1.0 / 4096.0;

/// A tree node as the CPU stores it (`tubecast_render::accel::tree::Node`, `#[repr(C)]`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuNode {
    lo: [[f32; 8]; 3],
    hi: [[f32; 8]; 3],
    child: [u32; 8],
    count: [u32; 8],
}

/// One item's primitive: a link `(a, ra)–(b, rb)` (`kind` 0) or a sphere of radius `ra`
/// (`kind` 1), relative to `org`, its origin relative to the tree centre.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuPrim {
    a: [f32; 3],
    ra: f32,
    b: [f32; 3],
    rb: f32,
    org: [f32; 3],
    kind: u32,
}

/// A ray as the walk takes it (see `shaders/tree.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuRay {
    o: [f32; 3],
    s_min: f32,
    d: [f32; 3],
    s_max: f32,
    to: [f32; 3],
    tmax: f32,
    td: [f32; 3],
    valid: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuHit {
    n: [f32; 3],
    s: f32,
    u: f32,
    item: u32,
    entering: u32,
    _pad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n_rays: u32,
    n_items: u32,
    margin: f32,
    scale: f32,
}

/// The ray frame of a tree: the CPU tracer's `Frame`, rebuilt from the export and the
/// primitives' boxes.
struct RayFrame {
    centre: [f64; 3],
    lo: [f64; 3],
    hi: [f64; 3],
    pad: f64,
    scale: f64,
    any: bool,
}

/// A union component's entry and exit ([`GpuScene::first_pieces`]).
pub type Piece = (Hit<f64>, Hit<f64>);

/// How a closest-hit query visits the items.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// Through the wide BVH, nearest child first.
    Tree,
    /// Every item, no tree (the reference for the tree walk; slow).
    Brute,
}

/// A scene on the GPU: the wide BVH's nodes, its items' primitives, and the query pipelines.
pub struct GpuScene<'g> {
    gpu: &'g Gpu,
    nodes: wgpu::Buffer,
    prims: wgpu::Buffer,
    /// Per item: its primitive id ([`Tracer::prim`]).
    item_prims: Vec<u32>,
    frame: RayFrame,
    closest: Kernel,
    any: Kernel,
    brute: Kernel,
    piece: Kernel,
    bytes: u64,
}

/// Depth of the tree under `root` (1 for a root of leaves).
fn depth(nodes: &[GpuNode]) -> usize {
    let mut deepest = 0;
    let mut todo = if nodes.is_empty() { vec![] } else { vec![(0u32, 1usize)] };
    while let Some((n, d)) = todo.pop() {
        deepest = deepest.max(d);
        let node = &nodes[n as usize];
        for i in 0..8 {
            if node.count[i] == 0 && node.child[i] != u32::MAX {
                todo.push((node.child[i], d + 1));
            }
        }
    }
    deepest
}

impl<'g> GpuScene<'g> {
    /// Upload `bvh` (its nodes as built, its items' primitives in leaf order). Errors:
    /// [`GpuError::Unsupported`] for spline primitives, [`GpuError::TooLarge`] for a scene over
    /// the adapter's buffer limits.
    pub fn upload(gpu: &'g Gpu, bvh: &WideBvh) -> Result<Self, GpuError> {
        let ex = bvh.export();
        let nodes: Vec<GpuNode> =
            ex.nodes.iter().map(|n| GpuNode { lo: n.lo, hi: n.hi, child: n.child, count: n.count }).collect();
        let c = ex.centre;
        let rel = |o: [f64; 3]| [(o[0] - c[0]) as f32, (o[1] - c[1]) as f32, (o[2] - c[2]) as f32];
        let mut prims = Vec::with_capacity(ex.item_prims.len());
        for &id in &ex.item_prims {
            let p = bvh.prim(id);
            let org = rel(p.origin);
            prims.push(match p.shape {
                Shape::Sphere { r } => GpuPrim { a: [0.0; 3], ra: r, b: [0.0; 3], rb: r, org, kind: 1 },
                Shape::Cylinder(l) | Shape::Cone(l) => {
                    GpuPrim { a: l.a.to_array(), ra: l.ra, b: l.b.to_array(), rb: l.rb, org, kind: 0 }
                }
                Shape::Spline { .. } => {
                    return Err(GpuError::Unsupported("spline primitives (use the links model)".into()))
                }
            });
        }
        // The scene box as the CPU's frame bounds it: the primitives' boxes, padded by 2·pad.
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for id in 0..bvh.prim_count() as u32 {
            let (a, b) = bvh.prim(id).aabb();
            for i in 0..3 {
                lo[i] = lo[i].min(a[i] - 2.0 * ex.pad);
                hi[i] = hi[i].max(b[i] + 2.0 * ex.pad);
            }
        }
        let frame = RayFrame { centre: c, lo, hi, pad: ex.pad, scale: ex.scale, any: !ex.empty && !nodes.is_empty() };
        // Seven pushes a level at most (Tree::walk).
        let stack = 7 * (depth(&nodes) + 1);
        let src = format!("{LINK_WGSL}\n{}", TREE_WGSL.replace("STACK_SIZE", &stack.to_string()));
        let bytes = (nodes.len() * 256 + prims.len() * std::mem::size_of::<GpuPrim>()) as u64;
        Ok(Self {
            gpu,
            nodes: gpu.upload("tree nodes", &nodes)?,
            prims: gpu.upload("primitives", &prims)?,
            item_prims: ex.item_prims,
            frame,
            closest: gpu.kernel(&src, "closest_tree", 3)?,
            any: gpu.kernel(&src, "any_tree", 3)?,
            brute: gpu.kernel(&src, "closest_brute", 3)?,
            piece: gpu.kernel(&src, "first_piece", 3)?,
            bytes,
        })
    }

    /// Bytes uploaded for the scene (nodes and primitives).
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// The ray as the walk takes it, with `t0` (the restart, in the ray's `t`) and `|d|`
    /// (`Frame::clip`, same operations).
    fn prepare(&self, ray: &Ray<f64>) -> (GpuRay, f64, f64) {
        let f = &self.frame;
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let miss = (GpuRay::zeroed(), 0.0, len);
        if !f.any {
            return miss;
        }
        let (o, d) = (ray.o.to_array(), dn.to_array());
        let (mut a, mut b) = (ray.t_min * len, ray.t_max * len);
        for i in 0..3 {
            if d[i] == 0.0 {
                if o[i] < f.lo[i] || o[i] > f.hi[i] {
                    return miss;
                }
            } else {
                let t1 = (f.lo[i] - o[i]) / d[i];
                let t2 = (f.hi[i] - o[i]) / d[i];
                a = a.max(t1.min(t2));
                b = b.min(t1.max(t2));
            }
        }
        if a.is_nan() || b.is_nan() || a > b {
            return miss;
        }
        let s0 = a - 4.0 * f.pad - LEAD / f.scale;
        let t0 = s0 / len;
        let p = V3::new(ray.d.x.mul_add(t0, ray.o.x), ray.d.y.mul_add(t0, ray.o.y), ray.d.z.mul_add(t0, ray.o.z));
        let rel = [p.x - f.centre[0], p.y - f.centre[1], p.z - f.centre[2]];
        let g = GpuRay {
            o: rel.map(|x| x as f32),
            s_min: ((ray.t_min - t0) * len) as f32,
            d: dn.cast::<f32>().to_array(),
            s_max: ((ray.t_max - t0) * len) as f32,
            to: rel.map(|x| (x * f.scale) as f32),
            tmax: (((b - s0) + 8.0 * f.pad) * f.scale) as f32,
            td: d.map(|x| x as f32 + 0.0),
            valid: 1,
        };
        (g, t0, len)
    }

    /// Run `k` over `rays`, `per` outputs per ray, mapped back to hits in the rays' `t`.
    fn query(&self, k: &Kernel, rays: &[Ray<f64>], per: usize) -> Result<Vec<Option<Hit<f64>>>, GpuError> {
        let prep: Vec<(GpuRay, f64, f64)> = rays.iter().map(|r| self.prepare(r)).collect();
        let input: Vec<GpuRay> = prep.iter().map(|p| p.0).collect();
        let buf = self.gpu.upload("rays", &input)?;
        let params = Params {
            n_rays: rays.len() as u32,
            n_items: self.item_prims.len() as u32,
            margin: (8.0 * self.frame.pad) as f32,
            scale: self.frame.scale as f32,
        };
        let out: Vec<GpuHit> = self.gpu.run(k, &params, &[&self.nodes, &self.prims, &buf], per * rays.len())?;
        Ok(out
            .iter()
            .zip(prep.iter().flat_map(|p| std::iter::repeat_n(p, per)))
            .map(|(h, &(_, t0, len))| {
                (h.item != u32::MAX).then(|| Hit {
                    t: t0 + f64::from(h.s) / len,
                    n: V3::from(h.n).cast(),
                    u: f64::from(h.u),
                    id: self.item_prims[h.item as usize],
                    entering: h.entering != 0,
                })
            })
            .collect())
    }

    /// The closest surface crossing of each ray in its `[t_min, t_max]` (entry, or exit for a
    /// ray starting inside), its `id` the primitive's ([`Tracer::prim`]). Rays must be valid.
    pub fn closest_hits(&self, rays: &[Ray<f64>], walk: Walk) -> Result<Vec<Option<Hit<f64>>>, GpuError> {
        self.query(if walk == Walk::Tree { &self.closest } else { &self.brute }, rays, 1)
    }

    /// Whether each ray meets a primitive's surface in its `[t_min, t_max]` (shadow and AO rays).
    pub fn any_hits(&self, rays: &[Ray<f64>]) -> Result<Vec<bool>, GpuError> {
        Ok(self.query(&self.any, rays, 1)?.iter().map(Option::is_some).collect())
    }

    /// The entry and exit of the first component of the union of every primitive's line
    /// interval that reaches each ray's `[t_min, t_max]`
    /// ([`tubecast_render::accel::first_component`], the `intersect --query piece` answer).
    pub fn first_pieces(&self, rays: &[Ray<f64>]) -> Result<Vec<Option<Piece>>, GpuError> {
        let out = self.query(&self.piece, rays, 2)?;
        Ok(out.chunks_exact(2).map(|p| p[0].zip(p[1])).collect())
    }

    /// The bound `δ` of the module docs: how far the GPU's local lines may lie from the CPU's
    /// (`16·2⁻²⁴·R`, `R` the distance from the centre to the padded scene box's corner plus
    /// the restart lead).
    pub fn band(&self) -> f64 {
        let f = &self.frame;
        if !f.any {
            return 0.0;
        }
        let r = (0..3).map(|i| (f.hi[i] - f.lo[i]).powi(2)).sum::<f64>().sqrt() * 0.5 + 4.0 * f.pad + LEAD / f.scale;
        16.0 * f64::from(f32::EPSILON) * 0.5 * r
    }
}
