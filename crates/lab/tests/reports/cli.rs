//! The `tubecast-lab` binary end to end: arguments, exit codes, files written.
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tubecast-lab"))
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tubecast-lab-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn report_writes_markdown_and_charts() {
    // The tiny seeded run: the accuracy report writes its markdown summary and SVG charts.
    let dir = tmp("report");
    let out = bin().args(["accuracy", "--quick", "--quiet", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let md: Vec<_> = std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).collect();
    assert!(md.iter().any(|p| p.extension().is_some_and(|x| x == "md")), "{md:?}");
    assert!(md.iter().any(|p| p.extension().is_some_and(|x| x == "svg")), "{md:?}");
    // A bad report name is a usage error.
    let out = bin().args(["everything"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}
