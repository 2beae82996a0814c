//! The memory estimate refuses a scene before loading it (the refused run's peak resident set
//! stays a fraction of a run that loads it), `--max-streamlines` / `--subsample` on the
//! command line, and progress bars only where asked for (never in a piped stderr).

use crate::common::bin;
crate::common::tmp_fn!();
use std::path::Path;
use std::process::Output;

/// `tubecast generate bundle` of `count` fibres of 100 links as `.tck`.
fn bundle(name: &str, count: usize) -> std::path::PathBuf {
    let p = tmp(name);
    let out = bin()
        .args(["generate", "bundle", "--segments", "100", "--count", &count.to_string(), "-o"])
        .arg(&p)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    p
}

fn info(input: &Path, extra: &[&str]) -> Output {
    bin().arg("info").arg(input).args(extra).env("TUBECAST_PEAK_RSS", "1").output().unwrap()
}

/// The peak resident set in kB the binary reports on stderr.
fn peak_kb(out: &Output) -> u64 {
    let err = String::from_utf8_lossy(&out.stderr);
    // The last line, at exit (the others are "… set after PHASE: N kB").
    let mut at_exit =
        err.lines().filter_map(|l| l.strip_prefix("tubecast: peak resident set ")).filter(|l| !l.starts_with("after"));
    let line = at_exit.next_back().expect("peak line");
    line.trim_end_matches("kB").trim().parse().unwrap()
}

#[test]
fn refused_before_anything_large_is_allocated() {
    let p = bundle("big.tck", 5000); // 5·10⁵ links
    let out = info(&p, &["--memory-limit", "40M"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    for part in ["needs about", "500000 links", "40M", "--subsample", "--max-streamlines", "--memory-limit", "GiB"] {
        let part = if part == "40M" { "0.04 GiB available (--memory-limit)" } else { part };
        assert!(err.contains(part), "{part:?} missing in {err}");
    }
    // Loading it for real (a limit it fits in) holds the scene, primitives and tree of 5·10⁵
    // links, more than 100 B each (Scene::memory_bytes alone is 48 B per link): ≥ 50 MB. The
    // refusal read the header and a sample of 200 streamlines (2·10⁴ links): it must stay
    // under a quarter of that.
    let ok = info(&p, &["--memory-limit", "100G"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let (refused, loaded) = (peak_kb(&out), peak_kb(&ok));
    assert!(loaded > 50_000, "the full load peaked at {loaded} kB only");
    assert!(refused * 4 < loaded, "refused at {refused} kB, loaded at {loaded} kB");
    // The way out the message names works: a subsample within the limit.
    let part = info(&p, &["--memory-limit", "40M", "--subsample", "0.05"]);
    assert!(part.status.success(), "{}", String::from_utf8_lossy(&part.stderr));
}

#[test]
fn selection_on_the_command_line() {
    let p = bundle("sel.tck", 300);
    let links = |extra: &[&str]| -> u64 {
        let out = info(&p, &[&["--json"], extra].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        j["links"].as_u64().unwrap()
    };
    assert_eq!(links(&[]), 300 * 100);
    assert_eq!(links(&["--max-streamlines", "7"]), 700);
    // About half: 150 ± 5σ fibres, σ = √(300·¼) ≈ 8.7.
    let half = links(&["--subsample", "0.5"]);
    assert!((10_700..=19_300).contains(&half) && half % 100 == 0, "{half}");
    assert_eq!(links(&["--subsample", "0.5"]), half, "deterministic");
    assert_eq!(links(&["--subsample", "0.5", "--max-streamlines", "3"]), 300);
    for (bad, what) in [("0", "(0, 1]"), ("1.5", "(0, 1]")] {
        let out = info(&p, &["--subsample", bad]);
        assert!(!out.status.success());
        assert!(String::from_utf8_lossy(&out.stderr).contains(what));
    }
    let swc = tmp("tree.swc");
    std::fs::write(&swc, "1 1 0 0 0 1 -1\n2 3 1 0 0 1 1\n").unwrap();
    let out = info(&swc, &["--max-streamlines", "1"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("SWC file is one tree"));
}

#[test]
fn progress_only_when_asked_where_stderr_is_no_terminal() {
    let p = bundle("bar.tck", 50);
    let quiet = info(&p, &[]);
    assert!(quiet.status.success());
    assert!(!String::from_utf8_lossy(&quiet.stderr).contains("loading"), "a bar in a piped stderr");
    let forced = info(&p, &["--progress"]);
    assert!(forced.status.success());
    assert!(String::from_utf8_lossy(&forced.stderr).contains("loading"), "no bar with --progress");
    let off = info(&p, &["--progress", "--quiet"]);
    assert!(!String::from_utf8_lossy(&off.stderr).contains("loading"), "a bar with --quiet");
}
