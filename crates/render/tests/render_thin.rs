//! Thin structures stay visible: `clamp_thin` widens sub-pixel tubes to a minimum footprint
//! and the renderer fades them by their coverage.

use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::render::{self, clamp_thin, Camera, ColorBy, Options, Shading};
use tubecast_render::scene::{Node, Scene};

fn thin_line(r: f64) -> Scene {
    let n = |x: f64| Node { pos: [x, 0.0, 0.0], radius: r, kind: 0 };
    Scene { nodes: vec![n(-4.0), n(0.0), n(4.0)], links: vec![[0, 1], [1, 2]], ..Scene::default() }
}

fn draw(scene: &Scene, cam: &Camera) -> render::Image {
    let opts = Options { color: ColorBy::Solid([1.0, 0.0, 0.0]), shading: Shading::Flat, ..Options::default() };
    render::render(scene, &Bvh::build(scene.primitives()), cam, &opts).unwrap()
}

#[test]
fn a_sub_pixel_line_is_widened_and_faded_by_its_coverage() {
    // Eye at z = 10 looking at the origin, 90° field of view, 100 × 100: a pixel at depth 10 is
    // 2·10·tan 45° / 100 = 0.2 wide. A line of radius 0.001 along x through the origin.
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
    let mut scene = thin_line(0.001);
    // Without the clamp: the pixel-centre rays of rows 49 and 50 pass 0.1 from the axis and
    // miss the 0.001-radius tube; the image is all background.
    let plain = draw(&scene, &cam);
    assert!(plain.rgb.iter().all(|p| *p == [1.0; 3]), "the thin line should alias away unclamped");
    // Clamped to 2 pixels: r_min = ½·2·0.2 = 0.2, coverage α = 0.001/0.2 = 0.005, and a covered
    // pixel is α·red + (1 − α)·white = (1, 0.995, 0.995) (hand-computed).
    assert_eq!(clamp_thin(&mut scene, &cam, 2.0), 3);
    assert!(scene.nodes.iter().all(|n| (n.radius - 0.2).abs() < 1e-12));
    let img = draw(&scene, &cam);
    let want = [1.0f32, 0.995, 0.995];
    for y in [49, 50] {
        for x in 30..70 {
            let p = img.at(x, y);
            assert!(p.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-5), "pixel ({x}, {y}) = {p:?}");
        }
    }
    // Rows 48 and 51 (centres 0.3 from the axis) stay background: the width is 2 pixels.
    assert!((0..100).all(|x| img.at(x, 48) == [1.0; 3] && img.at(x, 51) == [1.0; 3]));
}

#[test]
fn thick_tubes_and_bad_footprints_are_left_alone() {
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
    let mut scene = thin_line(0.5);
    assert_eq!(clamp_thin(&mut scene, &cam, 1.0), 0);
    assert!(scene.coverage.is_empty() && scene.nodes.iter().all(|n| n.radius == 0.5));
    let mut thin = thin_line(0.001);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(clamp_thin(&mut thin, &cam, bad), 0);
    }
    // Orthographic: the pixel size is 2·ortho/height everywhere.
    let o = cam.orthographic([0.0; 3]);
    assert_eq!(clamp_thin(&mut thin, &o, 1.0), 3);
    assert!(thin.nodes.iter().all(|n| (n.radius - 0.5 * 2.0 * o.ortho / 100.0).abs() < 1e-12));
}
