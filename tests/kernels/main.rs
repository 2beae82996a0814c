//! The kernel crate's tests of links, CSG, the `Primitive` trait, voxels, the interop
//! conversions and the committed fuzz corpora, one module per subject (the spline kernel's are
//! the `splines` binary: two binaries compile side by side). Expected values come from
//! the independent oracle (`tubecast-oracle`) or are derived by hand beside each test.
//!
//! Property runs are sized by proptest's `PROPTEST_CASES`: unset, each property runs the count
//! it names (proptest's 256), so `cargo test` stays fast; `PROPTEST_CASES=100000 cargo test
//! --release -p tubecast --test kernels` is the long run. Failing cases are kept under `tests/proptest-regressions/`, named
//! after the module file (proptest's default place for a binary rooted at `main.rs`).

mod common;
/// The spline tests' helpers (a scale measure of a quadratic tube, for the box tests).
#[path = "../splines/common/mod.rs"]
mod spline_common;

mod csg;
mod fuzz_corpus;
mod interop;
mod link;
mod primitive;
mod voxel;
