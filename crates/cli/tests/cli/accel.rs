//! `--accel grid|bvh`: `intersect` writes the same hit table through either structure (same
//! kernels, only the culling differs), and `render --accel grid` writes an image.

use crate::common::bin;
crate::common::tmp_fn!();
use tubecast_render::io::npy::{read, write, Array2};

#[test]
fn intersect_and_render_through_the_grid() {
    let swc = tmp("accel_helix.swc");
    assert!(bin().args(["generate", "helix", "--segments", "30", "-o"]).arg(&swc).status().unwrap().success());
    // 200 rays from a ring around the helix towards points on its axis.
    let mut data = Vec::new();
    for k in 0..200 {
        let a = k as f64 * 0.37;
        let z = -10.0 + 20.0 * (k as f64 / 200.0);
        data.extend([12.0 * a.cos(), 12.0 * a.sin(), z, -a.cos(), -a.sin(), 0.01 * (k % 7) as f64]);
    }
    let rp = tmp("accel_rays.npy");
    std::fs::write(&rp, write(&Array2 { rows: 200, cols: 6, data })).unwrap();
    let mut tables = Vec::new();
    for accel in ["bvh", "grid"] {
        let hp = tmp(&format!("accel_hits_{accel}.npy"));
        let mut cmd = bin();
        cmd.arg("intersect").arg(&swc).arg("--rays").arg(&rp).arg("--out").arg(&hp).args(["--accel", accel]);
        assert!(cmd.status().unwrap().success());
        tables.push(read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap());
    }
    assert_eq!(tables[0], tables[1], "grid and BVH hit tables differ");
    assert!(tables[0].data.chunks(8).filter(|r| r[7] == 1.0).count() > 50, "too few hits to compare");
    let png = tmp("accel_grid.png");
    let mut cmd = bin();
    cmd.arg("render")
        .arg(&swc)
        .arg("-o")
        .arg(&png)
        .args(["--width", "32", "--height", "24", "--accel", "grid", "--quiet"]);
    assert!(cmd.status().unwrap().success());
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
}
