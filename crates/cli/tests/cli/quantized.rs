//! `render --model quantized`: Kanzler's quantized lines through the ordinary renderer. Their
//! coverage may differ from the exact render's only within the silhouette band the derived
//! Hausdorff bound allows; bad quantization options are errors.
//!
//! # The band
//! The tubes here have one radius `r`, so each model's tube set is its axis lines swept by a
//! ball of radius `r`, and an orthographic ray (a line; the camera is outside the scene)
//! hits it iff its distance `d` to the axes is ≤ `r`. The quantized axes are within `ε` (the
//! printed bound) of the exact ones both ways, so `|d_q − d| ≤ ε`. Take a pixel that model X
//! misses and the other hits: `r < d_X ≤ r + ε`. Moving the ray sideways by `s` toward the
//! nearest point of X's axes lowers `d_X` by exactly `s`, so at `s = d_X − r + p√2/2 < ε + p√2/2`
//! (`p` the pixel size) `d_X ≤ r − p√2/2` (possible while `r ≥ p√2/2`), and the pixel centre
//! nearest to there (within `p√2/2`) has `d_X ≤ r`: X covers a pixel within
//! `ε/p + √2` pixels of every pixel where the two differ.

use crate::common::bin;
crate::common::tmp_fn!();
use std::path::Path;

/// Image size, camera distance, field of view (degrees), tube radius.
const W: usize = 256;
const H: usize = 64;
const DIST: f64 = 100.0;
const FOV: f64 = 18.0;
const R: f64 = 0.5;

/// The generated bundle's bounds (from `info --json`): its centre.
fn centre(tck: &Path) -> [f64; 3] {
    let out = bin().arg("info").arg(tck).args(["--json", "--radius", &R.to_string()]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let nums = |key: &str| -> Vec<f64> {
        let s = &text[text.find(key).unwrap() + key.len()..];
        let s = &s[s.find('[').unwrap() + 1..s.find(']').unwrap()];
        s.split(',').map(|t| t.trim().parse().unwrap()).collect()
    };
    let (lo, hi) = (nums("\"min\""), nums("\"max\""));
    std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]))
}

/// Render `tck` orthographically down −z onto the centre, with `extra` options: the coverage
/// mask (alpha > 0), the depth buffer, and stderr.
fn render(tck: &Path, c: [f64; 3], name: &str, extra: &[&str]) -> (Vec<bool>, Vec<f64>, String) {
    let (png, npy) = (tmp(&format!("{name}.png")), tmp(&format!("{name}.npy")));
    let v3 = |p: [f64; 3]| format!("{},{},{}", p[0], p[1], p[2]);
    let run = bin()
        .arg("render")
        .arg(tck)
        .args(["--ortho", "--thin", "off", "--background", "transparent", "--force", "--radius", &R.to_string()])
        .args(["--width", &W.to_string(), "--height", &H.to_string(), "--fov", &FOV.to_string()])
        .args(["--eye", &v3([c[0], c[1], c[2] + DIST]), "--look-at", &v3(c)])
        .args(extra)
        .arg("--depth")
        .arg(&npy)
        .arg("-o")
        .arg(&png)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(run.status.success(), "{err}");
    let mut reader =
        png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap())).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width as usize, info.height as usize, info.color_type), (W, H, png::ColorType::Rgba));
    let cover = buf[..W * H * 4].chunks(4).map(|px| px[3] > 0).collect();
    let bytes = std::fs::read(&npy).unwrap();
    let depth = bytes[bytes.len() - W * H * 8..].chunks(8).map(|b| f64::from_le_bytes(b.try_into().unwrap())).collect();
    (cover, depth, err)
}

/// The derived bound from the summary on stderr.
fn bound(stderr: &str) -> f64 {
    let s = &stderr[stderr.find("derived Hausdorff bound ").expect(stderr) + 24..];
    s.split_whitespace().next().unwrap().parse().unwrap()
}

/// Over the pixels where the masks differ: the number of them, and the largest distance (in
/// pixels) from one to the nearest pixel that the mask missing it covers (∞ when none within
/// `reach`).
fn band(a: &[bool], b: &[bool], reach: i64) -> (usize, f64) {
    let (mut n, mut worst) = (0, 0.0f64);
    for y in 0..H as i64 {
        for x in 0..W as i64 {
            let k = (y * W as i64 + x) as usize;
            if a[k] == b[k] {
                continue;
            }
            n += 1;
            let miss = if a[k] { b } else { a };
            let mut near = f64::INFINITY;
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let (u, v) = (x + dx, y + dy);
                    if (0..W as i64).contains(&u) && (0..H as i64).contains(&v) && miss[(v * W as i64 + u) as usize] {
                        near = near.min(((dx * dx + dy * dy) as f64).sqrt());
                    }
                }
            }
            worst = worst.max(near);
        }
    }
    (n, worst)
}

#[test]
fn quantized_render_differs_only_within_the_derived_silhouette_band() {
    let tck = tmp("quant_bundle.tck");
    assert!(bin()
        .args(["generate", "bundle", "--count", "12", "--segments", "40", "-o"])
        .arg(&tck)
        .status()
        .unwrap()
        .success());
    let c = centre(&tck);
    let p = 2.0 * (FOV / 2.0).to_radians().tan() * DIST / H as f64; // pixel size (orthographic)
    assert!(R >= p * 0.5f64.sqrt(), "the band's derivation needs r ≥ p√2/2 (p = {p})");
    let (exact, _, _) = render(&tck, c, "quant_exact", &[]);
    assert!(exact.iter().filter(|&&x| x).count() > W * H / 20, "the bundle fills the frame");
    let mut widest = (0.0, 0.0, 0.0);
    for (q, voxels) in [("8", "4"), ("8", "16"), ("16", "64")] {
        let (quant, depth, err) = render(
            &tck,
            c,
            &format!("quant_{q}"),
            &["--model", "quantized", "--quant-bins", q, "--quant-voxels", voxels],
        );
        assert!(depth.iter().all(|d| !d.is_nan()), "no NaN in the depth buffer");
        assert!(
            err.contains(&format!("Q = {q} bins")) && err.contains("B per segment") && err.contains("B per link"),
            "{err}"
        );
        let eps = bound(&err);
        let allowed = eps / p + 2f64.sqrt();
        let (n, worst) = band(&exact, &quant, allowed.ceil() as i64 + 2);
        assert!(
            worst <= allowed,
            "Q = {q}: a differing pixel {worst} px from the other silhouette > {allowed} (ε = {eps})"
        );
        assert!(n > 0, "Q = {q}: the quantized lines moved no silhouette");
        eprintln!("Q = {q}, {voxels} voxels: ε = {eps}, {n} pixels differ, worst {worst:.3} px ≤ {allowed:.3} px");
        if worst > widest.0 {
            widest = (worst, eps, allowed);
        }
    }
    // The check is not vacuous: on the coarsest grid some differing pixel lies beyond the band
    // that a bound a quarter as large would allow, so an under-estimated bound fails it.
    let (worst, eps, _) = widest;
    assert!(worst > eps / 4.0 / p + 2f64.sqrt(), "worst {worst} px within the band of ε/4 = {}", eps / 4.0);
}

#[test]
fn bad_quantization_options_are_errors() {
    let tck = tmp("quant_bad.tck");
    assert!(bin().args(["generate", "helix", "--segments", "10", "-o"]).arg(&tck).status().unwrap().success());
    for (args, says) in [
        (vec!["--quant-bins", "7"], "'7' for '--quant-bins <Q>': 7 is not in 8..=64"),
        (vec!["--quant-bins", "65"], "'65' for '--quant-bins <Q>': 65 is not in 8..=64"),
        (vec!["--quant-voxels", "0"], "'0' for '--quant-voxels <N>': 0 is not in 1..=4096"),
        (vec!["--color", "scalar:x"], "no data fields"),
    ] {
        let out = bin()
            .arg("render")
            .arg(&tck)
            .args(["--model", "quantized", "-o"])
            .arg(tmp("quant_bad.png"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("tubecast: error:") && err.contains(says), "{args:?}: {err}");
    }
    assert!(!tmp("quant_bad.png").exists(), "no image on error");
}
