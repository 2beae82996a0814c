//! The link, sphere and spline kernels on their own: one primitive against one local ray per
//! thread, for comparing the WGSL ports with the CPU kernels on identical `f32` input.

use crate::compute::Kernel;
use crate::device::{Gpu, GpuError};
use bytemuck::{Pod, Zeroable};
use tubecast::{Crossing, Interval, QuadTube, Ray, RoundCone, V3};

/// The WGSL source of the link and sphere kernels.
pub const LINK_WGSL: &str = include_str!("../shaders/link.wgsl");
/// The WGSL source of the spline kernel (appended to [`LINK_WGSL`], whose helpers it uses):
/// the kernel, its ray-space set-up and its root finders.
pub const SPLINE_WGSL: &str = concat!(
    include_str!("../shaders/spline.wgsl"),
    "\n",
    include_str!("../shaders/ray_space.wgsl"),
    "\n",
    include_str!("../shaders/roots.wgsl")
);
const PAIRS_WGSL: &str = include_str!("../shaders/pairs.wgsl");

/// A primitive of a kernel test: a link, or a sphere at the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Local {
    /// The stable round-cone link.
    Link(RoundCone<f32>),
    /// The sphere of this radius at the origin.
    Sphere(f32),
    /// The quadratic spline piece, answered as the CPU's default solver
    /// ([`tubecast::Solver::Polynomial`]) answers it (`shaders/spline.wgsl`).
    Spline(QuadTube<f32>),
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PairIn {
    a: [f32; 3],
    ra: f32,
    b: [f32; 3],
    rb: f32,
    o: [f32; 3],
    kind: u32,
    d: [f32; 3],
    slot: u32,
    c: [f32; 3],
    rc: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct IvOut {
    n_in: [f32; 3],
    t_in: f32,
    n_out: [f32; 3],
    t_out: f32,
    u_in: f32,
    u_out: f32,
    hit: u32,
    /// Lavapipe's loop budget ran out (`shaders/tree.wgsl`'s `loops_cut`).
    cut: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Count {
    n: u32,
    _pad: [u32; 3],
}

/// The kernel pipeline of [`Pairs::line_intervals`].
pub struct Pairs {
    kernel: Kernel,
}

impl Pairs {
    /// Compile the kernels for `gpu`.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        let src = format!("{LINK_WGSL}\n{SPLINE_WGSL}\n{PAIRS_WGSL}");
        Ok(Self { kernel: gpu.kernel(&src, "pairs_main", 1)? })
    }

    /// The line interval of each primitive `prims[i]` with the ray `rays[i]` (origin and
    /// direction; the range is ignored), as the CPU's `line_interval` gives it for `f32`.
    pub fn line_intervals(
        &self,
        gpu: &Gpu,
        prims: &[Local],
        rays: &[Ray<f32>],
    ) -> Result<Vec<Interval<f32>>, GpuError> {
        let v = |x: V3<f32>| x.to_array();
        let input: Vec<PairIn> = prims
            .iter()
            .zip(rays)
            .map(|(p, r)| {
                let (a, ra, b, rb, kind, c, rc) = match *p {
                    Local::Link(c) => (v(c.a), c.ra, v(c.b), c.rb, 0, [0.0; 3], 0.0),
                    Local::Sphere(r) => ([0.0; 3], r, [0.0; 3], r, 1, [0.0; 3], 0.0),
                    Local::Spline(q) => (v(q.b[0]), q.r[0], v(q.b[2]), q.r[2], 2, v(q.b[1]), q.r[1]),
                };
                PairIn { a, ra, b, rb, o: v(r.o), kind, d: v(r.d), slot: 0, c, rc }
            })
            .collect();
        self.run(gpu, &input)
    }

    /// The exact line pieces of each spline piece `tubes[i]` with the ray `rays[i]` (the
    /// range is ignored), slot by slot as the CPU's `QuadTube::intersect_pieces` with
    /// `Solver::Polynomial` gives them for `f32` on the whole line (`shaders/spline.wgsl`'s
    /// `spline_pieces`).
    pub fn spline_pieces(
        &self,
        gpu: &Gpu,
        tubes: &[QuadTube<f32>],
        rays: &[Ray<f32>],
    ) -> Result<Vec<[Interval<f32>; 5]>, GpuError> {
        let v = |x: V3<f32>| x.to_array();
        let input: Vec<PairIn> = tubes
            .iter()
            .zip(rays)
            .flat_map(|(q, r)| {
                (0..5).map(move |slot| PairIn {
                    a: v(q.b[0]),
                    ra: q.r[0],
                    b: v(q.b[2]),
                    rb: q.r[2],
                    o: v(r.o),
                    kind: 3,
                    d: v(r.d),
                    slot,
                    c: v(q.b[1]),
                    rc: q.r[1],
                })
            })
            .collect();
        let out = self.run(gpu, &input)?;
        Ok(out.chunks_exact(5).map(|c| [c[0], c[1], c[2], c[3], c[4]]).collect())
    }

    fn run(&self, gpu: &Gpu, input: &[PairIn]) -> Result<Vec<Interval<f32>>, GpuError> {
        let buf = gpu.upload("kernel inputs", input)?;
        let out: Vec<IvOut> =
            gpu.run(&self.kernel, &Count { n: input.len() as u32, _pad: [0; 3] }, &[&buf], input.len())?;
        if out.iter().any(|o| o.cut != 0) {
            return Err(GpuError::LoopLimit("a kernel test's inputs".into()));
        }
        Ok(out
            .iter()
            .map(|o| {
                if o.hit == 0 {
                    return Interval::miss();
                }
                let c = |t, n: [f32; 3], u| Crossing { t, n: V3::from(n), u };
                Interval::new(c(o.t_in, o.n_in, o.u_in), c(o.t_out, o.n_out, o.u_out), true)
            })
            .collect())
    }
}
