//! Render options: --background (colour, transparent RGBA), solid:#rrggbb, --view presets,
//! --ortho, --depth OUT.npy, --force, --radius N% ; info --json with units.

use crate::common::bin;
crate::common::tmp_fn!();
use std::path::{Path, PathBuf};
use tubecast_render::io::{npy, tck, Polyline};

/// One straight streamline along x from 0 to 1000 (a file in "µm-like" large units).
fn line_tck(name: &str) -> PathBuf {
    let p = tmp(name);
    let l = Polyline { points: vec![[0.0, 0.0, 0.0], [500.0, 0.0, 0.0], [1000.0, 0.0, 0.0]], radii: vec![] };
    std::fs::write(&p, tck::write(&[l], false)).unwrap();
    p
}

fn run(input: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut c = bin();
    c.arg("render").arg(input).arg("-o").arg(out).args(["--width", "40", "--height", "30", "--quiet"]).args(extra);
    c.output().unwrap()
}

/// Decode a PNG: (colour type, width, height, bytes).
fn decode(path: &Path) -> (png::ColorType, u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.color_type, info.width, info.height, buf)
}

#[test]
fn force_is_needed_to_overwrite() {
    let input = line_tck("force.tck");
    let out = tmp("force.png");
    assert!(run(&input, &out, &["--radius", "2%"]).status.success());
    let o = run(&input, &out, &["--radius", "2%"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--force"));
    assert!(run(&input, &out, &["--radius", "2%", "--force"]).status.success());
}

#[test]
fn background_colour_solid_colour_and_transparency() {
    let input = line_tck("bg.tck");
    let out = tmp("bg.png");
    // Background #102030 and solid #ff0000, flat enough to see both: the corner is the
    // background byte-exact, some pixel is pure-ish red (lit shading scales it).
    let o = run(&input, &out, &["--radius", "2%", "--background", "#102030", "--color", "solid:#ff0000"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (ct, w, _, px) = decode(&out);
    assert_eq!(ct, png::ColorType::Rgb);
    assert_eq!(&px[0..3], &[0x10, 0x20, 0x30]);
    assert!(px.chunks(3).any(|p| p[0] > 100 && p[1] < 40 && p[2] < 40), "no red tube pixel");
    // Transparent: RGBA, alpha 0 in the corner, 255 on the tube.
    let o = run(&input, &out, &["--radius", "2%", "--background", "transparent", "--force"]);
    assert!(o.status.success());
    let (ct, w2, _, px) = decode(&out);
    assert_eq!((ct, w2), (png::ColorType::Rgba, w));
    assert_eq!(px[3], 0);
    assert!(px.chunks(4).any(|p| p[3] == 255));
    // Transparent tubes: alpha is the accumulated opacity. Every line through the tube
    // crosses two surfaces of opacity 0.5 (entry, exit): α = 1 − 0.5² = 0.75, byte 191 ± 1
    // (f32 compositing, 1/255 quantisation); the background stays 0. (--thin off: no fade.)
    let o = run(
        &input,
        &out,
        &["--radius", "2%", "--background", "transparent", "--opacity", "0.5", "--thin", "off", "--force"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (ct, _, _, px) = decode(&out);
    assert_eq!(ct, png::ColorType::Rgba);
    assert!(px.chunks(4).all(|p| p[3] == 0 || (190..=192).contains(&p[3])), "alpha not 0 or 0.75");
    assert!(px.chunks(4).any(|p| p[3] == 191), "no transparent tube pixel");
    let o = run(&input, &out, &["--background", "#12", "--force"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("#rrggbb"));
}

#[test]
fn relative_radius_shows_tubes_at_any_scale_and_depth_is_written() {
    // The line is 1000 units long: an absolute 0.2 is under a pixel wide at 40 px, 2% is ~8 px.
    let input = line_tck("rel.tck");
    let (out, depth) = (tmp("rel.png"), tmp("rel-depth.npy"));
    let o = run(&input, &out, &["--radius", "2%", "--view", "xy", "--ortho", "--depth", depth.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d = npy::read(&std::fs::read(&depth).unwrap(), "d", None).unwrap();
    assert_eq!((d.rows, d.cols), (30, 40));
    let hits = d.data.iter().filter(|v| v.is_finite()).count();
    // Orthographic, looking down −z at a tube of radius 20 (2% of 1000) whose image is the
    // framed width: rows covered ≈ 2·20 / (view height / 30); at least one full row hit.
    assert!(hits >= 40, "{hits} pixels see the tube");
    assert!(d.data.iter().all(|v| !v.is_nan()));
    // Orthographic depth along the view axis: every hit of the xy view at the tube's top is at
    // the same depth where the tube is straight (z-extent ±20): spread ≤ 40.
    let fin: Vec<f64> = d.data.iter().copied().filter(|v| v.is_finite()).collect();
    let (lo, hi) = fin.iter().fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(hi - lo <= 40.0 + 1e-9, "depth spread {}", hi - lo);
    let o = run(&input, &tmp("abs.png"), &["--radius", "0%"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("percentage"));
    let o = run(&input, &tmp("v.png"), &["--view", "top"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("xy, xz, yz or iso"));
}

#[test]
fn info_json_with_units() {
    let input = line_tck("info.tck");
    let o = bin().args(["info", "--json"]).arg(&input).output().unwrap();
    assert!(o.status.success());
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["nodes"], 3);
    assert_eq!(j["links"], 2);
    assert!(j["units"].as_str().unwrap().starts_with("mm"));
    assert_eq!(j["bounds"]["max"][0].as_f64().unwrap(), 1000.2);
    let o = bin().arg("info").arg(&input).output().unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains("units      mm"));
}

#[test]
fn thin_tubes_stay_visible_by_default_for_tractograms() {
    // Radius 2 on a 1000-unit line: a pixel at 40 px is ≈ 26 units, so the pixel-centre lines
    // (±½ pixel from the axis) miss the tube; on by default for .tck (wireframe-like), the
    // tube is widened to 1 pixel and faded by its coverage ≈ 2/13, so some pixels differ from
    // the background; --thin off: none do. (A radius of 0.01 has coverage ≈ 8·10⁻⁴: composited
    // correctly, α·surface + (1 − α)·background, it stays under one 8-bit step of the
    // background, as a wire that thin should.)
    let input = line_tck("thin.tck");
    let (on, off) = (tmp("thin-on.png"), tmp("thin-off.png"));
    assert!(run(&input, &on, &["--radius", "2", "--view", "xy"]).status.success());
    assert!(run(&input, &off, &["--radius", "2", "--view", "xy", "--thin", "off"]).status.success());
    let covered = |p: &Path| decode(p).3.chunks(3).filter(|c| c != &[255, 255, 255]).count();
    assert_eq!(covered(&off), 0);
    assert!(covered(&on) >= 20, "{} pixels show the thin line", covered(&on));
}
