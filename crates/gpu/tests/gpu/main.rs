//! GPU tests: every GPU answer compared with the CPU's. Without a Vulkan adapter each test says
//! it skipped, unless `TUBECAST_REQUIRE_GPU=1` (CI sets it), which turns a missing adapter into
//! a failure.

mod constants;
mod kernels;
mod lines;
mod piece;
mod render;
mod spline;
mod split;
mod tree;

use std::io::Write;
use tubecast::{Ray, V3};
use tubecast_gpu::{Gpu, GpuError};
use tubecast_oracle::{line_gap, link_error_bound, quad_gap_fine, Line, Link, Quad, Vec3};
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::{Prim, Scene};

/// A furball through a bundle: many crossings per ray, tubes touching and overlapping.
pub fn fur() -> Scene {
    let mut lines = generate::furball(80, 12, 6);
    lines.extend(generate::bundle(30, 20, 2));
    Scene::from_polylines(&lines, 0.08, "fur").unwrap()
}

/// A point within 0.1 of a random node of `scene`.
pub fn near_node(rng: &mut Rng, scene: &Scene) -> V3<f64> {
    let node = scene.nodes[(rng.uniform() * scene.nodes.len() as f64) as usize].pos;
    V3::from(node) + V3::from(rng.unit()) * rng.range(0.0, 0.1)
}

pub fn ov(v: V3<f64>) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// The stored primitive as an exact `f64` link (its `f32` shape plus its `f64` origin).
pub fn link_of(p: &Prim) -> Link {
    let o = V3::from(p.origin);
    let c = p.round_cone().expect("links and spheres only");
    Link { a: ov(o + c.a.cast()), ra: f64::from(c.ra), b: ov(o + c.b.cast()), rb: f64::from(c.rb) }
}

/// The stored spline piece as an exact `f64` quadratic sweep (its `f32` control data plus its
/// `f64` origin).
pub fn quad_of(p: &Prim) -> Quad {
    let o = V3::from(p.origin);
    let q = p.quad().expect("spline pieces only");
    Quad { b: q.b.map(|b| ov(o + b.cast())), r: q.r.map(f64::from) }
}

/// A lower bound on the radius of curvature of primitive `p`'s surface: how far a hit point
/// must move for its normal to turn by one radian (the render test's `|Δn| ≤ |Δx|/ρ`).
///
/// Links and spheres: their largest radius, as the render test has always taken it. Spline
/// pieces of constant radius `r` (the shipped files' `--splines` model): a tube about the
/// centre line `p(t)`, whose principal curvatures are `1/r` and `κ·cos θ/(1 − κ·r·cos θ)`, so
/// `ρ ≥ min(r, 1/κ − r)` (`0`: unbounded, where `κ·r ≥ 1`). For a quadratic Bézier
/// `p' × p''` is constant (`p''` is), so `κ = |p' × p''|/|p'|³` is greatest where `|p'|` is
/// least: at the vertex of the parabola, clamped to `[0, 1]`.
pub fn curvature_radius(p: &Prim) -> f64 {
    let Some(q) = p.quad() else { return f64::from(p.max_radius()) };
    let r = q.r.map(f64::from);
    assert!(r.iter().all(|&x| x == r[0]), "constant-radius spline pieces only: {r:?}");
    let b = q.b.map(|x| x.cast::<f64>());
    let (d0, d2) = ((b[1] - b[0]) * 2.0, (b[2] - b[1] * 2.0 + b[0]) * 2.0);
    let tv = if d2.length2() > 0.0 { (-d0.dot(d2) / d2.length2()).clamp(0.0, 1.0) } else { 0.0 };
    let speed = (d0 + d2 * tv).length();
    let kappa = d0.cross(d2).length() / (speed * speed * speed);
    if !kappa.is_finite() || kappa * r[0] >= 1.0 {
        return 0.0;
    }
    r[0].min(1.0 / kappa - r[0])
}

/// The line's signed gap to primitive `p`'s exact surface (negative: it passes inside).
pub fn gap(p: &Prim, line: &Line) -> f64 {
    match p.quad() {
        Some(_) => quad_gap_fine(&quad_of(p), line),
        None => line_gap(&link_of(p), line).0,
    }
}

/// `E` for primitive `p` and the local ray of `ray` (origin: the line's point nearest the
/// primitive's origin), for unit roundoff `eps`: how far a kernel's crossing may lie from the
/// exact surface, measured along the surface normal.
///
/// A link's is its kernel's bound (`link_error_bound`). A spline piece's kernel answers exactly
/// for a tube whose radius is within `E_s` of the given one, its crossings shifted by up to
/// `E_s` along the ray (`tubecast::spline_error_band`, derived in `src/kernel/spline.rs`,
/// "Conditioning"): a crossing lies within `E_s` of the exact surface across it and `E_s`
/// along the ray, so within `2·E_s` of it (the shift's normal part is at most the shift).
pub fn bound(p: &Prim, ray: &Ray<f64>, eps: f64) -> f64 {
    let dn = ray.d * (1.0 / ray.d.length());
    let m = V3::from(p.origin);
    let foot = ray.o + dn * (m - ray.o).dot(dn);
    if let Some(q) = p.quad() {
        return 2.0 * q.error_band((foot - m).cast(), eps);
    }
    let l = link_of(p);
    let size = (l.b - l.a).length().max(l.ra).max(l.rb);
    link_error_bound(&l, ov(foot), size, eps)
}

/// [`bound`] for the `f32` kernels (`ε = 2⁻²³`).
pub fn bound32(p: &Prim, ray: &Ray<f64>) -> f64 {
    bound(p, ray, f64::from(f32::EPSILON))
}

/// The device, or `None` (with a message) when there is none and none is required.
pub fn gpu(test: &str) -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e @ GpuError::NoAdapter(_)) if std::env::var("TUBECAST_REQUIRE_GPU").map_or(true, |v| v != "1") => {
            // Straight to stderr, past the test harness's capture, so that a passing run shows it.
            let _ = writeln!(std::io::stderr(), "{test}: skipped, {e}");
            None
        }
        Err(e) => panic!("{test}: {e}"),
    }
}
