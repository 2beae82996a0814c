//! The kernels against external ground truth, one binary (each file under `tests/` would be a
//! crate of its own to compile and link): manifold3d + libigl fixtures of `reference/fixtures/`
//! for links and a spline tube. `cargo test` needs no Python.
//!
//! Sizes are fixed by the fixtures; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod fixtures;

mod links;
mod spline;
