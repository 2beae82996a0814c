//! # tubecast-oracle
//!
//! Independent `f64` oracles for the sphere sweep `⋃ B(p(u), r(u))`, used by tubecast's tests,
//! fuzz checks and reports. This crate depends on nothing of tubecast's, so it cannot share a
//! mistake with the code it judges.
#![deny(missing_docs)]
