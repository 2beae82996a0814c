//! View presets and the orthographic camera.

use tubecast_render::render::{Camera, Preset};

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
