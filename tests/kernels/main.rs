//! The kernel crate's tests, one binary (each file under `tests/` would be a crate of its own
//! to compile and link), one module per subject: links, splines, CSG, the `Primitive` trait,
//! voxels, the interop conversions and the committed fuzz corpora. Expected values come from
//! the independent oracle (`tubecast-oracle`) or are derived by hand beside each test.
//!
//! Property runs are sized by proptest's `PROPTEST_CASES`: unset, each property runs the count
//! it names (proptest's 256, or the smaller default passed to `spline::common::config`), so
//! `cargo test` stays fast; `PROPTEST_CASES=100000 cargo test --release -p tubecast --test
//! kernels` is the long run. Failing cases are kept under `tests/proptest-regressions/`, named
//! after the module file (proptest's default place for a binary rooted at `main.rs`).

mod common;

mod csg;
mod fuzz_corpus;
mod interop;
mod link;
mod primitive;
mod spline;
mod voxel;
