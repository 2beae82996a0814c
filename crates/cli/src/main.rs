//! The `tubecast` command line: render, info, intersect, generate, mesh, simplify.
//!
//! One direction of imports: [`args`] (what clap reads, with [`values`] parsed and
//! range-checked) → [`options`] (the checks that need several flags or the file system, made
//! before any work) → one `cmd_*` file per command → [`setup`] (loading, accelerators,
//! threads, warnings), [`choice`], [`quantized`], [`hits_io`] and [`progress`]; [`error`] and
//! [`values`] import nothing of the crate.

mod args;
mod choice;
mod cmd_generate;
mod cmd_info;
mod cmd_intersect;
mod cmd_mesh;
mod cmd_render;
mod cmd_simplify;
mod error;
mod gpu;
mod hits_io;
mod options;
mod progress;
mod quantized;
mod setup;
mod values;

use args::{Cli, Cmd};
use clap::error::ErrorKind;
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_sigpipe();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => e.exit(),
        Err(e) => {
            // clap's own message ("error: invalid value '0' for '--ao-samples <N>': ...") under
            // the prefix every other error has; usage errors exit 2.
            eprint!("tubecast: {}", e.render());
            return ExitCode::from(2);
        }
    };
    let r = match &cli.cmd {
        Cmd::Render(a) => cmd_render::render(a),
        Cmd::Info(a) => cmd_info::info(a),
        Cmd::Intersect(a) => cmd_intersect::intersect(a),
        Cmd::Generate(a) => cmd_generate::generate(a),
        Cmd::Mesh(a) => cmd_mesh::mesh(a),
        Cmd::Simplify(a) => cmd_simplify::simplify(a),
    };
    progress::report_peak(None);
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tubecast: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// Die of SIGPIPE when a reader closes our stdout (`tubecast info --json | head -1`), as
/// command-line tools do: Rust ignores the signal, so the next write to the closed pipe would
/// fail and `println!` would panic.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread is started; setting a signal's
    // disposition to its default has no other precondition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
