//! `render --ao cone|rays|off` with `--ao-samples N`: each writes an image, the older
//! `--ao N` is `--ao rays --ao-samples N` byte for byte, and a bad value is refused by name.

use crate::common::bin;
crate::common::tmp_fn!();

#[test]
fn ao_methods_render_and_bad_values_are_refused() {
    let swc = tmp("ao_helix.swc");
    assert!(bin().args(["generate", "helix", "--segments", "30", "-o"]).arg(&swc).status().unwrap().success());
    let run = |name: &str, ao: &[&str]| {
        let png = tmp(&format!("ao_{name}.png"));
        let mut cmd = bin();
        cmd.arg("render").arg(&swc).arg("-o").arg(&png).args(["--width", "32", "--height", "24", "--quiet"]);
        assert!(cmd.arg("--force").args(ao).status().unwrap().success(), "{ao:?} failed");
        std::fs::read(&png).unwrap()
    };
    let off = run("off", &["--ao", "off"]);
    let cone = run("cone", &["--ao", "cone", "--ao-samples", "8"]);
    let rays = run("rays", &["--ao", "rays", "--ao-samples", "4"]);
    assert_eq!(run("legacy", &["--ao", "4"]), rays, "--ao 4 differs from --ao rays --ao-samples 4");
    assert_ne!(cone, off, "cone AO changed nothing");
    assert_ne!(rays, off, "ray AO changed nothing");
    let out = bin().arg("render").arg(&swc).arg("-o").arg(tmp("ao_bad.png")).args(["--ao", "foo"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cone, rays, off"));
}
