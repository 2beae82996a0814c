//! Helpers shared by the render tests.

use tubecast::{Ray, V3};
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, ColorBy, Image, Options, Shading};
use tubecast_render::scene::Scene;

/// Unlit options: the pixel is the surface colour itself.
pub fn flat(color: ColorBy, opacity: f64) -> Options {
    Options { color, shading: Shading::Flat, opacity, ..Options::default() }
}

/// The link model of `lines` (radius 1 where a line has none), rendered with `opts` through
/// a 40° camera fitted to the scene's bounds ([`Scene::stats`]), `size`×`size` pixels.
pub fn render_links(lines: &[Polyline], size: u32, opts: &Options) -> (Scene, Bvh, Camera, Image) {
    let scene = Scene::from_polylines(lines, 1.0, "lines").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, size, size).unwrap();
    let img = render(&scene, &bvh, &cam, opts).unwrap();
    (scene, bvh, cam, img)
}

/// What [`compare_depth`] saw.
pub struct DepthCheck {
    /// Non-grazing pixels whose reference hits.
    pub hits: usize,
    /// Pixels skipped as grazing.
    pub grazing: usize,
    /// Largest depth error over the hits.
    pub worst: f64,
}

impl DepthCheck {
    /// Print the result as `what`, and require more than `min_hits` hits and fewer than
    /// `1/grazing_div` of them skipped as grazing.
    pub fn assert_covers(&self, what: &str, tol: f64, min_hits: usize, grazing_div: usize) {
        let Self { hits, grazing, worst } = *self;
        eprintln!("{what}: {hits} hits, {grazing} grazing skipped, worst |Δt| {worst:e} (tol {tol:e})");
        assert!(hits > min_hits, "{what} must cover part of the image ({hits} hit pixels)");
        assert!(grazing * grazing_div < hits, "too many grazing pixels skipped ({grazing} of {hits})");
    }
}

/// Compare a render's depth buffer with reference first hits `(t, normal)`; pixels whose
/// reference hit is grazing (`|n·d̂| < c`) are skipped; every other pixel must miss where
/// the reference misses and be within `tol` of it where it hits.
pub fn compare_depth(
    img: &Image,
    cam: &Camera,
    c: f64,
    tol: f64,
    reference: impl Fn(u32, u32, &Ray<f64>) -> Option<(f64, V3<f64>)>,
) -> DepthCheck {
    let (mut hits, mut grazing, mut worst) = (0, 0, 0.0f64);
    for y in 0..cam.height {
        for x in 0..cam.width {
            let ray = cam.ray(x, y);
            let best = reference(x, y, &ray);
            let depth = img.depth[(y * cam.width + x) as usize];
            // Near a silhouette hit/miss and t are ill-conditioned (t moves by δ/|n·d̂|).
            if best.is_some_and(|(_, n)| n.dot(ray.d.normalize_or_zero()).abs() < c) {
                grazing += 1;
                continue;
            }
            match best {
                None => assert!(depth.is_infinite(), "pixel ({x},{y}): render hit at {depth}, reference misses"),
                Some((t, _)) => {
                    hits += 1;
                    worst = worst.max((depth - t).abs());
                    assert!((depth - t).abs() <= tol, "pixel ({x},{y}): depth {depth} vs reference {t} (tol {tol:e})");
                }
            }
        }
    }
    DepthCheck { hits, grazing, worst }
}
