//! View presets, the orthographic camera, framing, antialiasing and the legend's contrast.

use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::render::{contrasting_ink, render, Camera, Colormap, Image, Options, Preset, Shading};
use tubecast_render::scene::{Node, Radii, Scene};

#[test]
fn presets_look_along_their_axes_and_frame_the_box() {
    let (lo, hi) = ([-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]);
    // (preset, forward, right, up) written out from the preset docs.
    let cases = [
        (Preset::Xy, [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        (Preset::Xz, [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        (Preset::Yz, [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    for (p, f, r, u) in cases {
        let c = Camera::fit_preset(lo, hi, p, 40.0, 64, 48).unwrap();
        for (got, want) in [(c.forward, f), (c.right, r), (c.up, u)] {
            assert!((0..3).all(|k| (got.to_array()[k] - want[k]).abs() < 1e-12), "{p:?}: {got:?} vs {want:?}");
        }
        // The eye is on the axis through the box centre (0, 0, 0), outside the box.
        let e = c.eye.to_array();
        assert!((0..3).filter(|&k| f[k] == 0.0).all(|k| e[k].abs() < 1e-9), "{p:?} eye {e:?}");
        assert!(c.eye.length() > 3.0_f64.hypot(2.0).hypot(1.0));
    }
    let iso = Camera::fit_preset(lo, hi, Preset::Iso, 40.0, 64, 48).unwrap();
    let s = -1.0 / 3.0_f64.sqrt();
    assert!(iso.forward.to_array().iter().all(|v| (v - s).abs() < 1e-12));
    assert!("top".parse::<Preset>().is_err());
}

#[test]
fn orthographic_rays_are_parallel_and_span_the_framed_height() {
    let c = Camera::fit_preset([-1.0; 3], [1.0; 3], Preset::Xy, 40.0, 10, 10).unwrap();
    let o = c.orthographic([0.0; 3]);
    // Half-height tan(20°)·distance; pixel row 0's centre is 0.9 of it above the axis.
    let half = 20f64.to_radians().tan() * c.eye.length();
    let (top, bottom) = (o.ray(5, 0), o.ray(5, 9));
    assert_eq!(top.d, c.forward);
    assert!((top.o.y - 0.9 * half).abs() < 1e-12 && (bottom.o.y + 0.9 * half).abs() < 1e-12);
    assert!((top.o.z - c.eye.z).abs() < 1e-12);
}

/// Spheres of a scene that does not fill its bounding box: a diagonal streak of small spheres
/// and one big sphere off to the side.
fn spheres() -> Vec<([f64; 3], f64)> {
    let mut s: Vec<([f64; 3], f64)> = (0..50).map(|i| ([i as f64, 0.5 * i as f64, -0.3 * i as f64], 0.5)).collect();
    s.push(([10.0, 30.0, 5.0], 4.0));
    s
}

#[test]
fn framed_cameras_fit_every_sphere_and_fill_the_limiting_side() {
    let s = spheres();
    let (lo, hi) = ([0.0, 0.0, -15.0], [50.0, 34.0, 9.0]);
    for preset in [Preset::Xy, Preset::Xz, Preset::Yz, Preset::Iso] {
        let fitted = Camera::fit_preset(lo, hi, preset, 40.0, 160, 120).unwrap();
        let cam = fitted.framed(s.iter().copied()).unwrap();
        assert_eq!((cam.forward, cam.right, cam.up), (fitted.forward, fitted.right, fitted.up));
        // Each sphere in the camera frame: inside the field when |x| + r·√(1 + t²) ≤ t·z
        // (the side planes of the frustum at distance ≥ r), t the half-field's tangent.
        let tv = 20f64.to_radians().tan();
        let th = tv * 160.0 / 120.0;
        let mut most: f64 = 0.0;
        for &(p, r) in &s {
            let q = V3::from(p) - cam.eye;
            let (x, y, z) = (q.dot(cam.right), q.dot(cam.up), q.dot(cam.forward));
            assert!(z > r, "{preset:?}: a sphere behind the eye");
            let used = ((x.abs() + r * (1.0 + th * th).sqrt()) / (th * z))
                .max((y.abs() + r * (1.0 + tv * tv).sqrt()) / (tv * z));
            most = most.max(used);
        }
        // The limiting sphere uses exactly 95% of the half-field (f64 rounding, ~1e-15 relative).
        assert!((most - 0.95).abs() < 1e-9, "{preset:?}: {most}");
        // Orthographic: every sphere within the half-height (and half-width), one at 95%.
        let ortho = fitted.orthographic([25.0, 17.0, -3.0]).framed(s.iter().copied()).unwrap();
        let mut most: f64 = 0.0;
        for &(p, r) in &s {
            let q = V3::from(p) - ortho.eye;
            let (x, y, z) = (q.dot(ortho.right), q.dot(ortho.up), q.dot(ortho.forward));
            assert!(z > r, "{preset:?}: a sphere behind the image plane");
            most = most.max((y.abs() + r) / ortho.ortho).max((x.abs() + r) / (ortho.ortho * 160.0 / 120.0));
        }
        assert!((most - 0.95).abs() < 1e-9, "{preset:?} ortho: {most}");
    }
    assert!(Camera::fit([0.0; 3], [1.0; 3], 40.0, 8, 8).unwrap().framed(std::iter::empty()).is_none());
}

#[test]
fn antialiasing_measures_coverage_within_its_derived_bound() {
    // One sphere of radius 2 seen orthographically, 20 pixels to its radius: its image is a
    // disk of area π·20² px². With N×N samples per pixel, one per cell, a pixel's alpha errs
    // only by the cells the silhouette cuts, 1/N² each; the circle crosses at most
    // 2πR·√2·N cells of side 1/N (|dx| + |dy| ≤ √2·ds per unit length), so the image's total
    // alpha is within 2πR·√2/N of the area.
    let scene = Scene {
        nodes: vec![Node { pos: [0.0; 3] }],
        radii: Radii::uniform(2.0),
        links: vec![[0, 0]].into(),
        ..Scene::default()
    };
    let bvh = Bvh::build(scene.primitives());
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 40.0, 64, 64).unwrap();
    // Half-height 3.2 scene units over 32 pixels: 0.1 per pixel, R = 20 px.
    let cam = Camera { ortho: 3.2, ..cam };
    let area = std::f64::consts::PI * 400.0;
    for n in [1u32, 2, 4, 8] {
        let opts = Options { shading: Shading::Flat, background: [0.0; 3], aa: n, ..Options::default() };
        let img = render(&scene, &bvh, &cam, &opts).unwrap();
        let total: f64 = img.alpha.iter().map(|&a| a as f64).sum();
        let bound = 2.0 * std::f64::consts::PI * 20.0 * 2f64.sqrt() / n as f64;
        assert!((total - area).abs() <= bound, "aa {n}: Σα = {total:.2}, area {area:.2}, bound {bound:.2}");
        // Each alpha is a count of samples over N².
        let n2 = (n * n) as f32;
        assert!(img.alpha.iter().all(|&a| ((a * n2).round() - a * n2).abs() < 1e-4), "aa {n}: alpha not k/N²");
        // and with several samples the silhouette's pixels are partly covered.
        let partial = img.alpha.iter().filter(|&&a| a > 0.0 && a < 1.0).count();
        assert_eq!(partial == 0, n == 1, "aa {n}: {partial} partly covered pixels");
    }
    assert!(Options { aa: 0, ..Options::default() }.validate().is_err());
    assert!(Options { aa: 17, ..Options::default() }.validate().is_err());
}

/// WCAG contrast ratio of two linear RGB colours.
fn contrast(a: [f32; 3], b: [f32; 3]) -> f32 {
    let l = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    (l(a).max(l(b)) + 0.05) / (l(a).min(l(b)) + 0.05)
}

#[test]
fn legend_ink_contrasts_with_every_background() {
    // Black's and white's ratios against a luminance L multiply to 1.05/0.05 = 21, so the
    // better one is ≥ √21 ≈ 4.583 (f32 rounding: ~1e-6 relative).
    for r in 0..=10 {
        for g in 0..=10 {
            for b in 0..=10 {
                let bg = [r as f32 / 10.0, g as f32 / 10.0, b as f32 / 10.0];
                let c = contrast(contrasting_ink(bg), bg);
                assert!(c >= 21f32.sqrt() * (1.0 - 1e-5), "{bg:?}: {c}");
            }
        }
    }
    // Drawn on black: white text in a black halo.
    let n = 300 * 200;
    let mut img = Image {
        width: 300,
        height: 200,
        rgb: vec![[0.0; 3]; n],
        alpha: vec![0.0; n],
        depth: vec![f64::INFINITY; n],
        background: [0.0; 3],
    };
    img.draw_legend(Colormap::Viridis, 0.25, 0.75, contrasting_ink([0.0; 3]));
    assert!(img.rgb.iter().filter(|p| **p == [1.0; 3]).count() >= 20, "no white text on black");
}
