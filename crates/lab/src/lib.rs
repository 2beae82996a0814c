//! # tubecast-lab
//!
//! The reports that chart tubecast's kernels against each other and against peers: accuracy
//! against cost, stability per failure region, speed and scaling ([`report`]), and the Embree 3
//! peer (`peer`, feature `embree`). Not published; run it through the `tubecast-lab` binary
//! (`cargo run --release -p tubecast-lab -- accuracy`).
#![deny(missing_docs)]

#[cfg(feature = "embree")]
pub mod peer;
pub mod report;
