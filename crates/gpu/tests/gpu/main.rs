//! GPU tests: every GPU answer compared with the CPU's. Without a Vulkan adapter each test says
//! it skipped, unless `TUBECAST_REQUIRE_GPU=1` (CI sets it), which turns a missing adapter into
//! a failure.

mod constants;
mod kernels;
mod lines;
mod piece;
mod render;
mod tree;

use std::io::Write;
use tubecast::{Ray, V3};
use tubecast_gpu::{Gpu, GpuError};
use tubecast_oracle::{link_error_bound, Link, Vec3};
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

/// `E` for primitive `p` and the local ray of `ray` (origin: the line's point nearest the
/// primitive's origin), for unit roundoff `eps`.
pub fn bound(p: &Prim, ray: &Ray<f64>, eps: f64) -> f64 {
    let l = link_of(p);
    let dn = ray.d * (1.0 / ray.d.length());
    let m = V3::from(p.origin);
    let foot = ray.o + dn * (m - ray.o).dot(dn);
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
