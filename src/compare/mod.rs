//! Harmonic balance against digital simulation for the same parameters (Sec. 5, Figs 11-13):
//! the paper's describing-function solution (df-exact, eq. 8-10), the multi-harmonic balance
//! (AFT) branch with Floquet stability, and simulation sweeps (carried up, carried down, every
//! attractor from a grid of initial conditions). [`gaps`] reports where one method finds a
//! steady state the other misses.

mod figure;
mod matching;
mod run;

#[cfg(test)]
mod tests;

pub use figure::compare_panels;
pub use matching::{gaps, Gap, Gaps, Match};
pub use run::{compare, CompareSettings, Comparison};

use crate::model::Impact;
use crate::sim::Motion;
use serde::Serialize;

/// Which method produced a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Source {
    /// Describing-function solution with the exact g, h (eq. 8, 10).
    DfExact,
    /// A point of the AFT pseudo-arclength continuation branch (in branch order).
    Aft,
    /// The AFT branch solved again at each frequency of the grid (used for matching).
    AftGrid,
    /// Simulation, carried sweep of increasing Omega.
    SweepUp,
    /// Simulation, carried sweep of decreasing Omega.
    SweepDown,
    /// Simulation, every attractor reached from the grid of initial conditions.
    Attractors,
}

impl Source {
    /// Name used in CSV and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Source::DfExact => "df-exact",
            Source::Aft => "aft",
            Source::AftGrid => "aft-grid",
            Source::SweepUp => "sweep-up",
            Source::SweepDown => "sweep-down",
            Source::Attractors => "attractors",
        }
    }

    /// True for the digital-simulation sources.
    pub fn is_simulation(self) -> bool {
        matches!(
            self,
            Source::SweepUp | Source::SweepDown | Source::Attractors
        )
    }
}

/// One steady state of any method at one frequency.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ComparePoint {
    /// Method.
    pub source: Source,
    /// Excitation frequency Omega_h.
    pub omega: f64,
    /// Half range of q.
    pub qa: f64,
    /// Mid range of q.
    pub qm: f64,
    /// Impact regime (Fig. 9).
    pub case: Impact,
    /// Stability when known (simulation attractors are stable by construction).
    pub stable: Option<bool>,
    /// Period in forcing periods (1 for harmonic balance; `None` for non-periodic motion).
    pub period: Option<u32>,
    /// Kind of simulated motion (`None` for harmonic balance).
    pub motion: Option<Motion>,
    /// Share of the initial-condition grid reaching the attractor (`Attractors` only).
    pub basin_fraction: Option<f64>,
}

impl ComparePoint {
    /// A period-1 harmonic-balance point.
    pub fn hb(source: Source, omega: f64, qa: f64, qm: f64, stable: Option<bool>) -> Self {
        ComparePoint {
            source,
            omega,
            qa,
            qm,
            case: Impact::from_range(qm - qa),
            stable,
            period: Some(1),
            motion: None,
            basin_fraction: None,
        }
    }
}
