//! `intersect` with float32 Fortran-order rays from stdin and CSV hits to stdout.

use crate::common::bin;
crate::common::tmp_fn!();
use std::io::Write;
use std::process::Stdio;
use tubecast_render::io::{tck, Polyline};

/// A float32 Fortran-order N×6 .npy (columns stored one after another).
fn rays_f32_fortran(rows: &[[f32; 6]]) -> Vec<u8> {
    let mut h = format!("{{'descr': '<f4', 'fortran_order': True, 'shape': ({}, 6), }}", rows.len());
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut d = b"\x93NUMPY\x01\x00".to_vec();
    d.extend_from_slice(&(h.len() as u16).to_le_bytes());
    d.extend_from_slice(h.as_bytes());
    for c in 0..6 {
        for r in rows {
            d.extend_from_slice(&r[c].to_le_bytes());
        }
    }
    d
}

#[test]
fn float32_fortran_rays_from_stdin_csv_hits_to_stdout() {
    // One link from (0,0,0) to (10,0,0), radius 1. Ray 0 straight down at x = 5 from z = 10:
    // enters at z = 1 (t = 9), leaves at z = −1 (t = 11), normal +z, link 0, u = 0.5, hit.
    // Ray 1 passes far away: a miss row.
    let scene = tmp("rays-line.tck");
    let l = Polyline { points: vec![[0.0; 3], [10.0, 0.0, 0.0]], radii: vec![] };
    std::fs::write(&scene, tck::write(&[l], false)).unwrap();
    let rays = rays_f32_fortran(&[[5.0, 0.0, 10.0, 0.0, 0.0, -1.0], [50.0, 0.0, 10.0, 0.0, 0.0, -1.0]]);
    let mut child = bin()
        .args(["intersect"])
        .arg(&scene)
        .args(["--radius", "1", "--rays", "-", "--out", "-", "--csv"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(&rays).unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "t_in,t_out,nx,ny,nz,link,u,hit");
    let row: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
    let want = [9.0, 11.0, 0.0, 0.0, 1.0, 0.0, 0.5, 1.0];
    for (k, (g, w)) in row.iter().zip(want).enumerate() {
        // The f32 cylinder kernel: t and u within 1e-5 of the exact values (f32 rounding of a
        // scene of size 10: ~10·2⁻²⁰).
        assert!((g - w).abs() <= 1e-5, "column {k}: {g} vs {w}");
    }
    assert_eq!(lines[2], "inf,inf,0,0,0,-1,0,0");
    assert_eq!(lines.len(), 3);
    // The same to a .csv file name without --csv.
    let out = tmp("hits.csv");
    let rays_path = tmp("rays.npy");
    std::fs::write(&rays_path, &rays).unwrap();
    let st = bin()
        .arg("intersect")
        .arg(&scene)
        .args(["--radius", "1", "--rays"])
        .arg(&rays_path)
        .arg("--out")
        .arg(&out)
        .status();
    assert!(st.unwrap().success());
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    // `--query all`: one row per boundary, under its own header; the miss has no row.
    let all = bin()
        .arg("intersect")
        .arg(&scene)
        .args(["--radius", "1", "--query", "all", "--csv", "--out", "-", "--rays"])
        .arg(&rays_path)
        .output()
        .unwrap();
    assert!(all.status.success(), "{}", String::from_utf8_lossy(&all.stderr));
    let text = String::from_utf8(all.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "ray,t,nx,ny,nz,link,u,flag");
    assert_eq!(lines.len(), 3, "{text}");
    assert!(lines[1].starts_with("0,") && lines[1].ends_with(",1") && lines[2].ends_with(",-1"), "{text}");
}
