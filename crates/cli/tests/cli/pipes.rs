//! Pipes behave: a reader that closes `tubecast`'s stdout early (`info --json | head -1`,
//! `intersect … -o - | head`) ends the process quietly, with status 0 or the conventional
//! SIGPIPE death, never a panic.

use crate::common::bin;
use std::io::Read;
use std::os::unix::process::ExitStatusExt;
use std::process::{Command, Stdio};
use tubecast_render::io::npy::{write, Array2};
crate::common::tmp_fn!();

/// SIGPIPE's number on Linux and the BSDs (POSIX leaves it to the system; these agree).
const SIGPIPE: i32 = 13;

/// Run `cmd` with its stdout a pipe whose reading end is closed after reading `keep` bytes
/// (0: closed before the process writes anything); its status and stderr.
fn closed_early(cmd: &mut Command, keep: usize) -> (std::process::ExitStatus, String) {
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut out = child.stdout.take().unwrap();
    if keep > 0 {
        let mut buf = vec![0; keep];
        out.read_exact(&mut buf).unwrap();
    }
    drop(out);
    let done = child.wait_with_output().unwrap();
    (done.status, String::from_utf8_lossy(&done.stderr).into_owned())
}

fn quiet_end(what: &str, (status, err): (std::process::ExitStatus, String)) {
    assert!(status.success() || status.signal() == Some(SIGPIPE), "{what}: {status:?}, {err}");
    assert!(!err.contains("panicked"), "{what}: {err}");
}

#[test]
fn a_closed_stdout_ends_the_process_without_a_panic() {
    let swc = tmp("pipe.swc");
    assert!(bin().args(["generate", "helix", "--segments", "40", "-o"]).arg(&swc).status().unwrap().success());
    // 20,000 rays up +z through the helix's footprint: CSV rows of ~60 bytes, far more than a
    // pipe buffers (64 KiB on Linux), so the writes go on after the reader has gone.
    let n = 20_000;
    let data: Vec<f64> = (0..n).flat_map(|i| [(i % 200) as f64 * 0.05 - 5.0, 0.0, -20.0, 0.0, 0.0, 1.0]).collect();
    let rays = tmp("pipe-rays.npy");
    std::fs::write(&rays, write(&Array2 { rows: n, cols: 6, data })).unwrap();
    for keep in [0, 100] {
        let mut info = bin();
        info.args(["info", "--json"]).arg(&swc);
        quiet_end("info --json", closed_early(&mut info, keep.min(1)));
        let mut hits = bin();
        hits.arg("intersect").arg(&swc).arg("--rays").arg(&rays).args(["--csv", "-o", "-"]);
        quiet_end("intersect -o -", closed_early(&mut hits, keep));
        let mut text = bin();
        text.arg("info").arg(&swc);
        quiet_end("info", closed_early(&mut text, keep.min(1)));
    }
}
