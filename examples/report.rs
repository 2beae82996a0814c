//! Run the reports without the CLI:
//!
//! ```text
//! cargo run --release --example report -- accuracy|stability|speed|peers|all [--out DIR]
//!     [--seed N] [--quick] [--big] [--threads N] [--quiet]
//! ```
//!
//! `--big` extends the speed report to 10⁶ segments; `--quick` is the tiny test setting;
//! `peers` needs `--features embree`. Defaults: the settings of `docs/report/`.

use std::path::PathBuf;
use std::process::ExitCode;
use tubecast::report::{self, ReportOptions};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut which = None;
    let mut out = PathBuf::from("docs/report");
    let mut opts = ReportOptions::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| format!("{name} needs a value"));
        let r: Result<(), String> = (|| {
            match a.as_str() {
                "--out" => out = PathBuf::from(value("--out")?),
                "--seed" => opts.seed = value("--seed")?.parse().map_err(|e| format!("--seed: {e}"))?,
                "--threads" => opts.threads = value("--threads")?.parse().map_err(|e| format!("--threads: {e}"))?,
                "--quick" => opts = ReportOptions { seed: opts.seed, ..ReportOptions::quick() },
                "--big" => opts.max_segments = 1_000_000,
                "--quiet" => opts.progress = false,
                "accuracy" | "stability" | "speed" | "peers" | "all" => which = Some(a.clone()),
                other => return Err(format!("unknown argument {other:?}")),
            }
            Ok(())
        })();
        if let Err(e) = r {
            eprintln!("report: {e}");
            return ExitCode::from(2);
        }
    }
    let Some(which) = which else {
        eprintln!("usage: report accuracy|stability|speed|peers|all [--out DIR] [--seed N] [--quick] [--big] [--threads N] [--quiet]");
        return ExitCode::from(2);
    };
    let all = which == "all";
    let mut jobs: Vec<(&str, fn(&std::path::Path, &ReportOptions) -> Result<report::ReportFiles, report::ReportError>)> =
        Vec::new();
    if all || which == "accuracy" {
        jobs.push(("accuracy", report::run_accuracy));
    }
    if all || which == "stability" {
        jobs.push(("stability", report::run_stability));
    }
    if all || which == "speed" {
        jobs.push(("speed", report::run_speed));
    }
    #[cfg(feature = "embree")]
    if all || which == "peers" {
        jobs.push(("peers", report::run_peers));
    }
    #[cfg(not(feature = "embree"))]
    if which == "peers" {
        eprintln!("report: the peers report needs `--features embree`");
        return ExitCode::from(2);
    }
    for (name, job) in jobs {
        match job(&out, &opts) {
            Ok(f) => println!("{name}: wrote {} and {} chart(s)", f.markdown.display(), f.charts.len()),
            Err(e) => {
                eprintln!("report {name}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
