//! A branch of period-nu orbits (nu > 1) for the multi-harmonic balance, seeded by simulation.
//!
//! The linear start (eq. 13) is a period-1 orbit, which is also a solution of the period-nu
//! ansatz (its harmonics of Omega / nu that are not multiples of nu are zero): continued from
//! there, the branch stays period-1 whatever nu is, and a period-nu orbit is reached only where
//! the period-1 branch period-doubles and the continuation happens to turn onto the other
//! branch. So a period-nu branch starts from a period-nu attractor that the exact simulation
//! reaches from a grid of initial conditions (the first frequency of the grid where one is
//! found), whose Fourier coefficients ([`super::guess_from_state`]) Newton polishes; it is then
//! continued down and up to the ends of the range.

use super::aft::AftOptions;
use super::aft_guess::guess_from_state;
use super::aft_point::HbPoint;
use super::aft_solve::solve_at;
use super::continuation::{continue_from, ContinuationOptions};
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::progress::{NoProgress, Progress};
use crate::sim::{find_attractors, ExactFlow, IcGrid, Motion, SteadyOptions};

/// A period-nu branch and where it was seeded.
pub struct SeededBranch {
    /// The frequency of the simulated period-nu attractor the branch starts from.
    pub seed_omega: f64,
    /// The branch by continuation order, from its end towards `omegas`' first to its end
    /// towards the last.
    pub points: Vec<HbPoint>,
}

/// The period-`opts.subharmonic` branch over the frequencies `omegas` (increasing), seeded at
/// the first of them where a period-nu attractor is reached from `grid` (see the module's
/// notes). An error names the range searched when no frequency has one.
pub fn subharmonic_branch(
    model: &GearPair,
    omegas: &[f64],
    grid: &IcGrid,
    opts: &AftOptions,
    cont: &ContinuationOptions,
    progress: &dyn Progress,
) -> Result<SeededBranch> {
    let nu = opts.subharmonic;
    let (Some(&first), Some(&last)) = (omegas.first(), omegas.last()) else {
        return Err(GearError::param("omega", 0.0, "no frequency to search"));
    };
    progress.start(
        omegas.len() as u64,
        "frequencies searched for a period-ν orbit",
    );
    let mut seed = None;
    for &omega in omegas {
        let m = model.at_omega(omega)?;
        let map = find_attractors(
            &ExactFlow::new(&m)?,
            grid,
            &SteadyOptions::default(),
            &NoProgress,
        )?;
        progress.advance(1);
        let found = map
            .attractors
            .iter()
            .find(|a| a.steady.motion == Motion::Periodic && a.steady.period == Some(nu));
        if let Some(x0) = found.and_then(|a| a.steady.poincare.first().copied()) {
            seed = Some((m, x0));
            break;
        }
    }
    progress.finish();
    let Some((m, x0)) = seed else {
        return Err(GearError::Unsupported(format!(
            "no period-{nu} attractor is reached by simulation from the grid of initial \
             conditions at any frequency in {first} .. {last}: a period-{nu} branch starts from \
             one (a wider --ic-grid or another range may find it)"
        )));
    };
    let start = solve_at(&m, &guess_from_state(&m, x0, opts)?, opts)?;
    let down = continue_from(model, &start, first, opts, cont, &NoProgress)?;
    let up = continue_from(model, &start, last, opts, cont, &NoProgress)?;
    // Each continuation begins at the seed: it is kept once.
    let mut points: Vec<HbPoint> = down.into_iter().rev().collect();
    points.extend(up.into_iter().skip(1));
    Ok(SeededBranch {
        seed_omega: m.omega,
        points,
    })
}
