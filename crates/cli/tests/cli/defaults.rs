//! Defaults that look right: the camera frames the subject on the shipped files, thin tubes
//! are drawn for every format (SWC too), `--aa N` antialiases, the legend reads on any
//! background.

use crate::common::bin;
use std::path::{Path, PathBuf};
use tubecast_render::io::npy;
crate::common::tmp_fn!();

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn render(input: &Path, out: &Path, extra: &[&str]) {
    let o = bin().arg("render").arg(input).args(["-q", "--force", "-o"]).arg(out).args(extra).output().unwrap();
    assert!(o.status.success(), "{}: {}", input.display(), String::from_utf8_lossy(&o.stderr));
}

/// Decode an RGB PNG: width, height, bytes.
fn decode(path: &Path) -> (usize, usize, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width as usize, info.height as usize, buf)
}

#[test]
fn the_camera_frames_the_shipped_files() {
    let neurons = tmp("frame-neurons.swc");
    let helix = tmp("frame-helix.swc");
    assert!(bin().args(["generate", "neurons", "--n", "2", "-o"]).arg(&neurons).status().unwrap().success());
    assert!(bin().args(["generate", "helix", "-o"]).arg(&helix).status().unwrap().success());
    let mut files = vec![neurons, helix];
    for rel in [
        "reference/readers/nibabel/standard.trk",
        "reference/readers/nibabel/complex.trk",
        "reference/readers/nibabel/standard.tck",
        "reference/readers/trx/complex_float32_uint32_stored.trx",
        "fuzz/corpus/swc/tree.swc",
        "crates/cli/tests/data/simplify/bundle.obj",
        "crates/cli/tests/data/simplify/helix.obj",
    ] {
        files.push(repo(rel));
    }
    let (w, h) = (160, 120);
    for f in files {
        for view in [&[][..], &["--view", "xy"][..], &["--view", "iso", "--ortho"][..]] {
            let depth = tmp("frame.npy");
            let size = ["--width", "160", "--height", "120", "--depth", depth.to_str().unwrap()];
            render(&f, &tmp("frame.png"), &[&size[..], view].concat());
            let d = npy::read(&std::fs::read(&depth).unwrap(), "depth", None).unwrap();
            let seen: Vec<(usize, usize)> =
                (0..w * h).filter(|&i| d.data[i].is_finite()).map(|i| (i % w, i / w)).collect();
            let (x0, x1) = (seen.iter().map(|p| p.0).min().unwrap(), seen.iter().map(|p| p.0).max().unwrap());
            let (y0, y1) = (seen.iter().map(|p| p.1).min().unwrap(), seen.iter().map(|p| p.1).max().unwrap());
            // The subject's extent over the image side it spans most of (a long thin bundle
            // cannot fill the height too without being cut): the framing leaves 5% on the side
            // that limits, up to perspective and a one-pixel thin-tube widening.
            let fill = ((x1 - x0 + 1) as f64 / w as f64).max((y1 - y0 + 1) as f64 / h as f64);
            assert!(fill >= 0.6, "{} {view:?}: the subject fills {fill:.2} of the image", f.display());
            // Nothing is cut off at the edges.
            assert!(x0 > 0 && y0 > 0 && x1 < w - 1 && y1 < h - 1, "{} {view:?}: touches the edge", f.display());
        }
    }
}

#[test]
fn thin_tubes_are_drawn_for_swc_too() {
    // A 100 µm neurite of radius 0.01 µm: a pixel of a 40 px image spans ≈ 2.6 µm, so the
    // pixel centres miss the tube unless it is widened (the default for every format now).
    let swc = tmp("thin.swc");
    std::fs::write(&swc, "1 3 0 0 0 0.01 -1\n2 3 50 0 0 0.01 1\n3 3 100 0 0 0.01 2\n").unwrap();
    let (on, off) = (tmp("thin-on.png"), tmp("thin-off.png"));
    render(&swc, &on, &["--width", "40", "--height", "30", "--view", "xy"]);
    render(&swc, &off, &["--width", "40", "--height", "30", "--view", "xy", "--thin", "off"]);
    let covered = |p: &Path| decode(p).2.chunks(3).filter(|c| c != &[255, 255, 255]).count();
    assert_eq!(covered(&off), 0);
    assert!(covered(&on) >= 20, "{} pixels show the thin neurite", covered(&on));
}

/// sRGB byte → linear.
fn linear(b: u8) -> f64 {
    let s = b as f64 / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn antialiasing_approaches_the_pixel_average() {
    // The pixel average, estimated by 4×4 pixel centres of a 4× larger image (the same framing:
    // the camera depends on the aspect only), against 1 and 4×4 jittered samples at 64×48.
    let swc = tmp("aa.swc");
    assert!(bin().args(["generate", "helix", "--segments", "40", "-o"]).arg(&swc).status().unwrap().success());
    let flat = ["--thin", "off", "--color", "solid:#204080", "--background", "white"];
    let (big, one, four, plain) = (tmp("aa-big.png"), tmp("aa-1.png"), tmp("aa-4.png"), tmp("aa-default.png"));
    render(&swc, &big, &[&flat[..], &["--width", "256", "--height", "192"]].concat());
    render(&swc, &one, &[&flat[..], &["--width", "64", "--height", "48", "--aa", "1"]].concat());
    render(&swc, &plain, &[&flat[..], &["--width", "64", "--height", "48"]].concat());
    render(&swc, &four, &[&flat[..], &["--width", "64", "--height", "48", "--aa", "4"]].concat());
    assert_eq!(std::fs::read(&one).unwrap(), std::fs::read(&plain).unwrap(), "--aa 1 is the default");
    let (bw, _, b) = decode(&big);
    let reference: Vec<f64> = (0..64 * 48 * 3)
        .map(|i| {
            let (c, p) = (i % 3, i / 3);
            let (x, y) = (p % 64, p / 64);
            let cell = (0..16).map(|s| b[((4 * y + s / 4) * bw + 4 * x + s % 4) * 3 + c]);
            cell.map(linear).sum::<f64>() / 16.0
        })
        .collect();
    let err = |p: &Path| -> f64 {
        let px = decode(p).2;
        px.iter().zip(&reference).map(|(&v, r)| (linear(v) - r).abs()).sum::<f64>() / reference.len() as f64
    };
    let (e1, e4) = (err(&one), err(&four));
    // Both estimate each pixel's average colour, and miss only where an edge crosses a pixel
    // (elsewhere every estimate is the surface or the background, up to shading across the
    // pixel). There one sample is off by the share of the pixel on the other side of the
    // edge, a quarter of the contrast on average; 4×4 samples, one per cell, only by the
    // cells the edge cuts, one row of four in sixteen at most: under half the first.
    assert!(e4 < 0.5 * e1, "mean error, linear units: 1 sample {e1:.4}, 16 samples {e4:.4}");
}

/// WCAG contrast ratio of two linear RGB colours.
fn contrast(a: [f64; 3], b: [f64; 3]) -> f64 {
    let l = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let (la, lb) = (l(a), l(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

#[test]
fn the_legend_reads_on_any_background() {
    let input = repo("reference/readers/nibabel/complex.trk");
    for bg in ["black", "white", "grey", "#102030", "#f0e0a0", "0.2,0.6,0.2"] {
        let png = tmp("legend.png");
        render(
            &input,
            &png,
            &["--color", "scalar:fa", "--legend", "--width", "300", "--height", "200", "--background", bg],
        );
        let (w, h, px) = decode(&png);
        let at = |x: usize, y: usize| -> [u8; 3] { std::array::from_fn(|k| px[(y * w + x) * 3 + k]) };
        let back = at(0, 0).map(linear);
        // The ink that contrasts more (the two ratios multiply to 21, so the better one is
        // ≥ √21 ≈ 4.58, above WCAG's 4.5 for text), drawn in the right third of the image.
        let ink = if contrast([1.0; 3], back) > contrast([0.0; 3], back) { [1.0; 3] } else { [0.0; 3] };
        let ink8 = ink.map(|v| (v * 255.0) as u8);
        let drawn = (0..h).flat_map(|y| (2 * w / 3..w).map(move |x| (x, y))).filter(|&(x, y)| at(x, y) == ink8).count();
        assert!(drawn >= 20, "{bg}: no legend text in {ink8:?} ({drawn} pixels)");
        let c = contrast(ink, back);
        assert!(c >= 4.5, "{bg}: legend ink {ink:?} on {back:?} has contrast {c:.2}");
    }
}
