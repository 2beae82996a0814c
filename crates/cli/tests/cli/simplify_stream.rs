//! `simplify` streams: its output equals, byte for byte, what the command wrote before it
//! streamed (files in `tests/data/simplify/`, written by main at 09f0319 with the same
//! arguments: `*.simplified.*` and the printed `*.stdout`); a truncated or malformed input is
//! an error that leaves no output behind; the output may be the input itself (with --force).

use crate::common::bin;
crate::common::tmp_fn!();
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/simplify").join(name)
}

fn repo(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(name)
}

#[test]
fn the_output_is_what_it_was_before_streaming() {
    let cases = [
        (repo("reference/readers/nibabel/standard.trk"), "0.5", "standard.simplified.trk"),
        (repo("reference/readers/nibabel/complex_big_endian.trk"), "0.5", "complex_big_endian.simplified.trk"),
        (repo("reference/readers/nibabel/standard.tck"), "0.5", "standard.simplified.tck"),
        (data("helix.obj"), "0.05", "helix.simplified.obj"),
        (data("bundle.obj"), "0.01", "bundle.simplified.obj"),
        (repo("fuzz/corpus/swc/tree.swc"), "0.5", "tree.simplified.swc"),
    ];
    for (input, tol, expected) in cases {
        let out = tmp(&format!("stream_{expected}"));
        let run = bin().arg("simplify").arg(&input).args(["--tolerance", tol, "-o"]).arg(&out).output().unwrap();
        assert!(run.status.success(), "{expected}: {}", String::from_utf8_lossy(&run.stderr));
        assert!(std::fs::read(&out).unwrap() == std::fs::read(data(expected)).unwrap(), "{expected} differs");
        let said = String::from_utf8_lossy(&run.stdout).replace(&out.display().to_string(), "OUT");
        let want = std::fs::read_to_string(data(&format!("{expected}.stdout"))).unwrap();
        assert_eq!(said, want, "{expected}");
    }
}

#[test]
fn a_truncated_or_malformed_input_leaves_no_output() {
    let full = std::fs::read(repo("reference/readers/nibabel/standard.trk")).unwrap();
    let tck = std::fs::read(repo("reference/readers/nibabel/standard.tck")).unwrap();
    let obj = std::fs::read(data("bundle.obj")).unwrap();
    // standard.trk cut at byte 3000, inside its streamlines (header: 1000 bytes); the
    // standard.tck without its Inf end marker (12 bytes); an OBJ whose 40th line is
    // cut after "v" (no coordinates).
    let cut_obj: Vec<u8> = {
        let text = String::from_utf8(obj).unwrap();
        let mut lines: Vec<&str> = text.lines().collect();
        lines[39] = "v";
        lines.join("\n").into_bytes()
    };
    let cases: [(&str, Vec<u8>, &str); 3] = [
        ("cut.trk", full[..3000].to_vec(), "truncated"),
        ("cut.tck", tck[..tck.len() - 12].to_vec(), "Inf end marker"),
        ("cut.obj", cut_obj, "line 40"),
    ];
    for (name, bytes, says) in cases {
        let input = tmp(name);
        std::fs::write(&input, bytes).unwrap();
        let out = tmp(&format!("out_{name}"));
        let _ = std::fs::remove_file(&out);
        let run = bin().arg("simplify").arg(&input).args(["--tolerance", "0.5", "-o"]).arg(&out).output().unwrap();
        assert!(!run.status.success(), "{name}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains("tubecast: error:") && err.contains(says), "{name}: {err}");
        assert!(!out.exists(), "{name}: no output");
        assert!(!PathBuf::from(format!("{}.partial", out.display())).exists(), "{name}: no partial output");
    }
}

#[test]
fn the_output_may_be_the_input() {
    let p = tmp("in_place.tck");
    std::fs::copy(repo("reference/readers/nibabel/standard.tck"), &p).unwrap();
    // Overwriting the input is overwriting a file: refused without --force, the input intact.
    let run = bin().arg("simplify").arg(&p).args(["--tolerance", "0.5", "-o"]).arg(&p).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("--force"));
    assert!(std::fs::read(&p).unwrap() == std::fs::read(repo("reference/readers/nibabel/standard.tck")).unwrap());
    let run = bin().arg("simplify").arg(&p).args(["--tolerance", "0.5", "--force", "-o"]).arg(&p).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(std::fs::read(&p).unwrap() == std::fs::read(data("standard.simplified.tck")).unwrap());
}
