//! The clock of the voxel reports: process CPU time, robust to a shared machine.

use std::time::Instant;

/// Process CPU time where Linux exposes it (the sum over the process's threads of the first
/// field of `/proc/self/task/*/schedstat`, nanoseconds on the CPU), else wall time. On a shared
/// machine the CPU time of a one-thread run is what the work costs; wall time also counts the
/// time other processes held the cores.
#[derive(Clone, Copy)]
pub(super) struct Clock {
    cpu_ns: Option<u64>,
    wall: Instant,
}

impl Clock {
    pub(super) fn now() -> Self {
        Self { cpu_ns: cpu_ns(), wall: Instant::now() }
    }
    /// Seconds from `earlier` to `self`.
    pub(super) fn since(&self, earlier: Self) -> f64 {
        match (self.cpu_ns, earlier.cpu_ns) {
            (Some(a), Some(b)) if a >= b => (a - b) as f64 * 1e-9,
            _ => (self.wall - earlier.wall).as_secs_f64(),
        }
    }
}

fn cpu_ns() -> Option<u64> {
    let mut sum = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let text = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        sum += text.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(sum)
}
