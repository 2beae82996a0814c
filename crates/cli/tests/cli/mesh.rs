//! `tubecast mesh` and `render --model mesh` end to end, and their errors.

use crate::common::bin;
crate::common::tmp_fn!();

#[test]
fn mesh_exports_and_mesh_render() {
    let tck = tmp("mesh_helix.tck");
    assert!(bin().args(["generate", "helix", "--segments", "40", "-o"]).arg(&tck).status().unwrap().success());
    for ext in ["ply", "obj", "glb"] {
        let out = tmp(&format!("mesh.{ext}"));
        let run = bin().arg("mesh").arg(&tck).args(["--tolerance", "0.01", "-o"]).arg(&out).output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let said = String::from_utf8_lossy(&run.stdout).to_string();
        let bytes = std::fs::read(&out).unwrap();
        let tris: usize = said.split(" triangles").next().unwrap().rsplit(' ').next().unwrap().parse().unwrap();
        match ext {
            "ply" => assert!(String::from_utf8_lossy(&bytes[..300]).contains(&format!("element face {tris}\n"))),
            "obj" => assert_eq!(String::from_utf8_lossy(&bytes).lines().filter(|l| l.starts_with("f ")).count(), tris),
            _ => assert_eq!(&bytes[..4], b"glTF"),
        }
    }
    let png = tmp("mesh.png");
    let run = bin()
        .arg("render")
        .arg(&tck)
        .args(["--model", "mesh", "--tolerance", "0.01", "--width", "64", "--height", "48", "--quiet", "-o"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
}

#[test]
fn mesh_errors_exit_nonzero_with_a_message() {
    let tck = tmp("mesh_err.tck");
    assert!(bin().args(["generate", "helix", "--segments", "10", "-o"]).arg(&tck).status().unwrap().success());
    for (args, says) in [
        (vec!["mesh", "--tolerance", "0", "-o", "x.ply"], "tolerance"),
        (vec!["mesh", "--tolerance", "0.01", "-o", "x.stl"], ".ply, .obj or .glb"),
        (vec!["render", "--model", "mesh", "-o", "x.png"], "--tolerance"),
    ] {
        let out = bin().arg(args[0]).arg(&tck).args(&args[1..]).current_dir(std::env::temp_dir()).output().unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("tubecast: error:") && err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn simplify_keeps_the_format_and_the_bound() {
    let trk = tmp("simp.trk");
    assert!(bin().args(["generate", "bundle", "--count", "5", "-o"]).arg(&trk).status().unwrap().success());
    let out = tmp("simp_out.trk");
    let run = bin().arg("simplify").arg(&trk).args(["--tolerance", "0.01", "-o"]).arg(&out).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let said = String::from_utf8_lossy(&run.stdout).to_string();
    let (kept, total): (usize, usize) = {
        let w: Vec<&str> = said.split_whitespace().collect();
        (w[1].parse().unwrap(), w[3].parse().unwrap())
    };
    assert!(kept < total, "{said}");
    let info = bin().arg("info").arg(&out).output().unwrap();
    assert!(String::from_utf8_lossy(&info.stdout).contains(&format!("nodes      {kept}")));
    let bad = bin().arg("simplify").arg(&trk).args(["--tolerance", "0.01", "-o"]).arg(tmp("x.tck")).output().unwrap();
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("extension"));
}

#[test]
fn info_reports_the_automatic_choice() {
    let trk = tmp("choice.trk");
    assert!(bin().args(["generate", "bundle", "--count", "5", "-o"]).arg(&trk).status().unwrap().success());
    for args in [["--tolerance", "0.01"], ["--pixel-error", "0.5"]] {
        let out = bin().arg("info").arg(&trk).args(args).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let line = text.lines().find(|l| l.starts_with("choice")).expect("a choice line");
        let worst: f64 = line.rsplit(' ').next().unwrap().parse().unwrap();
        assert!(worst >= 0.0 && (args[0] != "--tolerance" || worst <= 0.01), "{line}");
    }
    let png = tmp("choice.png");
    let run = bin()
        .arg("render")
        .arg(&trk)
        .args(["--tolerance", "0.01", "--width", "32", "--height", "24", "--quiet", "-o"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
}
