//! Scenes, one binary (each file under `tests/` would be a crate of its own to compile and
//! link): building and memory layout, the seeded generators, the automatic primitive choice,
//! spline fitting and simplification against the independent oracle, degenerate and
//! extreme-scale input.
//!
//! Sizes are fixed by each test; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod build;
mod choice_oracle;
mod choice_spline_fit;
mod empty;
mod fit_data;
mod generate;
mod layout;
mod min_radius;
mod simplify_oracle;
mod splines;
