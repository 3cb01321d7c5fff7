//! The paper's parametric and excitation studies (Secs 6 and 8), each computed from the model,
//! never tabulated: [`run_study`] returns the figures (every panel captioned with its
//! parameters), one CSV row per computed point and a JSON summary; [`write_outputs`] writes them.
//!
//! | study | paper | method |
//! |---|---|---|
//! | `parametric-load` | Figs 15, 16 | df-exact, F_m 0.1, zeta 0.05, F_hat 10, 2, 1, 0.5 |
//! | `parametric-mean` | Fig. 17 | df-exact, F_ah 0.05, zeta 0.05, F_hat 10, 4, 2, 1 |
//! | `damping` | Fig. 18 | df-exact, F_m 0.1, F_hat 2, zeta 0.025 ... 0.1 |
//! | `excitation` | Figs 24, 25 | AFT (H = 15) for eq. 5 and eq. 4, plus df-exact for eq. 5 |
//! | `superposition` | Figs 26, 27 | simulation sweeps, three STE harmonics (eq. 20) |
//! | `superposition-hb` | Fig. 28 | df-exact per harmonic, superposed with phases; AFT simultaneous |
//! | `combined` | Fig. 29 | AFT, torque at Omega_T and STE at Omega_h = 2 Omega_T |
//!
//! [`escape_study`] (not one of the paper's: issue 23) follows Fig. 4's chaos for 40,000 periods
//! with both integrators; `geardyn escape` runs it.

mod combined;
mod escape;
mod excitation;
pub mod figures;
mod output;
mod parametric;
mod superposition;
mod superposition_hb;

pub use escape::{escape_study, write_escape_study, EscapeStudy, EscapeStudyOptions};
pub use figures::Figure;
pub use output::{write_outputs, StudyOutput, StudyRow};

use crate::error::{GearError, Result};
use crate::hb::HbPoint;

/// A continued AFT branch and its solutions on the study's frequency grid.
pub(crate) type Traced = (Vec<HbPoint>, Vec<Vec<HbPoint>>);

/// The studies of [`run_study`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyName {
    /// Figs 15, 16: force ratio F_hat varied through F_ah at F_m 0.1.
    ParametricLoad,
    /// Fig. 17: F_hat varied through F_m at F_ah 0.05.
    ParametricMean,
    /// Fig. 18: damping ratio varied.
    Damping,
    /// Figs 24, 25: internal STE (eq. 5) versus external torque (eq. 4) excitation.
    Excitation,
    /// Figs 26, 27: three STE harmonics simultaneously versus their superposition.
    Superposition,
    /// Fig. 28: superposition of the describing-function solutions of three STE harmonics.
    SuperpositionHb,
    /// Fig. 29: torque and STE excitation combined, Omega_h = 2 Omega_T.
    Combined,
}

impl StudyName {
    /// Every study.
    pub const ALL: [StudyName; 7] = [
        StudyName::ParametricLoad,
        StudyName::ParametricMean,
        StudyName::Damping,
        StudyName::Excitation,
        StudyName::Superposition,
        StudyName::SuperpositionHb,
        StudyName::Combined,
    ];

    /// Command-line and file name.
    pub fn name(self) -> &'static str {
        match self {
            StudyName::ParametricLoad => "parametric-load",
            StudyName::ParametricMean => "parametric-mean",
            StudyName::Damping => "damping",
            StudyName::Excitation => "excitation",
            StudyName::Superposition => "superposition",
            StudyName::SuperpositionHb => "superposition-hb",
            StudyName::Combined => "combined",
        }
    }

    /// Default number of frequencies of the study's Omega grid.
    pub fn default_points(self) -> usize {
        match self {
            StudyName::ParametricLoad | StudyName::ParametricMean | StudyName::Damping => 281,
            StudyName::Excitation | StudyName::Combined => 141,
            StudyName::Superposition => 141,
            StudyName::SuperpositionHb => 281,
        }
    }
}

/// Options common to the studies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyOptions {
    /// Frequencies of the Omega grid (>= 2); `None` for the study's default.
    pub points: Option<usize>,
}

/// Largest frequency grid of a study (`--points`): the simulation studies take about 1 s per
/// frequency.
pub const MAX_POINTS: usize = 2001;

/// `n` equally spaced frequencies from `lo` to `hi` inclusive.
pub(crate) fn grid(lo: f64, hi: f64, n: usize) -> Result<Vec<f64>> {
    if !(2..=MAX_POINTS).contains(&n) {
        return Err(GearError::param(
            "points",
            n as f64,
            "the frequency grid needs between 2 and 2001 points",
        ));
    }
    Ok((0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect())
}

/// Compute one study.
pub fn run_study(name: StudyName, opts: &StudyOptions) -> Result<StudyOutput> {
    let n = opts.points.unwrap_or(name.default_points());
    // Checked before any study starts (some build several grids, the first after a long run).
    grid(0.0, 1.0, n)?;
    match name {
        StudyName::ParametricLoad => parametric::load(n),
        StudyName::ParametricMean => parametric::mean(n),
        StudyName::Damping => parametric::damping(n),
        StudyName::Excitation => excitation::run(n),
        StudyName::Superposition => superposition::run(n),
        StudyName::SuperpositionHb => superposition_hb::run(n),
        StudyName::Combined => combined::run(n),
    }
}
