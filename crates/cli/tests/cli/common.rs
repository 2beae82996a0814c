//! Helpers shared by the command-line tests.

use std::process::Command;

/// The `tubecast` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tubecast"))
}

/// A path named `name` in the directory of this test process for the test module `module`.
pub fn tmp_in(module: &str, name: &str) -> std::path::PathBuf {
    let module = module.rsplit("::").next().unwrap_or(module);
    let d = std::env::temp_dir().join(format!("tubecast-cli-{}", std::process::id())).join(module);
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// `fn tmp(name) -> PathBuf` for the module that invokes it: a directory of its own, so that
/// the modules of this one test binary, running side by side, never share a file.
macro_rules! tmp_fn {
    () => {
        #[allow(dead_code)]
        fn tmp(name: &str) -> std::path::PathBuf {
            $crate::common::tmp_in(module_path!(), name)
        }
    };
}
pub(crate) use tmp_fn;
