//! Progress bars on stderr for load, build and render: shown when stderr is a terminal (never
//! in logs, pipes or tests) or with `--progress`, never with `--quiet`.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Whether this process shows progress (set once from the command's options).
static ON: AtomicBool = AtomicBool::new(false);
/// Whether it was forced (`--progress`): drawn even where stderr is no terminal.
static FORCED: AtomicBool = AtomicBool::new(false);

/// Decide from `--progress` and `--quiet` (and whether stderr is a terminal).
pub fn configure(force: bool, quiet: bool) {
    ON.store(!quiet && (force || std::io::stderr().is_terminal()), Ordering::Relaxed);
    FORCED.store(!quiet && force, Ordering::Relaxed);
}

/// Whether progress is shown.
pub fn enabled() -> bool {
    ON.load(Ordering::Relaxed)
}

fn target() -> ProgressDrawTarget {
    match (enabled(), FORCED.load(Ordering::Relaxed)) {
        (false, _) => ProgressDrawTarget::hidden(),
        (true, true) => ProgressDrawTarget::term_like(Box::new(console::Term::stderr())),
        (true, false) => ProgressDrawTarget::stderr(),
    }
}

/// A bar of `len` bytes for reading `what`.
pub fn bytes(len: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(len), target());
    if let Ok(st) = ProgressStyle::with_template("{msg} [{bar:40}] {bytes}/{total_bytes} {elapsed}") {
        bar.set_style(st.progress_chars("=> "));
    }
    bar.set_message(what.to_string());
    bar
}

/// Run `f` under a spinner saying `what` (a step that reports no progress of its own).
pub fn step<R>(what: &str, f: impl FnOnce() -> R) -> R {
    let bar = ProgressBar::with_draw_target(None, target());
    if let Ok(st) = ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
        bar.set_style(st);
    }
    bar.set_message(what.to_string());
    if enabled() {
        bar.enable_steady_tick(Duration::from_millis(120));
    }
    let r = f();
    bar.finish_and_clear();
    report_peak(Some(what));
    r
}

/// With the environment variable `TUBECAST_PEAK_RSS` set, print the process's peak resident
/// set so far (`VmHWM` of `/proc/self/status`, Linux) on stderr as `tubecast: peak resident set
/// N kB` at exit, and `tubecast: peak resident set after PHASE: N kB` after loading and
/// building: how the memory estimate and the streaming readers are checked.
pub fn report_peak(phase: Option<&str>) {
    if std::env::var_os("TUBECAST_PEAK_RSS").is_none() {
        return;
    }
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    if let Some(kb) = status.lines().find_map(|l| l.strip_prefix("VmHWM:")) {
        match phase {
            Some(p) => eprintln!("tubecast: peak resident set after {p}: {}", kb.trim()),
            None => eprintln!("tubecast: peak resident set {}", kb.trim()),
        }
    }
}
