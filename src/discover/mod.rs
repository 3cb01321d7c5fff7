//! Discrepancy discovery (issue 5): decide whether the paper's model (M0) misses something in
//! measured pp DTE curves, name the missing effect from a library of nested candidates, add it,
//! and show the gap shrink on training and held-out loads (docs/discover-method.md).
//!
//! One likelihood, the estimation engine's (`crate::fit`): M0 and each candidate fitted to the
//! training loads under one error family (scale, tails, correlation along speed), each
//! candidate's likelihood ratio calibrated by a parametric bootstrap from the fitted M0 and its
//! fitted errors, Holm's correction over the candidates, a name only if it also predicts the
//! held-out loads better than M0, its size with a profile-likelihood interval.

mod calibration;
mod compare;
mod effects;
mod forward;
mod memo;
mod noise;
mod procedure;
mod result;
mod start;
mod stats;
mod training;
mod windows;

pub use compare::split;
pub use effects::{Candidate, Effect, LIBRARY};
pub use forward::{Curve, Setup, MIN_ZETA};
pub use noise::{DiscoveryNoise, NoiseOrigin, TailChoice};
pub use procedure::{discover, discover_setup};
pub use result::{
    check_options, least_bootstrap, CandidateResult, DiscoverOptions, Discovery, ExcludedPoints,
    Gap, GapSet, PowerBound, PredictionCheck, ResidualCurve, TestResult, MAX_BOOTSTRAP,
};
pub use training::Correlation;
pub use windows::{windows, Window, HALF_WIDTH as WINDOW_HALF_WIDTH};
