//! Helpers shared by the command-line tests.
#![allow(dead_code)] // each test binary uses some of them

use std::process::Command;

/// The `tubecast` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tubecast"))
}

/// A path named `name` in a directory of this test process.
pub fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tubecast-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}
