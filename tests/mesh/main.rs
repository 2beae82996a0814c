//! Certified tessellation, one binary (each file under `tests/` would be a crate of its own to
//! compile and link): single links, chains, bifurcations and spline tubes within ε of the exact
//! surface both ways, watertight, and against the manifold3d meshes of `reference/fixtures/`.
//!
//! Sizes are fixed by each test; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod common;
// The fixture reader of the `reference` binary, shared rather than copied.
#[path = "../reference/fixtures.rs"]
mod fixtures;

mod chain;
mod link;
mod reference;
