//! Multi-harmonic balance solutions of a continued branch at prescribed frequencies: every
//! segment of the branch that straddles a frequency gives a guess (linear interpolation of the
//! coefficients), polished by Newton at exactly that frequency. Used to compare the AFT branch
//! with simulation sweeps on the same frequency grid (Figs 11-13) and to superpose responses
//! (Figs 27-29).

use super::aft::AftOptions;
use super::aft_guess::guess_from_state;
use super::aft_point::HbPoint;
use super::aft_solve::solve_at;
use super::continuation::{continue_branch, continue_from, ContinuationOptions};
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::progress::NoProgress;
use crate::sim::{steady_state, ExactFlow, SteadyOptions};

/// Every solution of `branch` (a pseudo-arclength continuation of `model` computed with `opts`)
/// at each frequency of `omegas`: one list per frequency, duplicates (q_a and q_m within 1e-7)
/// removed. Segments whose Newton polish does not converge are skipped, so a list may be empty
/// where the branch does not reach the frequency.
pub fn branch_at(
    model: &GearPair,
    branch: &[HbPoint],
    omegas: &[f64],
    opts: &AftOptions,
) -> Vec<Vec<HbPoint>> {
    omegas
        .iter()
        .map(|&w| {
            let mut out: Vec<HbPoint> = Vec::new();
            let Ok(m) = model.at_omega(w) else {
                return out;
            };
            for seg in branch.windows(2) {
                let (p, q) = (&seg[0], &seg[1]);
                let (lo, hi) = (p.omega.min(q.omega), p.omega.max(q.omega));
                if !(lo <= w && w <= hi) || p.coeffs.len() != q.coeffs.len() {
                    continue;
                }
                let t = if hi > lo {
                    (w - p.omega) / (q.omega - p.omega)
                } else {
                    0.0
                };
                let guess: Vec<f64> = p
                    .coeffs
                    .iter()
                    .zip(&q.coeffs)
                    .map(|(a, b)| a + t * (b - a))
                    .collect();
                if let Ok(s) = solve_at(&m, &guess, opts) {
                    let dup = out.iter().any(|o| {
                        (o.qa - s.qa).abs() <= 1e-7 * (1.0 + s.qa)
                            && (o.qm - s.qm).abs() <= 1e-7 * (1.0 + s.qm.abs())
                    });
                    if !dup {
                        out.push(s);
                    }
                }
            }
            out.sort_by(|a, b| a.qa.total_cmp(&b.qa));
            out
        })
        .collect()
}

/// [`super::continue_branch`] from `omega_start` to `omega_end`; when the linear (eq. 13) start
/// does not converge (no contact-only solution at `omega_start`, e.g. external excitation at
/// F_hat < 1, Fig. 25b), the branch is seeded instead from the simulated steady state reached from
/// the static equilibrium (1 + F_m, 0), polished by Newton and continued with
/// [`super::continue_from`].
pub fn branch_from_start(
    model: &GearPair,
    omega_start: f64,
    omega_end: f64,
    opts: &AftOptions,
    cont: &ContinuationOptions,
) -> Result<Vec<HbPoint>> {
    match continue_branch(model, omega_start, omega_end, opts, cont, &NoProgress) {
        Ok(b) => Ok(b),
        Err(first) => seeded_branch(model, omega_start, omega_end, opts, cont).map_err(|_| first),
    }
}

/// A branch seeded at `omega_seed` by the simulated steady state from the static equilibrium
/// (1 + F_m, 0), polished by Newton and continued towards `omega_end`.
fn seeded_branch(
    model: &GearPair,
    omega_seed: f64,
    omega_end: f64,
    opts: &AftOptions,
    cont: &ContinuationOptions,
) -> Result<Vec<HbPoint>> {
    let m0 = model.at_omega(omega_seed)?;
    let flow = ExactFlow::new(&m0)?;
    let s = steady_state(
        &flow,
        [1.0 + model.mean_force, 0.0],
        &SteadyOptions::default(),
    )?;
    let Some(&x0) = s.poincare.first() else {
        return Err(GearError::Numerical(
            "steady state without section point".into(),
        ));
    };
    let guess = guess_from_state(&m0, x0, opts)?;
    let start = solve_at(&m0, &guess, opts)?;
    continue_from(model, &start, omega_end, opts, cont, &NoProgress)
}

/// Branches that together cover [`omega_start`, `omega_end`]: [`branch_from_start`], and when
/// that branch does not reach `omega_end` (it turned back or stalled), a second one seeded by
/// simulation at `omega_end` and continued down towards `omega_start` (as for eq. 4 at F_hat 0.5,
/// Fig. 25b, which has no contact-only solution anywhere). A failing second seed is left out.
pub fn branches_covering(
    model: &GearPair,
    omega_start: f64,
    omega_end: f64,
    opts: &AftOptions,
    cont: &ContinuationOptions,
) -> Result<Vec<Vec<HbPoint>>> {
    let first = branch_from_start(model, omega_start, omega_end, opts, cont)?;
    let reach = first
        .iter()
        .map(|p| p.omega)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut out = vec![first];
    if reach < omega_end - 1e-6 {
        if let Ok(b) = seeded_branch(model, omega_end, omega_start, opts, cont) {
            out.push(b);
        }
    }
    Ok(out)
}
