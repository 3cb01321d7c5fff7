//! Discrepancy discovery (issue 5): decide whether the paper's model (M0) misses something in
//! measured pp DTE curves, name the missing effect from a library of nested candidates, add it,
//! and show the gap shrink on training and held-out loads.
//!
//! Detect: chi-square of the normalised residuals, Wald-Wolfowitz runs along frequency and
//! residual energy in Omega windows, each calibrated by a parametric bootstrap under the fitted
//! M0 and Holm-corrected. Name: score statistics rank the candidates, bootstrap-calibrated
//! likelihood ratios test them (Holm across candidates), the leading ones are refitted, nearly
//! collinear ones are reported as ambiguous, and a discrepancy that the best candidate does not
//! remove is `unexplained`.

mod ambiguity;
#[cfg(test)]
mod bootstrap_check;
mod calibration;
mod decide;
mod effects;
mod fit;
mod forward;
mod interval;
mod linearized;
mod memo;
mod noise;
#[cfg(test)]
mod power;
mod probes;
mod procedure;
mod profile;
mod refit;
mod report;
mod run;
pub mod stats;
mod study;
mod training;
mod windows;

pub use effects::{Candidate, Effect, LIBRARY};
pub use forward::{Curve, Setup};
pub use noise::{DiscoveryNoise, NoiseOrigin, TailChoice};
pub use report::{discovery_json, summary_text, write_discovery};
pub use run::{
    discover, discover_setup, split, CandidateResult, DiscoverOptions, Discovery, ExcludedPoints,
    Gap, GapSet, OtherStart, PredictionCheck, Procedure, ResidualCurve, TestResult, MAX_BOOTSTRAP,
};
pub use stats::clopper_pearson_upper95;
pub use study::{run_study, Hidden, SeedOutcome, StudyOptions, StudySummary};
pub use training::Correlation;
pub use windows::{windows, Window};
