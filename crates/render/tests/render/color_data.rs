//! Colouring by the data the files carry: TrackVis scalars and properties, the `.tsf` beside a
//! `.tck`, through a named colour map (`ColorBy::Values`).

use std::path::PathBuf;
use tubecast_render::accel::Bvh;
use tubecast_render::io::{tck, trk, Polyline};
use tubecast_render::render::{self, ColorBy, Colormap, Options, Shading, View};
use tubecast_render::scene::{LoadOptions, Scene};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tubecast-color-data-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Two streamlines along x at y = ±2, two points each; a TrackVis file with scalar "fa"
/// (per point) and property "len" (per streamline).
fn two_lines_trk(fa: [f32; 4], len: [f32; 2]) -> Vec<u8> {
    let h = trk::TrkHeader { n_scalars: 1, n_properties: 1, ..trk::TrkHeader::default() };
    let p = |x: f64, y: f64| [x, y, 0.0];
    let lines = vec![
        Polyline { points: vec![p(-4.0, 2.0), p(4.0, 2.0)], radii: vec![] },
        Polyline { points: vec![p(-4.0, -2.0), p(4.0, -2.0)], radii: vec![] },
    ];
    let mut d = trk::write(&h, &lines, false);
    d[38..40].copy_from_slice(b"fa");
    d[240..243].copy_from_slice(b"len");
    // Records of 40 bytes from 1000: count, 2 × (x y z fa), len (the writer wrote zeros there).
    for (s, base) in [0usize, 1].iter().zip([1004usize, 1044]) {
        for k in 0..2 {
            let at = base + k * 16 + 12;
            d[at..at + 4].copy_from_slice(&fa[2 * s + k].to_le_bytes());
        }
        d[base + 32..base + 36].copy_from_slice(&len[*s].to_le_bytes());
    }
    d
}

#[test]
fn trackvis_scalars_and_properties_become_node_values() {
    let path = tmp("two.trk");
    std::fs::write(&path, two_lines_trk([0.1, 0.2, 0.3, 0.4], [5.0, 9.0])).unwrap();
    let (mut scene, _, fields) = Scene::load_fields(&path, &LoadOptions::default()).unwrap();
    scene.select_values(&fields, "scalar:fa").unwrap();
    assert_eq!(scene.values, [0.1f32, 0.2, 0.3, 0.4].map(|v| v as f64));
    scene.select_values(&fields, "property:len").unwrap();
    assert_eq!(scene.values, vec![5.0, 5.0, 9.0, 9.0]);
    scene.select_values(&fields, "scalar:radius").unwrap();
    assert_eq!(scene.values, vec![0.2; 4]);
    let e = scene.select_values(&fields, "scalar:nope").unwrap_err().to_string();
    assert!(e.contains("scalar:fa") && e.contains("property:len"), "{e}");
}

#[test]
fn tsf_beside_a_tck_is_scalar_tsf() {
    let lines = vec![Polyline { points: vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], radii: vec![] }];
    let path = tmp("t.tck");
    std::fs::write(&path, tck::write(&lines, false)).unwrap();
    std::fs::write(path.with_extension("tsf"), tck::write_tsf(&[vec![1.5, 2.5, 3.5]])).unwrap();
    let (mut scene, _, fields) = Scene::load_fields(&path, &LoadOptions::default()).unwrap();
    scene.select_values(&fields, "scalar:tsf").unwrap();
    assert_eq!(scene.values, vec![1.5, 2.5, 3.5]);
    // A .tsf with other streamline lengths is not this file's companion: an error.
    std::fs::write(path.with_extension("tsf"), tck::write_tsf(&[vec![1.0, 2.0]])).unwrap();
    assert!(Scene::load_fields(&path, &LoadOptions::default()).unwrap_err().to_string().contains("lengths differ"));
    // read_tsf round trip and malformed data.
    assert_eq!(
        tck::read_tsf(&tck::write_tsf(&[vec![1.0], vec![2.0, 3.0]]), "a.tsf").unwrap(),
        vec![vec![1.0], vec![2.0, 3.0]]
    );
    let mut cut = tck::write_tsf(&[vec![1.0]]);
    cut.truncate(cut.len() - 4);
    assert!(tck::read_tsf(&cut, "cut.tsf").unwrap_err().to_string().contains("Inf end marker"));
}

/// sRGB byte → linear, the standard transfer function (written out here, not the crate's).
fn lin(v: u8) -> f32 {
    let s = v as f32 / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn flat_render_shows_the_colour_map_ends() {
    // fa = 0 on the upper streamline, 1 on the lower: flat shading shows viridis(0) = #440154
    // and viridis(1) = #fde725 (the published ends of viridis) exactly, NaN-free.
    let path = tmp("ends.trk");
    std::fs::write(&path, two_lines_trk([0.0, 0.0, 1.0, 1.0], [0.0, 0.0])).unwrap();
    let (mut scene, _, fields) =
        Scene::load_fields(&path, &LoadOptions { default_radius: 0.8, min_radius: None }).unwrap();
    scene.select_values(&fields, "scalar:fa").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let view = View {
        eye: Some([0.0, 0.0, 20.0]),
        look_at: Some([0.0; 3]),
        up: [0.0, 1.0, 0.0],
        fov_deg: 40.0,
        width: 64,
        height: 64,
    };
    let cam = view.camera(([-5.0; 3], [5.0; 3])).unwrap();
    let opts = Options { color: ColorBy::Values(Colormap::Viridis), shading: Shading::Flat, ..Options::default() };
    let img = render::render(&scene, &bvh, &cam, &opts).unwrap();
    let want_lo = [0x44, 0x01, 0x54].map(lin);
    let want_hi = [0xfd, 0xe7, 0x25].map(lin);
    let (mut lo, mut hi) = (0, 0);
    for p in &img.rgb {
        assert!(p.iter().all(|c| c.is_finite()));
        let close = |w: [f32; 3]| p.iter().zip(w).all(|(a, b)| (a - b).abs() <= 1e-6);
        lo += close(want_lo) as usize;
        hi += close(want_hi) as usize;
    }
    assert!(lo > 20 && hi > 20, "pixels of viridis(0): {lo}, of viridis(1): {hi}");
    // The upper streamline (y = +2) is the one with value 0: image rows grow downward.
    let col = 32;
    let upper = (0..32).find(|&y| img.at(col, y) != [1.0; 3]).expect("the upper tube is visible");
    assert!(img.at(col, upper + 1).iter().zip(want_lo).all(|(a, b)| (a - b).abs() <= 1e-6));
}

#[test]
fn legend_bar_runs_from_low_to_high_with_its_labels() {
    let (w, h) = (200u32, 100u32);
    let n = (w * h) as usize;
    let mut img = render::Image {
        width: w,
        height: h,
        rgb: vec![[1.0; 3]; n],
        alpha: vec![0.0; n],
        depth: vec![f64::INFINITY; n],
        background: [1.0; 3],
    };
    img.draw_legend(Colormap::Viridis, -0.5, 2.0, [0.0; 3]);
    // Layout (documented): bar over rows h/5 .. h − h/5, top row the map's high end, bottom
    // row its low end; find the bar's columns by the top row's viridis(1) colour.
    let (top, bottom) = (h / 5, h - h / 5);
    let want_hi = [0xfd, 0xe7, 0x25].map(lin);
    let want_lo = [0x44, 0x01, 0x54].map(lin);
    let near = |p: [f32; 3], w: [f32; 3]| p.iter().zip(w).all(|(a, b)| (a - b).abs() <= 1e-6);
    let xs: Vec<u32> = (0..w).filter(|&x| near(img.at(x, top), want_hi)).collect();
    assert!(xs.len() >= 6, "bar columns {xs:?}");
    assert!(xs.iter().all(|&x| near(img.at(x, bottom - 1), want_lo)));
    // Frame and labels in ink, to the right of the bar's first column, nowhere left of the bar.
    let ink = |x: u32, y: u32| img.at(x, y) == [0.0; 3];
    assert!((xs[xs.len() - 1] + 2..w).any(|x| (top..top + 5).any(|y| ink(x, y))), "high label drawn");
    assert!((xs[xs.len() - 1] + 2..w).any(|x| (bottom - 5..bottom).any(|y| ink(x, y))), "low label drawn");
    assert!((0..xs[0] - 1).all(|x| (0..h).all(|y| img.at(x, y) == [1.0; 3])), "nothing drawn left of the bar");
    assert_eq!(render::legend_label(-0.5), "-0.5");
    assert_eq!(render::legend_label(2.0), "2");
    assert_eq!(render::legend_label(1.5e-6), "1.50e-6");
    assert_eq!(render::legend_label(0.0), "0");
}
