//! The CPU's wide BVH on the GPU: its nodes uploaded as they are ([`WideBvh::export`]), its
//! items' primitives in leaf order, and closest-hit, any-hit, first-component and line-interval
//! queries for batches of `f64` rays.
//!
//! # Rays
//! Each ray is clipped to the scene box and restarted before it in `f64` on the CPU, exactly as
//! the CPU tracer does (the tree's own [`TreeExport::restart`]), so the tree walk sees the
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
//! surface, where `E` is the kernel's bound ([`crate::kernel`]'s tests use it; for a spline
//! piece twice the band of `tubecast::spline_error_band`, which bounds the error both across the
//! surface and along the ray), and hit/miss can differ from the CPU's only where the line passes
//! within `2E + δ` of the surface. [`GpuScene::band`] returns `δ` for a scene.

use crate::compute::Kernel;
use crate::device::{Gpu, GpuError};
use crate::kernel::{LINK_WGSL, SPLINE_WGSL};
use bytemuck::{Pod, Zeroable};
use std::sync::OnceLock;
use tubecast::csg::Tagged;
use tubecast::{Crossing, Hit, Interval, Ray, V3};
use tubecast_render::accel::{Tracer, TreeExport, WideBvh};
use tubecast_render::scene::Shape;

const TREE_WGSL: &str = include_str!("../shaders/tree.wgsl");
const LINES_WGSL: &str = include_str!("../shaders/lines.wgsl");
/// The spline kernel's entry points as misses, for scenes without spline pieces (why: the
/// file's own comment).
const NO_SPLINE_WGSL: &str = include_str!("../shaders/no_spline.wgsl");

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
/// (`kind` 1), relative to `org`, its origin relative to the tree centre; or a spline piece
/// (`kind & 3 == 2`): control points `a`, `b₁`, `b` and radii `ra`, `r₁`, `rb`, where `b₁`,
/// `r₁` are the `a`, `ra` of the record `kind >> 2` (appended after the items' records, so
/// that links and spheres keep their 48 bytes).
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
    /// The driver cut the walk's loops short (`shaders/tree.wgsl`'s `loops_cut`).
    cut: u32,
}

impl GpuHit {
    /// tree.wgsl's `closer`: `self` is a crossing nearer than `b` (equal: the lower item).
    fn closer(&self, b: &GpuHit) -> bool {
        self.item != NONE && (b.item == NONE || self.s < b.s || (self.s == b.s && self.item < b.item))
    }
}

/// tree.wgsl's `NONE`: no item.
const NONE: u32 = u32::MAX;

/// Threads of a workgroup (`@workgroup_size(64)`): a ray rerun alone takes a whole workgroup,
/// wider than any SIMD vector lavapipe runs, so that no other ray shares its loop budget.
const GROUP_THREADS: usize = 64;

/// The items a brute-force dispatch tries at first with spline pieces in the scene (then
/// halved where lavapipe's loop budget runs out): a spline piece's solves take tens to hundreds
/// of loop passes, and the budget is 65 535 (`shaders/tree.wgsl`'s `loops_cut`).
const BRUTE_SPLINE_ITEMS: u32 = 256;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n_rays: u32,
    n_items: u32,
    margin: f32,
    scale: f32,
    item_lo: u32,
    item_hi: u32,
    _pad: [u32; 2],
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
    /// The nodes and the primitives, each split across [`Gpu::SPLIT`] buffers
    /// ([`Gpu::upload_split`]), and how many of each hold records.
    nodes: Vec<wgpu::Buffer>,
    prims: Vec<wgpu::Buffer>,
    used: [usize; 2],
    /// The tree as exported: its items' primitive ids ([`Tracer::prim`]), its frame, and the
    /// restart of every ray ([`TreeExport::restart`]).
    ex: TreeExport<'g>,
    closest: Kernel,
    any: Kernel,
    /// The brute-force and first-component kernels, built on first use (a render needs neither,
    /// and each pipeline costs a shader compile, a long one with the spline kernel).
    brute: OnceLock<Kernel>,
    seed: OnceLock<Kernel>,
    span: OnceLock<Kernel>,
    /// The line-interval kernels (count, list), built on first use from `tree` (tree.wgsl
    /// with its stack size).
    lines: OnceLock<(Kernel, Kernel)>,
    tree: String,
    /// Whether the scene holds spline pieces (the modules then carry the spline kernel).
    splines: bool,
    bytes: u64,
}

/// The read-only storage inputs of the queries' kernels: the split nodes and primitives, and
/// the rays (tree.wgsl's bindings 1 to 9).
const INPUTS: usize = 2 * Gpu::SPLIT + 1;

/// tree.wgsl's accessor `name` of the records of kind `ty` in the bindings `var`0, `var`1, …:
/// record `i` is record `i mod per` of binding `i / per`, `used` of them holding records. One
/// binding is read directly; several by branches on the binding (no loop: lavapipe's loop
/// budget).
fn accessor(name: &str, ty: &str, var: &str, per: u32, used: usize) -> String {
    if used <= 1 {
        return format!("fn {name}(i: u32) -> {ty} {{\n    return {var}0[i];\n}}\n");
    }
    let mut s = format!("fn {name}(i: u32) -> {ty} {{\n    let c = i / {per}u;\n    let j = i - c * {per}u;\n");
    for b in 0..used - 1 {
        s += &format!("    if c == {b}u {{\n        return {var}{b}[j];\n    }}\n");
    }
    s + &format!("    return {var}{}[j];\n}}\n", used - 1)
}

/// `xs` spread one per workgroup for a rerun: item j at slot `GROUP_THREADS·j` (thread i runs
/// ray i), alone in workgroup j, whose other slots hold `empty` (an invalid ray, which walks
/// nothing; a count of 0), so that no two rerun rays share a SIMD vector's loop budget.
fn one_per_group<T: Copy>(xs: impl ExactSizeIterator<Item = T>, empty: T) -> Vec<T> {
    let n = xs.len();
    let mut out = vec![empty; GROUP_THREADS * n.saturating_sub(1) + 1];
    for (j, x) in xs.enumerate() {
        out[GROUP_THREADS * j] = x;
    }
    out
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
    /// Upload `bvh` (its nodes as built, its items' primitives in leaf order: links, spheres and
    /// spline pieces). Errors: [`GpuError::TooLarge`] for a scene over the adapter's buffer
    /// limits.
    pub fn upload(gpu: &'g Gpu, bvh: &'g WideBvh) -> Result<Self, GpuError> {
        let ex = bvh.export();
        let nodes: Vec<GpuNode> =
            ex.nodes.iter().map(|n| GpuNode { lo: n.lo, hi: n.hi, child: n.child, count: n.count }).collect();
        let c = ex.centre;
        let rel = |o: [f64; 3]| [(o[0] - c[0]) as f32, (o[1] - c[1]) as f32, (o[2] - c[2]) as f32];
        let mut prims = Vec::with_capacity(ex.item_prims.len());
        // The spline pieces' middle control points and radii, appended after the items.
        let mut middles = Vec::new();
        for &id in &ex.item_prims {
            let p = bvh.prim(id);
            let org = rel(p.origin);
            prims.push(match p.shape {
                Shape::Sphere { r } => GpuPrim { a: [0.0; 3], ra: r, b: [0.0; 3], rb: r, org, kind: 1 },
                Shape::Cylinder(l) | Shape::Cone(l) => {
                    GpuPrim { a: l.a.to_array(), ra: l.ra, b: l.b.to_array(), rb: l.rb, org, kind: 0 }
                }
                Shape::Spline { quad: q, .. } => {
                    // The record's index must fit the kind word's upper 30 bits (2³⁰ records of
                    // 48 bytes, 48 GiB, are far above the four bindings of any adapter anyway).
                    let index = ex.item_prims.len() + middles.len();
                    if index >= 1 << 30 {
                        let bytes = (index as u64 + 1) * std::mem::size_of::<GpuPrim>() as u64;
                        let limit = Gpu::SPLIT as u64 * gpu.max_binding();
                        return Err(GpuError::TooLarge { what: "primitives", bytes, limit });
                    }
                    let index = index as u32;
                    middles.push(GpuPrim { a: q.b[1].to_array(), ra: q.r[1], b: [0.0; 3], rb: 0.0, org, kind: 2 });
                    GpuPrim {
                        a: q.b[0].to_array(),
                        ra: q.r[0],
                        b: q.b[2].to_array(),
                        rb: q.r[2],
                        org,
                        kind: 2 | index << 2,
                    }
                }
            });
        }
        let splines = !middles.is_empty();
        prims.extend(middles);
        // Seven pushes a level at most (Tree::walk).
        let stack = 7 * (depth(&nodes) + 1);
        let bytes = (nodes.len() * 256 + prims.len() * std::mem::size_of::<GpuPrim>()) as u64;
        let (node_bufs, node_per) = gpu.upload_split("tree nodes", &nodes, gpu.split[0])?;
        let (prim_bufs, prim_per) = gpu.upload_split("primitives", &prims, gpu.split[1])?;
        let used = [nodes.len().div_ceil(node_per as usize).max(1), prims.len().div_ceil(prim_per as usize).max(1)];
        let accessors = accessor("node_at", "Node", "nodes", node_per, used[0])
            + &accessor("prim_at", "Prim", "prims", prim_per, used[1]);
        let tree = TREE_WGSL.replace("STACK_SIZE", &stack.to_string()).replace("ACCESSORS", &accessors);
        let src = Self::module(&tree, false, splines);
        Ok(Self {
            gpu,
            nodes: node_bufs,
            prims: prim_bufs,
            used,
            ex,
            closest: gpu.kernel(&src, "closest_tree", INPUTS)?,
            any: gpu.kernel(&src, "any_tree", INPUTS)?,
            brute: OnceLock::new(),
            seed: OnceLock::new(),
            span: OnceLock::new(),
            lines: OnceLock::new(),
            tree,
            splines,
            bytes,
        })
    }

    /// The shader module: the link and spline kernels (the spline kernel's stubs where the
    /// scene has no spline pieces: `splines` false) and `tree` (tree.wgsl with its stack size),
    /// its output after the inputs (binding `INPUTS + 1`); or one further, with lines.wgsl (its
    /// offsets before it), for `list_lines`.
    fn module(tree: &str, list: bool, splines: bool) -> String {
        let spline = if splines { SPLINE_WGSL } else { NO_SPLINE_WGSL };
        if list {
            format!("{LINK_WGSL}\n{spline}\n{}\n{LINES_WGSL}", tree.replace("OUT_BINDING", &(INPUTS + 2).to_string()))
        } else {
            format!("{LINK_WGSL}\n{spline}\n{}", tree.replace("OUT_BINDING", &(INPUTS + 1).to_string()))
        }
    }

    /// Bytes uploaded for the scene (nodes and primitives).
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// How many bindings the scene's tree nodes and its primitives take (each at most
    /// [`Gpu::SPLIT`]; more than one where a kind is over [`Gpu::max_binding`]).
    #[doc(hidden)]
    pub fn bindings(&self) -> [usize; 2] {
        self.used
    }

    /// The bind group's inputs: the split nodes and primitives, then `more` (the rays, and the
    /// interval offsets of `list_lines`).
    fn bind<'a>(&'a self, more: &[&'a wgpu::Buffer]) -> Vec<&'a wgpu::Buffer> {
        self.nodes.iter().chain(&self.prims).chain(more.iter().copied()).collect()
    }

    /// The rays of one dispatch with `per` outputs each: as many as the rays' and the outputs'
    /// buffers hold within [`Gpu::max_binding`], a whole number of workgroups (so that the
    /// reruns of [`Self::run_rays`] keep each ray alone in its workgroup), at least one.
    fn batch(&self, per: usize) -> usize {
        let limit = self.gpu.max_binding() as usize;
        let rays = limit / std::mem::size_of::<GpuRay>();
        let outs = if per == 0 { rays } else { limit / (per * std::mem::size_of::<GpuHit>()) };
        (rays.min(outs) / GROUP_THREADS * GROUP_THREADS).max(GROUP_THREADS)
    }

    /// Run `k` over the prepared rays `input`, `per` outputs per ray, over the items `items`,
    /// in dispatches of [`Self::batch`] rays: the rays and outputs of a large query need not fit
    /// one binding.
    fn dispatch(&self, k: &Kernel, input: &[GpuRay], per: usize, items: (u32, u32)) -> Result<Vec<GpuHit>, GpuError> {
        let mut out = Vec::with_capacity(per * input.len());
        for chunk in input.chunks(self.batch(per)) {
            let buf = self.gpu.upload("rays", chunk)?;
            let got: Vec<GpuHit> = self.gpu.run_sized(
                k,
                &self.params(chunk.len(), items),
                &self.bind(&[&buf]),
                chunk.len(),
                per * chunk.len(),
            )?;
            out.extend(got);
        }
        Ok(out)
    }

    /// The ray as the walk takes it, with `t0` (the restart, in the ray's `t`) and `|d|`: the
    /// CPU walk's own restart ([`TreeExport::restart`]), rounded to `f32` as the CPU rounds it
    /// (origin `rel·scale`, direction with `+ 0.0`, `tmax = s_end·scale`) for the tree, and
    /// unscaled for the primitives' local origins.
    fn prepare(&self, ray: &Ray<f64>) -> (GpuRay, f64, f64) {
        self.prepare_over(ray, false)
    }

    /// [`Self::prepare`], the walk over the ray's whole line where `line` (its range still in
    /// `s_min`, `s_max`): as the CPU's `Tracer::line_intervals` walks it.
    fn prepare_over(&self, ray: &Ray<f64>, line: bool) -> (GpuRay, f64, f64) {
        let len = ray.d.length();
        let (s_lo, s_hi) = if line { (f64::NEG_INFINITY, f64::INFINITY) } else { (ray.t_min * len, ray.t_max * len) };
        // (An empty tree has no root to walk: every ray misses, as `restart` says for it too.)
        let restart = if self.ex.nodes.is_empty() { None } else { self.ex.restart(ray, s_lo, s_hi) };
        let Some(r) = restart else {
            return (GpuRay::zeroed(), 0.0, len);
        };
        let sc = self.ex.scale;
        let g = GpuRay {
            o: r.rel.map(|x| x as f32),
            s_min: ((ray.t_min - r.t0) * r.len) as f32,
            d: r.dir.map(|x| x as f32),
            s_max: ((ray.t_max - r.t0) * r.len) as f32,
            to: r.rel.map(|x| (x * sc) as f32),
            tmax: (r.s_end * sc) as f32,
            td: r.dir.map(|x| x as f32 + 0.0),
            valid: 1,
        };
        (g, r.t0, r.len)
    }

    /// The uniform of a dispatch over `n` rays (the brute force over the items `items`).
    fn params(&self, n: usize, items: (u32, u32)) -> Params {
        Params {
            n_rays: n as u32,
            n_items: self.ex.item_prims.len() as u32,
            margin: (8.0 * self.ex.pad) as f32,
            scale: self.ex.scale as f32,
            item_lo: items.0,
            item_hi: items.1,
            _pad: [0; 2],
        }
    }

    /// All items, for [`Self::params`].
    fn all_items(&self) -> (u32, u32) {
        (0, self.ex.item_prims.len() as u32)
    }

    /// Run `k` over the prepared rays `input`, `per` outputs per ray, over the items `items`
    /// (brute force only). Each ray whose loops the driver cut short (lavapipe's loop budget,
    /// shared by the rays of one SIMD vector: `shaders/tree.wgsl`'s `loops_cut`) is run again
    /// alone in a workgroup; cut short alone too, it is an error: never a wrong answer.
    fn run_rays(&self, k: &Kernel, input: &[GpuRay], per: usize, items: (u32, u32)) -> Result<Vec<GpuHit>, GpuError> {
        let mut out = self.dispatch(k, input, per, items)?;
        let cut: Vec<usize> =
            (0..input.len()).filter(|&i| out[per * i..per * (i + 1)].iter().any(|h| h.cut != 0)).collect();
        if cut.is_empty() {
            return Ok(out);
        }
        let alone = one_per_group(cut.iter().map(|&i| input[i]), GpuRay::zeroed());
        let again = self.dispatch(k, &alone, per, items)?;
        for (j, &i) in cut.iter().enumerate() {
            let got = &again[per * GROUP_THREADS * j..per * (GROUP_THREADS * j + 1)];
            if got.iter().any(|h| h.cut != 0) {
                return Err(GpuError::LoopLimit(format!("ray {i} of the batch")));
            }
            out[per * i..per * (i + 1)].copy_from_slice(got);
        }
        Ok(out)
    }

    /// The brute-force closest hits of the prepared rays: dispatches over item ranges, merged
    /// by tree.wgsl's `closer` (a total order on `(s, item)`, so the merge is the one-pass
    /// answer), a range halved for the rays whose loops the driver cut short there.
    fn brute(&self, input: &[GpuRay]) -> Result<Vec<GpuHit>, GpuError> {
        let k = self.lazy(&self.brute, "closest_brute")?;
        let mut best = vec![GpuHit { item: NONE, ..GpuHit::zeroed() }; input.len()];
        let n = self.ex.item_prims.len() as u32;
        let first = if self.splines { BRUTE_SPLINE_ITEMS } else { n.max(1) };
        let all: Vec<usize> = (0..input.len()).collect();
        let mut todo: Vec<(Vec<usize>, u32, u32)> =
            (0..n.div_ceil(first)).map(|c| (all.clone(), c * first, ((c + 1) * first).min(n))).collect();
        while let Some((which, lo, hi)) = todo.pop() {
            let rays: Vec<GpuRay> = which.iter().map(|&i| input[i]).collect();
            // One item per dispatch: the rerun alone decides (or fails).
            let out = if hi - lo <= 1 {
                self.run_rays(k, &rays, 1, (lo, hi))?
            } else {
                self.dispatch(k, &rays, 1, (lo, hi))?
            };
            let mut cut = Vec::new();
            for (h, &i) in out.iter().zip(&which) {
                if h.cut != 0 {
                    cut.push(i);
                } else if h.closer(&best[i]) {
                    best[i] = *h;
                }
            }
            if !cut.is_empty() {
                let mid = lo + (hi - lo) / 2;
                todo.push((cut.clone(), lo, mid));
                todo.push((cut, mid, hi));
            }
        }
        Ok(best)
    }

    /// A GPU crossing in the ray's `t` (`t0`, `len` from [`Self::prepare`]); `None` for none.
    fn hit(&self, h: &GpuHit, t0: f64, len: f64) -> Option<Hit<f64>> {
        (h.item != u32::MAX).then(|| Hit {
            t: t0 + f64::from(h.s) / len,
            n: V3::from(h.n).cast(),
            u: f64::from(h.u),
            id: self.ex.item_prims[h.item as usize],
            entering: h.entering != 0,
        })
    }

    /// Run `k` over `rays` (the brute force where `k` is `None`), `per` outputs per ray, mapped
    /// back to hits in the rays' `t`.
    fn query(&self, k: Option<&Kernel>, rays: &[Ray<f64>], per: usize) -> Result<Vec<Option<Hit<f64>>>, GpuError> {
        let prep: Vec<(GpuRay, f64, f64)> = rays.iter().map(|r| self.prepare(r)).collect();
        let input: Vec<GpuRay> = prep.iter().map(|p| p.0).collect();
        let out = match k {
            Some(k) => self.run_rays(k, &input, per, self.all_items())?,
            None => self.brute(&input)?,
        };
        Ok(out
            .iter()
            .zip(prep.iter().flat_map(|p| std::iter::repeat_n(p, per)))
            .map(|(h, &(_, t0, len))| self.hit(h, t0, len))
            .collect())
    }

    /// The closest surface crossing of each ray in its `[t_min, t_max]` (entry, or exit for a
    /// ray starting inside), its `id` the primitive's ([`Tracer::prim`]). Rays must be valid.
    pub fn closest_hits(&self, rays: &[Ray<f64>], walk: Walk) -> Result<Vec<Option<Hit<f64>>>, GpuError> {
        let k = if walk == Walk::Tree { Some(&self.closest) } else { None };
        self.query(k, rays, 1)
    }

    /// Whether each ray meets a primitive's surface in its `[t_min, t_max]` (shadow and AO rays).
    pub fn any_hits(&self, rays: &[Ray<f64>]) -> Result<Vec<bool>, GpuError> {
        Ok(self.query(Some(&self.any), rays, 1)?.iter().map(Option::is_some).collect())
    }

    /// The entry and exit of the first component of the union of every primitive's line
    /// interval that reaches each ray's `[t_min, t_max]`
    /// ([`tubecast_render::accel::first_component`], the `intersect --query piece` answer).
    ///
    /// The seed interval, then steps that widen the span to every interval meeting it, one
    /// walk per ray and dispatch (`shaders/tree.wgsl`'s `seed_piece`, `span_piece`), the span
    /// compared in `f32` as the walk gives it. The walks cover the whole line, as the CPU's: a
    /// ray starting inside the union has its component's entry behind the origin, reached
    /// through intervals that may lie wholly behind it (restarted at the origin, the walk missed
    /// those, and the entry came out late).
    pub fn first_pieces(&self, rays: &[Ray<f64>]) -> Result<Vec<Option<Piece>>, GpuError> {
        let (seed, span) = (self.lazy(&self.seed, "seed_piece")?, self.lazy(&self.span, "span_piece")?);
        let prep: Vec<(GpuRay, f64, f64)> = rays.iter().map(|r| self.prepare_over(r, true)).collect();
        let input: Vec<GpuRay> = prep.iter().map(|p| p.0).collect();
        let mut f = self.run_rays(seed, &input, 2, self.all_items())?;
        let mut growing: Vec<usize> = (0..input.len()).filter(|&i| f[2 * i].item != NONE).collect();
        // Each step that grows adds an item's interval: at most one step per item, and a last
        // that finds no growth.
        for _ in 0..=self.ex.item_prims.len() {
            if growing.is_empty() {
                break;
            }
            let spans: Vec<GpuRay> =
                growing.iter().map(|&i| GpuRay { s_min: f[2 * i].s, s_max: f[2 * i + 1].s, ..input[i] }).collect();
            let g = self.run_rays(span, &spans, 2, self.all_items())?;
            let mut still = Vec::new();
            for (j, &i) in growing.iter().enumerate() {
                let grew = g[2 * j].s < f[2 * i].s || g[2 * j + 1].s > f[2 * i + 1].s;
                f[2 * i] = g[2 * j];
                f[2 * i + 1] = g[2 * j + 1];
                if grew {
                    still.push(i);
                }
            }
            growing = still;
        }
        Ok((0..input.len())
            .map(|i| {
                let (_, t0, len) = prep[i];
                // A component that begins past the range does not reach it.
                if f[2 * i].item == NONE || f[2 * i].s > input[i].s_max {
                    return None;
                }
                self.hit(&f[2 * i], t0, len).zip(self.hit(&f[2 * i + 1], t0, len))
            })
            .collect())
    }

    /// Every primitive's line interval that meets each ray's `[t_min, t_max]` (closed), tagged
    /// with the primitive's id ([`Tracer::prim`]), in no particular order: the intervals of
    /// [`Tracer::line_intervals`] that reach the range. The union's boundaries within the range
    /// ([`tubecast::csg::union`] with the ray's `t_min`, `t_max`) are the same with or without
    /// the others: an interval wholly outside the range covers no point of it.
    ///
    /// Two walks per ray: one counts the intervals, the second writes them where the counts'
    /// prefix sums put them. Errors: the GPU's, and [`GpuError::TooLarge`] for a ray with more
    /// intervals than one output buffer holds.
    pub fn line_intervals(&self, rays: &[Ray<f64>]) -> Result<Vec<Vec<Tagged<f64>>>, GpuError> {
        let (count, list) = self.line_kernels()?;
        let prep: Vec<(GpuRay, f64, f64)> = rays.iter().map(|r| self.prepare(r)).collect();
        let input: Vec<GpuRay> = prep.iter().map(|p| p.0).collect();
        let counts: Vec<u32> = self.run_rays(count, &input, 1, self.all_items())?.iter().map(|c| c.item).collect();
        // Runs of rays whose intervals fit one output buffer (an entry and an exit each), and
        // whose rays fit one binding.
        let fit = (self.gpu.max_binding() / (2 * std::mem::size_of::<GpuHit>() as u64)).max(1);
        let most = self.batch(0);
        let mut all = Vec::with_capacity(rays.len());
        let mut start = 0;
        while start < rays.len() {
            let (mut end, mut total) = (start, 0u64);
            while end < rays.len() && end - start < most && (end == start || total + u64::from(counts[end]) <= fit) {
                total += u64::from(counts[end]);
                end += 1;
            }
            let mut lists = self.list_run(list, &input[start..end], &counts[start..end])?;
            // Rays whose list walk the driver cut short: again, each alone in a workgroup
            // (`Self::run_rays`), with empty lists between them, as many a dispatch as the rays'
            // binding holds (their intervals are some of the run's: they fit).
            let cut_all: Vec<usize> =
                (0..lists.len()).filter(|&k| lists[k].first().is_some_and(|h| h.cut != 0)).collect();
            for cut in cut_all.chunks(most / GROUP_THREADS) {
                let alone = one_per_group(cut.iter().map(|&k| input[start + k]), GpuRay::zeroed());
                let alone_counts = one_per_group(cut.iter().map(|&k| counts[start + k]), 0);
                let again = self.list_run(list, &alone, &alone_counts)?;
                for (j, &k) in cut.iter().enumerate() {
                    let got = &again[GROUP_THREADS * j];
                    if got.first().is_some_and(|h| h.cut != 0) {
                        return Err(GpuError::LoopLimit(format!("ray {} of the batch", start + k)));
                    }
                    lists[k] = got.clone();
                }
            }
            for (k, l) in lists.iter().enumerate() {
                let (_, t0, len) = prep[start + k];
                all.push(
                    l.chunks_exact(2)
                        .filter_map(|p| {
                            let (e, x) = (self.hit(&p[0], t0, len)?, self.hit(&p[1], t0, len)?);
                            let c = |h: Hit<f64>| Crossing { t: h.t, n: h.n, u: h.u };
                            Some(Tagged { iv: Interval::new(c(e), c(x), true), id: e.id })
                        })
                        .collect(),
                );
            }
            start = end;
        }
        Ok(all)
    }

    /// The list kernel over `input` with the intervals `counts` says each ray has: each ray's
    /// entry/exit pairs (the first entry's `cut` set where the walk was cut short).
    fn list_run(&self, list: &Kernel, input: &[GpuRay], counts: &[u32]) -> Result<Vec<Vec<GpuHit>>, GpuError> {
        let offsets: Vec<u32> = std::iter::once(0)
            .chain(counts.iter().scan(0u32, |acc, &c| {
                *acc += c;
                Some(*acc)
            }))
            .collect();
        let total = offsets[offsets.len() - 1] as usize;
        let chunk = self.gpu.upload("rays", input)?;
        let offs = self.gpu.upload("interval offsets", &offsets)?;
        let out: Vec<GpuHit> = self.gpu.run_sized(
            list,
            &self.params(input.len(), self.all_items()),
            &self.bind(&[&chunk, &offs]),
            input.len(),
            2 * total,
        )?;
        Ok(offsets.windows(2).map(|w| out[2 * w[0] as usize..2 * w[1] as usize].to_vec()).collect())
    }

    /// The kernel of entry point `entry` of the queries' module, built into `cell` on first use.
    fn lazy<'a>(&self, cell: &'a OnceLock<Kernel>, entry: &str) -> Result<&'a Kernel, GpuError> {
        if let Some(k) = cell.get() {
            return Ok(k);
        }
        let k = self.gpu.kernel(&Self::module(&self.tree, false, self.splines), entry, INPUTS)?;
        Ok(cell.get_or_init(|| k))
    }

    /// The count and list kernels of [`Self::line_intervals`], built on first use (most
    /// scenes never need them, and each pipeline costs a shader compile).
    fn line_kernels(&self) -> Result<&(Kernel, Kernel), GpuError> {
        if let Some(k) = self.lines.get() {
            return Ok(k);
        }
        let count = self.gpu.kernel(&Self::module(&self.tree, false, self.splines), "count_lines", INPUTS)?;
        let list = self.gpu.kernel(&Self::module(&self.tree, true, self.splines), "list_lines", INPUTS + 1)?;
        let built = (count, list);
        Ok(self.lines.get_or_init(|| built))
    }

    /// The bound `δ` of the module docs: how far the GPU's local lines may lie from the CPU's
    /// (`16·2⁻²⁴·R`, `R` at least the distance from the centre to the padded scene box's corner
    /// plus the restart lead: no restart point or primitive origin lies farther).
    ///
    /// `R` is read from the walk's own restart rather than rebuilt from the tree's constants: a
    /// ray from the centre along `±eᵢ` restarts the lead `l` before the box and ends
    /// `s_end = hᵢ + l + 8·pad` past the restart (`hᵢ` the padded box's half extent), and
    /// `|(hᵢ + l)ᵢ| ≥ |h| + l` (the `hᵢ`, `l` are non-negative), so that norm is a valid `R`
    /// (at most `√3·l` above the least one, and `l ≪ |h|`).
    pub fn band(&self) -> f64 {
        let c = V3::from(self.ex.centre);
        let mut reach = [0.0f64; 3];
        for (i, r) in reach.iter_mut().enumerate() {
            for sign in [1.0, -1.0] {
                let mut d = [0.0; 3];
                d[i] = sign;
                let Some(x) = self.ex.restart(&Ray::new(c, V3::from(d)), 0.0, f64::INFINITY) else {
                    return 0.0;
                };
                *r = r.max(x.s_end - 8.0 * self.ex.pad);
            }
        }
        let r = reach.iter().map(|x| x * x).sum::<f64>().sqrt();
        16.0 * f64::from(f32::EPSILON) * 0.5 * r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tubecast_render::scene::generate::{self, Rng};
    use tubecast_render::scene::{Model, Scene};

    /// The shaders' bindings are the ones the host binds: [`Gpu::SPLIT`] node bindings from 1,
    /// as many primitive bindings after them, the rays at `INPUTS`, lines.wgsl's offsets after
    /// them; the accessors read one binding directly and several by the record's binding; the
    /// records are the sizes `tests/gpu/split.rs` splits by.
    #[test]
    fn the_shaders_bindings_are_the_hosts() {
        for k in 0..Gpu::SPLIT {
            let node = format!("@binding({}) var<storage, read> nodes{k}: array<Node>;", 1 + k);
            let prim = format!("@binding({}) var<storage, read> prims{k}: array<Prim>;", 1 + Gpu::SPLIT + k);
            assert!(TREE_WGSL.contains(&node) && TREE_WGSL.contains(&prim), "{node} {prim}");
        }
        assert!(!TREE_WGSL.contains(&format!("nodes{}:", Gpu::SPLIT)));
        assert!(TREE_WGSL.contains(&format!("@binding({INPUTS}) var<storage, read> rays")));
        assert!(LINES_WGSL.contains(&format!("@binding({}) var<storage, read> offsets", INPUTS + 1)));
        let one = accessor("node_at", "Node", "nodes", 7, 1);
        assert!(one.contains("return nodes0[i];") && !one.contains("nodes1"), "{one}");
        let three = accessor("prim_at", "Prim", "prims", 7, 3);
        assert!(
            three.contains("let c = i / 7u;") && three.contains("return prims2[j];") && !three.contains("prims3"),
            "{three}"
        );
        assert_eq!((std::mem::size_of::<GpuNode>(), std::mem::size_of::<GpuPrim>()), (256, 48));
    }

    /// The loop budget check (`shaders/tree.wgsl`'s `loops_cut`) against what it guards: the
    /// brute force over every item of a spline scene in one dispatch, which on lavapipe spends the
    /// budget (its answers were no hits at all), beside [`GpuScene::brute`]'s ranges. Every ray
    /// the check passes has the ranges' answer bit for bit; on lavapipe some ray is flagged (so
    /// the check can fire); on other drivers none need be.
    #[test]
    fn loops_cut_flags_the_rays_whose_loops_ran_out() {
        let gpu = match Gpu::new() {
            Ok(g) => g,
            Err(e @ GpuError::NoAdapter(_)) if std::env::var("TUBECAST_REQUIRE_GPU").map_or(true, |v| v != "1") => {
                eprintln!("loops_cut_flags_the_rays_whose_loops_ran_out: skipped, {e}");
                return;
            }
            Err(e) => panic!("{e}"),
        };
        let mut lines = generate::furball(40, 12, 2);
        lines.extend(generate::bundle(20, 12, 3));
        let scene = Scene::from_polylines(&lines, 0.05, "furball").unwrap();
        let bvh = WideBvh::from_scene(&scene, Model::Splines).unwrap();
        let gs = GpuScene::upload(&gpu, &bvh).unwrap();
        let mut rng = Rng::new(5);
        let rays: Vec<Ray<f64>> = (0..64)
            .map(|_| {
                let node = scene.nodes[(rng.uniform() * scene.nodes.len() as f64) as usize].pos;
                let d = V3::from(rng.unit());
                Ray::with_range(V3::from(node) - d * 30.0, d, 0.0, 60.0)
            })
            .collect();
        let input: Vec<GpuRay> = rays.iter().map(|r| gs.prepare(r).0).collect();
        let ranges = gs.brute(&input).unwrap();
        let k = gs.lazy(&gs.brute, "closest_brute").unwrap();
        let buf = gpu.upload("rays", &input).unwrap();
        let once: Vec<GpuHit> =
            gpu.run(k, &gs.params(input.len(), gs.all_items()), &gs.bind(&[&buf]), input.len()).unwrap();
        let key = |h: &GpuHit| (h.item, h.s.to_bits());
        let mut cut = 0;
        for (i, (a, b)) in once.iter().zip(&ranges).enumerate() {
            if a.cut != 0 {
                cut += 1;
            } else {
                assert_eq!(key(a), key(b), "ray {i}: one dispatch, not flagged, differs from the ranges");
            }
        }
        let hits = ranges.iter().filter(|h| h.item != NONE).count();
        eprintln!("{}: {cut} of {} rays flagged in one dispatch; {hits} hits", gpu.describe(), rays.len());
        assert!(hits > 10, "{hits} hits: the test says little");
        if gpu.describe().contains("llvmpipe") {
            assert!(cut > 0, "lavapipe ran every spline piece's solves in one dispatch within its loop budget");
        }
    }
}
