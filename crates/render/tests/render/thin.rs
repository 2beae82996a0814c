//! Thin structures stay visible: `clamp_thin` widens sub-pixel tubes to a minimum footprint
//! and the renderer fades them by their coverage.

use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::render::{self, clamp_thin, Camera, ColorBy, Options, Shading};
use tubecast_render::scene::{Node, Radii, Scene};

fn thin_line(r: f64) -> Scene {
    let n = |x: f64| Node { pos: [x, 0.0, 0.0] };
    let links = vec![[0, 1], [1, 2]].into();
    Scene { nodes: vec![n(-4.0), n(0.0), n(4.0)], links, radii: Radii::uniform(r), ..Scene::default() }
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
    assert!((0..3).all(|i| (scene.radius(i) - 0.2).abs() < 1e-12));
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
    assert!(scene.coverage.is_empty() && (0..3).all(|i| scene.radius(i) == 0.5));
    let mut thin = thin_line(0.001);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(clamp_thin(&mut thin, &cam, bad), 0);
    }
    // Orthographic: the pixel size is 2·ortho/height everywhere.
    let o = cam.orthographic([0.0; 3]);
    assert_eq!(clamp_thin(&mut thin, &o, 1.0), 3);
    assert!((0..3).all(|i| (thin.radius(i) - 0.5 * 2.0 * o.ortho / 100.0).abs() < 1e-12));
}

#[test]
fn a_faded_line_in_front_of_a_tube_shows_the_tube_through_it() {
    // The camera of the test above (a pixel at depth 10 is 0.2 wide). A red (type 3) line of
    // radius 0.05 along x at z = 0, clamped to 2 pixels: r_min = 0.2, coverage α = 0.25. Behind
    // it a blue (type 2) tube of radius 1 along y at z = −3 (its pixel is 0.26 wide: left alone).
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
    let n = |p: [f64; 3]| Node { pos: p };
    let mut scene = Scene {
        nodes: vec![n([-4.0, 0.0, 0.0]), n([4.0, 0.0, 0.0]), n([0.0, -6.0, -3.0]), n([0.0, 6.0, -3.0])],
        radii: Radii::from_vec(vec![0.05, 0.05, 1.0, 1.0]),
        links: vec![[0, 1], [2, 3]].into(),
        kinds: vec![3, 3, 2, 2],
        ..Scene::default()
    };
    assert_eq!(clamp_thin(&mut scene, &cam, 2.0), 2);
    let opts = Options { color: ColorBy::Type, shading: Shading::Flat, ..Options::default() };
    let img = render::render(&scene, &Bvh::build(scene.primitives()), &cam, &opts).unwrap();
    let (red, blue) = ([0.9f32, 0.25, 0.2], [0.25f32, 0.45, 0.95]);
    let mix = |under: [f32; 3]| -> [f32; 3] { std::array::from_fn(|k| 0.25 * red[k] + 0.75 * under[k]) };
    let close = |p: [f32; 3], w: [f32; 3]| p.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-5);
    // Columns 49 and 50 (centres ±0.1 at depth 10, ±0.13 at the tube's depth 13, inside its
    // radius 1): the line over the tube, α·red + (1 − α)·blue (hand-computed from the type
    // palette). Columns 35 and 65 (centres ∓2.9 at depth 10, ∓3.77 at depth 13: beside the tube):
    // the line over the white background.
    for y in [49, 50] {
        for x in [49, 50] {
            assert!(close(img.at(x, y), mix(blue)), "over the tube ({x}, {y}) = {:?}", img.at(x, y));
            assert!((img.alpha[(y * 100 + x) as usize] - 1.0).abs() < 1e-6);
        }
        for x in [35, 65] {
            assert!(close(img.at(x, y), mix([1.0; 3])), "over the background ({x}, {y}) = {:?}", img.at(x, y));
        }
    }
}
