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
        (vec!["mesh", "--tolerance", "0.01", "--runs", "--splines", "-o", "x.ply"], "--splines"),
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

/// The PLY's faces: every directed edge once and its reverse once (closed, consistently
/// oriented, each edge in two faces). Returns the face count.
fn ply_is_watertight(bytes: &[u8]) -> usize {
    let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let head = String::from_utf8_lossy(&bytes[..end]).to_string();
    let count = |what: &str| -> usize {
        head.lines().find_map(|l| l.strip_prefix(&format!("element {what} "))).unwrap().trim().parse().unwrap()
    };
    let (nv, nf) = (count("vertex"), count("face"));
    let faces = &bytes[end + 12 * nv..];
    assert_eq!(faces.len(), 13 * nf, "face bytes");
    let mut edges = std::collections::HashMap::new();
    for f in faces.chunks(13) {
        assert_eq!(f[0], 3);
        let v: Vec<u32> = (0..3).map(|k| u32::from_le_bytes(f[1 + 4 * k..5 + 4 * k].try_into().unwrap())).collect();
        for k in 0..3 {
            *edges.entry((v[k], v[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge {a}-{b} used {n} times");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} has no twin");
    }
    nf
}

/// A bifurcation and a crossing branch (SWC), as the union by default: one watertight
/// surface, certified within the tolerance (the JSON's union certificate); `--shells` writes
/// the per-chain shells instead.
#[test]
fn mesh_writes_the_union_by_default_and_shells_on_request() {
    let swc = tmp("union_tree.swc");
    std::fs::write(
        &swc,
        "1 1 0 0 0 0.5 -1\n2 3 2 0 0 0.45 1\n3 3 4 1.5 0 0.35 2\n4 3 4 -1 0.8 0.4 2\n5 3 1 -2 0.2 0.25 -1\n6 3 1.2 2 -0.1 0.3 5\n",
    )
    .unwrap();
    let ply = tmp("union_tree.ply");
    let json = |args: &[&str]| -> serde_json::Value {
        let run = bin().arg("mesh").arg(&swc).args(args).args(["--json", "--force", "-o"]).arg(&ply).output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        serde_json::from_slice(&run.stdout).unwrap()
    };
    let u = json(&["--tolerance", "0.005"]);
    assert_eq!(u["surface"], "union");
    assert!(u["certified"].as_f64().unwrap() <= 0.005, "{u}");
    assert_eq!(u["union"]["over_tolerance"], 0, "{u}");
    assert_eq!(u["closed_parts"], 1, "the crossing branch meets the tree: {u}");
    assert_eq!(ply_is_watertight(&std::fs::read(&ply).unwrap()) as u64, u["triangles"].as_u64().unwrap());
    // Every radius of this tree differs from its neighbours': `--runs` leaves every link to
    // the hulls, so the same union.
    let r = json(&["--tolerance", "0.005", "--runs"]);
    assert_eq!((r["union"]["runs"].as_u64(), &r["triangles"]), (Some(0), &u["triangles"]), "{r}");
    let s = json(&["--tolerance", "0.005", "--shells"]);
    assert_eq!(s["surface"], "shells");
    assert!(s["union"].is_null());
}

/// The union's bodies: three of the generator's Bundle fibres (twelve gently bending links each,
/// one radius) are meshed as runs by default and as hulls with `--hulls` (a tree whose radii
/// change at every node gets hulls by default: above). Both are certified within the
/// tolerance.
#[test]
fn mesh_chooses_runs_for_long_streamlines_and_hulls_on_request() {
    let tck = tmp("union_runs.tck");
    let gen = ["generate", "bundle", "--count", "3", "--segments", "12", "--force", "-o"];
    assert!(bin().args(gen).arg(&tck).status().unwrap().success());
    let ply = tmp("union_runs.ply");
    let json = |args: &[&str]| -> serde_json::Value {
        let run = bin().arg("mesh").arg(&tck).args(args).args(["--json", "--force", "-o"]).arg(&ply).output().unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        serde_json::from_slice(&run.stdout).unwrap()
    };
    let auto = json(&["--tolerance", "1.2e-3", "--radius", "0.12"]);
    let hulls = json(&["--tolerance", "1.2e-3", "--radius", "0.12", "--hulls"]);
    assert!(auto["union"]["runs"].as_u64().unwrap() >= 1, "{auto}");
    assert_eq!(hulls["union"]["runs"], 0, "{hulls}");
    assert_eq!(auto["closed_parts"], hulls["closed_parts"]);
    for j in [&auto, &hulls] {
        assert!(j["certified"].as_f64().unwrap() <= 1.2e-3, "{j}");
    }
    let both = bin().arg("mesh").arg(&tck).args(["--tolerance", "1e-3", "--runs", "--hulls", "-o"]).arg(&ply).output();
    let err = String::from_utf8_lossy(&both.unwrap().stderr).to_string();
    assert!(err.contains("--hulls") && err.contains("cannot be used"), "{err}");
}

/// A union too large for `--memory-limit` is refused before it is built, naming the estimate
/// and what lowers it.
#[test]
fn mesh_refuses_a_union_above_the_memory_limit() {
    let swc = tmp("union_mem.swc");
    std::fs::write(&swc, "1 1 0 0 0 0.5 -1\n2 3 2 0 0 0.45 1\n3 3 4 1.5 0 0.35 2\n").unwrap();
    let run = bin()
        .arg("mesh")
        .arg(&swc)
        .args(["--tolerance", "1e-6", "--memory-limit", "64M", "--force", "-o"])
        .arg(tmp("union_mem.ply"))
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("GB") && err.contains("raise the tolerance") && err.contains("limit"), "{err}");
    assert!(!tmp("union_mem.ply").exists(), "nothing written");
}

/// Two cylinders (r = 0.5) whose axes are 10⁻³ closer than touching meet in a crease of
/// `sin(β/2) ≈ 0.045`, where the first build's bound is over ε = 10⁻². The refinement that
/// meets ε (about 33,000 hull triangles, 72 MB by the union's estimate) does not fit a
/// 66 MiB (69.2 MB) limit, while the first build (about 2,000, 64.5 MB) does: the mesh made
/// is still written, and the CLI warns with the bound reached (2.65·10⁻²) and with the
/// estimate that stopped the refinement. At that resolution the two polyhedra do not meet
/// (their overlap, 10⁻³, is below the sagitta, 6.6·10⁻³): two closed parts, each watertight,
/// the gap between them within the bound.
#[test]
fn mesh_warns_where_the_refinement_cannot_reach_the_tolerance() {
    let swc = tmp("union_narrow.swc");
    std::fs::write(
        &swc,
        "1 3 0 0 0 0.5 -1\n2 3 1.840369583322223 0.6809367458292225 0.3864776124976668 0.5 1\n\
         3 3 0.2231766641102757 -0.861158122771064 0.4545325776905615 0.5 -1\n\
         4 3 2.0635462474324986 -0.18022137694184148 0.8410101901882283 0.5 3\n",
    )
    .unwrap();
    let ply = tmp("union_narrow.ply");
    let run = bin()
        .arg("mesh")
        .arg(&swc)
        .args(["--tolerance", "0.01", "--memory-limit", "66M", "--force", "-o"])
        .arg(&ply)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("warning: the certified bound") && err.contains("sin(β/2)"), "{err}");
    assert!(err.contains("refinement stopped") && err.contains("72 MB") && err.contains("--memory-limit"), "{err}");
    assert!(String::from_utf8_lossy(&run.stdout).contains("2 closed parts"));
    ply_is_watertight(&std::fs::read(&ply).unwrap());
}
