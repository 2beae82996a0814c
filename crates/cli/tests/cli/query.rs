//! `tubecast intersect --query hit|piece|all --threads N` end to end.

use crate::common::bin;
crate::common::tmp_fn!();
use tubecast_render::io::npy::{read, write, Array2};

fn run(swc: &std::path::Path, rays: &std::path::Path, extra: &[&str], name: &str) -> Array2 {
    let hp = tmp(name);
    let out =
        bin().arg("intersect").arg(swc).arg("--rays").arg(rays).arg("--out").arg(&hp).args(extra).output().unwrap();
    assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
    read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap()
}

#[test]
fn the_three_queries_agree_on_a_ray_from_outside() {
    let swc = tmp("q-helix.swc");
    assert!(bin().args(["generate", "helix", "--segments", "20", "-o"]).arg(&swc).status().unwrap().success());
    // The ray of cli_commands.rs (up +z from (4, 0, −20), entering strand 0's first sphere at
    // t = 9.575, link 0, u = 0) and one that misses.
    let rays = Array2 { rows: 2, cols: 6, data: vec![4.0, 0.0, -20.0, 0.0, 0.0, 1.0, 100.0, 0.0, 0.0, 0.0, 0.0, 1.0] };
    let rp = tmp("q-rays.npy");
    std::fs::write(&rp, write(&rays)).unwrap();
    let hit = run(&swc, &rp, &["--threads", "1"], "q-hit.npy");
    let piece = run(&swc, &rp, &["--query", "piece", "--threads", "2"], "q-piece.npy");
    let all = run(&swc, &rp, &["--query", "all"], "q-all.npy");
    let (h, p) = (hit.row(0), piece.row(0));
    // The same f64 interval on both paths: the entry is bit-identical (see accel/table.rs).
    assert_eq!((h[0], h[5], h[6], h[7]), (p[0], 0.0, 0.0, 1.0), "hit {h:?} piece {p:?}");
    assert!((9.575 - h[0]).abs() < 1e-5 && h[1] > h[0] && h[1] <= p[1], "{h:?} {p:?}");
    assert_eq!(hit.row(1), piece.row(1));
    assert_eq!(hit.row(1)[7], 0.0);
    // All crossings: ray 0 only, entries and exits alternating, the first one the piece's.
    assert!(all.rows >= 2 && all.rows % 2 == 0, "{} rows", all.rows);
    assert_eq!((all.row(0)[0], all.row(0)[1], all.row(0)[7]), (0.0, p[0], 1.0));
    assert_eq!((all.row(1)[1], all.row(1)[7]), (p[1], -1.0));
    assert!((0..all.rows).all(|k| all.row(k)[0] == 0.0));
}

#[test]
fn zero_threads_is_refused() {
    let out = bin().args(["render", "x.swc", "-o", "x.png", "--threads", "0"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--threads"));
}
