//! Alpha is the accumulated opacity: front-to-back compositing of every exterior surface the
//! pixel's line crosses, each of opacity `a`, gives `α = 1 − (1 − a)ᵏ` for `k` surfaces, 0 on
//! the background; the RGBA PNG stores it with straight (not premultiplied) colour.
//!
//! Tolerances: `α` is computed in f32 as `1 − Π(1 − a)` with at most four factors, each
//! product and the final difference rounded once (relative 2⁻²⁴ each), so |α − exact| ≤
//! 6·2⁻²⁴ < 1e-6; the straight colour divides an f32 sum of two rounded products by α ≥ 0.3,
//! error < 1e-5. PNG bytes quantise to 1/255: the alpha byte is round(255·α) exactly when the
//! f32 error stays far from a rounding tie, so the byte is compared within 1 (1/255).

use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::render::{self, clamp_thin, Camera, ColorBy, Image, Options, Shading};
use tubecast_render::scene::{Node, Radii, Scene};

const RED: [f32; 3] = [1.0, 0.0, 0.0];

fn tube(a: [f64; 3], b: [f64; 3], r: f64) -> Scene {
    let n = |pos| Node { pos };
    Scene { nodes: vec![n(a), n(b)], links: vec![[0, 1]].into(), radii: Radii::uniform(r), ..Scene::default() }
}

fn draw(scene: &Scene, cam: &Camera, opacity: f64, background: [f32; 3]) -> Image {
    let opts =
        Options { color: ColorBy::Solid(RED), shading: Shading::Flat, opacity, background, ..Options::default() };
    render::render(scene, &Bvh::build(scene.primitives()), cam, &opts).unwrap()
}

/// Looking down −z at the origin, orthographic, 20 × 20 pixels of size 1 (image spans ±10).
fn top_view() -> Camera {
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 20, 20).unwrap();
    cam.orthographic([0.0; 3])
}

/// Decode an RGBA PNG's bytes.
fn png_rgba(img: &Image, name: &str) -> Vec<u8> {
    let path = std::env::temp_dir().join(format!("tubecast-alpha-{}-{name}.png", std::process::id()));
    img.write_png_rgba(&path).unwrap();
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let _ = std::fs::remove_file(&path);
    buf[..info.buffer_size()].to_vec()
}

fn byte_near(got: u8, want: f64) -> bool {
    (got as f64 - want * 255.0).abs() <= 1.0
}

#[test]
fn one_surface_over_a_transparent_background_has_alpha_equal_to_the_opacity() {
    // The eye inside a wide tube along z, looking along +x with a 60° field of view: every
    // pixel's line starts inside and crosses only the exit surface (the union's boundaries are
    // those with t ≥ 0), so every pixel sees exactly one layer of opacity a.
    let scene = tube([0.0, 0.0, -100.0], [0.0, 0.0, 100.0], 20.0);
    let cam = Camera::look_at(V3::zero(), V3::new(1.0, 0.0, 0.0), V3::new(0.0, 0.0, 1.0), 60.0, 16, 12).unwrap();
    for a in [0.3f64, 0.5, 0.8] {
        for bg in [[0.0; 3], [1.0; 3], [0.2, 0.4, 0.9]] {
            let img = draw(&scene, &cam, a, bg);
            for i in 0..img.alpha.len() {
                assert!((img.alpha[i] as f64 - a).abs() < 1e-6, "a {a}: pixel {i} alpha {}", img.alpha[i]);
                // Straight colour: the background taken back out leaves the surface's red.
                let (c, _) = img.straight(i);
                assert!(c.iter().zip(RED).all(|(x, y)| (x - y).abs() < 1e-5), "a {a} bg {bg:?}: {c:?}");
            }
            let px = png_rgba(&img, "inside");
            for p in px.chunks(4) {
                assert!(byte_near(p[3], a), "a {a}: alpha byte {}", p[3]);
                assert!(p[0] >= 254 && p[1] <= 1 && p[2] <= 1, "straight colour {p:?}");
            }
        }
    }
}

#[test]
fn stacked_surfaces_accumulate_and_the_background_stays_clear() {
    let cam = top_view();
    let a = 0.4f64;
    // One tube along x through the origin, radius 1: the centre rows' lines enter and exit it,
    // two surfaces: α = 1 − (1 − a)².
    let one = tube([-8.0, 0.0, 0.0], [8.0, 0.0, 0.0], 1.0);
    // A second tube 5 below it: four surfaces, α = 1 − (1 − a)⁴.
    let mut two = one.clone();
    two.nodes.extend([Node { pos: [-8.0, 0.0, -5.0] }, Node { pos: [8.0, 0.0, -5.0] }]);
    two.links.push([2, 3]);
    for (scene, k) in [(&one, 2), (&two, 4)] {
        let img = draw(scene, &cam, a, [1.0; 3]);
        let want = 1.0 - (1.0 - a).powi(k);
        let px = png_rgba(&img, &format!("stack{k}"));
        for x in 2..18u32 {
            for y in [9u32, 10] {
                let i = (y * 20 + x) as usize;
                assert!((img.alpha[i] as f64 - want).abs() < 1e-6, "{k} surfaces at ({x}, {y}): {}", img.alpha[i]);
                assert!(byte_near(px[4 * i + 3], want), "{k} surfaces: alpha byte {}", px[4 * i + 3]);
            }
        }
        // Rows 0..5 and 15..20 are ≥ 4.5 from the axis: background, alpha 0 (byte 0), and
        // the RGB image shows the background colour there.
        for y in (0..5).chain(15..20) {
            for x in 0..20u32 {
                let i = (y * 20 + x) as usize;
                assert_eq!((img.alpha[i], px[4 * i + 3]), (0.0, 0), "background at ({x}, {y})");
                assert_eq!(img.rgb[i], [1.0; 3]);
            }
        }
    }
}

#[test]
fn opaque_hits_have_alpha_one_and_faded_thin_tubes_their_coverage() {
    let cam = top_view();
    let img = draw(&tube([-8.0, 0.0, 0.0], [8.0, 0.0, 0.0], 1.0), &cam, 1.0, [0.0; 3]);
    assert_eq!(img.alpha[(10 * 20 + 10) as usize], 1.0);
    assert_eq!(img.alpha[0], 0.0);
    // A tube of radius 0.001 widened to 2 pixels (r_min = 1): coverage 0.001, and the pixel's
    // alpha is that coverage (a wire over the background), its colour straight red.
    let mut thin = tube([-8.0, 0.0, 0.0], [8.0, 0.0, 0.0], 0.001);
    assert_eq!(clamp_thin(&mut thin, &cam, 2.0), 2);
    let img = draw(&thin, &cam, 1.0, [1.0; 3]);
    let i = (10 * 20 + 10) as usize;
    assert!((img.alpha[i] - 0.001).abs() < 1e-6, "alpha {}", img.alpha[i]);
    let (c, _) = img.straight(i);
    assert!((c[0] - 1.0).abs() < 1e-3 && c[1] < 1e-3 && c[2] < 1e-3, "{c:?}");
    // Composited over white: 0.001·red + 0.999·white.
    assert!((img.rgb[i][1] - 0.999).abs() < 1e-6);
}
