//! # tubecast-oracle
//!
//! Independent `f64` oracles for the sphere sweep `⋃ B(p(u), r(u))`, used by tubecast's tests,
//! fuzz checks and reports. This crate depends on nothing of tubecast's, so it cannot share a
//! mistake with the code it judges: it has its own [`Vec3`], and callers convert their types
//! into it (a few lines each).
//!
//! * [`link`]: a link (`p`, `r` linear): exact distance and normal, the line's gap and its
//!   interval (convex in `u`: bisection and golden section).
//! * [`spline`]: a quadratic Bézier tube: dense sampling refined by golden section;
//!   [`spline_fine`]: the same for thin tubes (`L/r` to 10⁵ and beyond), radius offset.
//! * [`minimise`]: the golden-section and derivative-bisection minimisers.
//! * [`link_cases`], [`spline_cases`]: the seeded case generators of the reports, aimed at each
//!   failure region, and the error bound of the stable link they are judged by.
//! * [`rng`]: the seeded stream (`rand_xoshiro`'s SplitMix64) and its float helpers.
//!
//! ```
//! use tubecast_oracle::{line_interval, Line, Link, Vec3};
//! // A unit-radius cylinder along x, crossed perpendicularly at distance 0.6 from its axis.
//! let l = Link { a: Vec3::new(0.0, 0.0, 0.0), ra: 1.0, b: Vec3::new(4.0, 0.0, 0.0), rb: 1.0 };
//! let ray = Line { o: Vec3::new(2.0, 0.6, -5.0), d: Vec3::new(0.0, 0.0, 1.0) };
//! let hit = line_interval(&l, &ray).unwrap();
//! assert!((hit.t_in - 4.2).abs() < 1e-12 && (hit.t_out - 5.8).abs() < 1e-12);
//! ```
#![deny(missing_docs)]

pub mod link;
pub mod link_cases;
pub mod minimise;
pub mod rng;
pub mod spline;
pub mod spline_cases;
pub mod spline_fine;
pub mod spline_thin;
mod vec;

pub use link::{line_gap, line_interval, sweep_dist, sweep_normal, Crossing, Link};
pub use link_cases::{
    link_bound, link_case, link_error_bound, link_tip_term, link_truth, LinkCase, LinkRegion, LinkTruth, LINK_REGIONS,
};
pub use minimise::{convex_argmin, golden_min};
pub use spline::{quad_crossing, quad_gap, quad_hit_measure, Quad, QuadCrossing};
pub use spline_cases::{
    report_spline_case, spline_case, spline_truth, SplineCase, SplineRegion, SplineTruth, SPLINE_REGIONS,
};
pub use spline_fine::{quad_crossing_offset, quad_gap_fine};
pub use spline_thin::{thin_case, ThinCase, ThinFamily, THIN_FAMILIES};
pub use vec::{line_dist, sphere_crossing, Line, Vec3};
