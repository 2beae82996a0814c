//! Empty: Han et al.'s tangent cone and unit-cone transform are a baseline, not a kernel to
//! call, and live in [`crate::baseline::cone`]. `kernel/mod.rs` still declares this module;
//! it goes with that line.
