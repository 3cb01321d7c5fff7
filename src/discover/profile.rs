//! Profile-likelihood 95% interval of a refitted effect's estimate (Venzon & Moolgavkar 1988;
//! Bates & Watts 1988, Sec. 6.1): the values of its profile coordinate
//! ([`Candidate::profiled`]: an amplitude, gamma, or beta) at which the residual sum of squares
//! of the refit's own points, in its own noise scales, minimised over everything else (zeta,
//! omega_n, every training load's STE, the phase and the rest of delta), exceeds the refit's by
//! q^2, q the refit's t quantile ([`super::interval::RefitNoise::quantile`]: Satterthwaite's
//! degrees of freedom for an estimated noise, 1.96 for a stated one, where q^2 = chi2(0.95; 1)
//! = 3.84), as `validate`'s profiles do.
//!
//! Why not the Wald interval alone: the pp response is steep next to a fold, and a linearised
//! fit leans on the one or two kept points there. On a constant-noise null set a torque ripple
//! refit had a Wald standard error of 0.0002 (twenty times below the ripple's usual), one kept
//! point carrying 38% of its variance; on eps 0.2 sets at a random phase the Wald intervals
//! covered the truth on 13 of 17 seeds. The profile asks the curves themselves how far the
//! estimate can move, the fold's points included.
//!
//! Each side is the engine's root search (`crate::fit::search_side`) on the signed root
//! deviance, from the Wald bound as first step and within [`MAX_FITS_PER_SIDE`] fits: each
//! profile point is an all-load fit, tens of forward sweeps, and the search takes a point within
//! [`ROOT_TOL`] of the threshold as the end rather than refining it further.
//!
//! A profile point can fit better than the refit itself: the pp response jumps with the
//! parameters and Levenberg-Marquardt stops on a ledge. On an eps 0.2 set (relative noise,
//! random phase, seed 14 of the study) the refit ended at eps 0.189 with a Wald interval
//! [0.182, 0.196], and the profile's first point above it, eps 0.196, fitted better. The
//! profile then reports that point ([`Profile::Better`]) for the refit to continue from.

use super::effects::Candidate;
use super::fit::{fit_model, EffectInFit, Mask, ModelFit};
use super::forward::Setup;
use super::noise::Scales;
use crate::error::Result;
use crate::fit::{search_side, Fitted, InnerFit, SearchOptions, SideEnd, Stop};
use std::f64::consts::PI;

/// First step of a phase profile without a Wald arc (rad, about 6 degrees).
const PHASE_FALLBACK_STEP: f64 = 0.1;
/// Profile fits per side at most, bracketing and root search together.
const MAX_FITS_PER_SIDE: usize = 6;
/// A side's root is accepted within this of the quantile q (about 2.5% of the bound's
/// distance from the estimate where the model is linear).
const ROOT_TOL: f64 = 0.05;
/// Jacobians of one profile fit at most (each starts within a step of its minimum).
const PROFILE_JACOBIANS: usize = 6;
/// Brent's tolerance on a side's end, in Wald standard errors: below [`ROOT_TOL`]'s reach, so
/// that the end is found by that rule or by the budget.
const END_TOLERANCE: f64 = 1e-3;
/// A profile point below the refit's residual sum of squares by more than this (sigma^2; a
/// tenth of the 3.84 the interval spans, ten times the 0.01 a profile fit may stop above its
/// own minimum) is a better minimum.
const BETTER_BY: f64 = 0.1;

/// What a profile fits: the refit, its points and scales.
pub struct ProfileProblem<'a> {
    pub setup: &'a Setup,
    pub train: &'a [usize],
    pub mask: &'a Mask,
    pub scales: &'a Scales,
    pub cand: Candidate,
    pub fit: &'a ModelFit,
    /// The intervals' 97.5% quantile ([`super::interval::RefitNoise::quantile`]): the profile
    /// rises by its square at an end, as in `crate::fit::profile_interval`.
    pub q: f64,
}

/// What a profile found.
#[derive(Clone, Debug, PartialEq)]
pub enum Profile {
    /// The interval's lower and upper sides.
    Interval(Bound, Bound),
    /// A point that fits better than the refit: its parameters in the layout of a fit of the
    /// candidate ([`ModelFit::lm`]), to refit from.
    Better(Vec<f64>),
}

/// What a phase profile found ([`ProfileProblem::phase_arc`]).
#[derive(Clone, Debug, PartialEq)]
pub enum PhaseProfile {
    /// The arc's sides, rad from the estimate's phase (the lower one negative); None on a side
    /// that stays inside for half a turn or does not rise within its fits.
    Arc(Option<f64>, Option<f64>),
    /// A point that fits better than the refit, in the layout of a fit of the candidate.
    Better(Vec<f64>),
}

/// How a side of the interval ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// The profile crosses q^2 here (estimate units).
    At(f64),
    /// An amplitude's profile stays below it down to zero: the bound is zero.
    Zero,
    /// It does not rise enough within the fits allowed: no bound on this side.
    Open,
}

impl ProfileProblem<'_> {
    /// The 95% profile interval of the estimate from the Wald interval `wald` (estimate
    /// units) as first guesses, or a better fit than the refit's.
    pub fn interval(&self, wald: Option<(f64, f64)>) -> Result<Profile> {
        let (u_hat, free) = self.cand.profiled(&self.fit.effect.delta);
        let mut centre = self.fit.lm.params.clone();
        centre.truncate(centre.len() - self.cand.dim());
        centre.extend_from_slice(&free);
        let guess = |bound: Option<f64>| {
            bound
                .map(|b| (self.cand.profiled_of_estimate(b) - u_hat).abs())
                .filter(|h| h.is_finite() && *h > 0.0)
        };
        let fallback = 0.1 * u_hat.abs().max(self.cand.scale());
        let (lo_h, hi_h) = (guess(wald.map(|w| w.0)), guess(wald.map(|w| w.1)));
        // An amplitude's Wald interval is clipped at zero; its upper half-width is the guess.
        let lo_h = if self.cand.profiled_is_amplitude() {
            hi_h.or(lo_h)
        } else {
            lo_h.or(hi_h)
        };
        let held = Held {
            problem: self,
            coordinate: Coordinate::Profiled,
            centre: u_hat,
        };
        // An amplitude's lower side ends at zero.
        let floor = self.cand.profiled_is_amplitude().then_some(u_hat.max(0.0));
        let side = |dir: f64, h: f64, limit: Option<f64>| {
            search_side(&held, centre.clone(), dir, options(h, limit, self.q))
        };
        let (lo, hi) = rayon::join(
            || side(-1.0, lo_h.unwrap_or(fallback), floor),
            || side(1.0, hi_h.unwrap_or(fallback), None),
        );
        let bound = |end: SideEnd<Vec<f64>>, dir: f64| match end {
            SideEnd::At { distance, .. } => Ok(Bound::At(
                self.cand.estimate_of_profiled(u_hat + dir * distance),
            )),
            SideEnd::Limit => Ok(Bound::Zero),
            SideEnd::Open => Ok(Bound::Open),
            SideEnd::Better { u, fitted } => Err(held.layout(u, &fitted)),
        };
        Ok(match (bound(lo?, -1.0), bound(hi?, 1.0)) {
            (Err(better), _) | (_, Err(better)) => Profile::Better(better),
            (Ok(lo), Ok(hi)) => Profile::Interval(lo, hi),
        })
    }

    /// The 95% profile-likelihood arc of a phase-carrying candidate's first phase psi
    /// ([`Candidate::first_phase`]): the phases on each side of the estimate at which the
    /// residual sum of squares minimised over everything else (the amplitude kept positive,
    /// [`EffectInFit::PhaseHeld`]) exceeds the refit's by q^2, searched from the Wald
    /// half-width `wald_half` (rad) as first step; or a better fit than the refit's.
    ///
    /// Why: the all-load fit hardly moves a phase, so the refit's phase is where the polar
    /// profile's 30 degree grid and Levenberg-Marquardt left it, and the Wald arc about it
    /// covered the truth on 12 of 18 eps 0.15 seeds. The profile asks the likelihood itself.
    pub fn phase_arc(&self, wald_half: Option<f64>) -> Result<PhaseProfile> {
        let delta = &self.fit.effect.delta;
        let psi_hat = Candidate::first_phase(delta);
        let (amplitude, free) = self.cand.profiled(delta);
        let mut centre = self.fit.lm.params.clone();
        centre.truncate(centre.len() - self.cand.dim());
        centre.push(amplitude);
        centre.extend_from_slice(&free[1..]);
        let h = wald_half
            .filter(|h| h.is_finite() && *h > 0.0)
            .unwrap_or(PHASE_FALLBACK_STEP)
            .min(0.5 * PI);
        let held = Held {
            problem: self,
            coordinate: Coordinate::Phase,
            centre: psi_hat,
        };
        // Each side goes half a turn at most.
        let side = |dir: f64| search_side(&held, centre.clone(), dir, options(h, Some(PI), self.q));
        let (lo, hi) = rayon::join(|| side(-1.0), || side(1.0));
        let end = |end: SideEnd<Vec<f64>>, dir: f64| match end {
            SideEnd::At { distance, .. } => Ok(Some(dir * distance)),
            // Inside up to half a turn, or not rising within the fits: no bound on that side.
            SideEnd::Limit | SideEnd::Open => Ok(None),
            SideEnd::Better { u, fitted } => Err(held.layout(u, &fitted)),
        };
        Ok(match (end(lo?, -1.0), end(hi?, 1.0)) {
            (Err(better), _) | (_, Err(better)) => PhaseProfile::Better(better),
            (Ok(lo), Ok(hi)) => PhaseProfile::Arc(lo, hi),
        })
    }
}

/// The search of one side from its first step `h` (the coordinate's units; the search clamps
/// it to `limit`), never beyond `limit` from the estimate, to the root deviance `q`.
fn options(h: f64, limit: Option<f64>, q: f64) -> SearchOptions {
    SearchOptions {
        first_step: h,
        se: h / q,
        q,
        limit,
        max_fits: MAX_FITS_PER_SIDE,
        accept: ROOT_TOL,
        bracket_width: None,
        tolerance: END_TOLERANCE * h / q,
        better_by: Some(BETTER_BY),
    }
}

/// Which coordinate a profile holds.
#[derive(Clone, Copy)]
enum Coordinate {
    /// [`Candidate::profiled`]'s: an amplitude, gamma or beta.
    Profiled,
    /// A phase-carrying candidate's first phase.
    Phase,
}

/// A profile's inner fit: the refit's model with one coordinate held `centre` + u.
struct Held<'a, 'b> {
    problem: &'a ProfileProblem<'b>,
    coordinate: Coordinate,
    centre: f64,
}

impl Held<'_, '_> {
    fn held(&self, u: f64) -> EffectInFit<'static> {
        let at = self.centre + u;
        match self.coordinate {
            Coordinate::Profiled => EffectInFit::Profiled(self.problem.cand, at),
            Coordinate::Phase => EffectInFit::PhaseHeld(self.problem.cand, at),
        }
    }

    /// The parameters `fitted` of the point at u in the layout of a fit of the candidate.
    fn layout(&self, u: f64, fitted: &[f64]) -> Vec<f64> {
        let n = 2 + self.problem.train.len();
        let mut params = fitted[..n].to_vec();
        params.extend(self.held(u).effect(&fitted[n..]).delta);
        params
    }
}

impl InnerFit for Held<'_, '_> {
    type Start = Vec<f64>;

    fn fit_at(&self, u: f64, start: &Vec<f64>) -> Result<Fitted<Vec<f64>>> {
        let p = self.problem;
        Ok(
            match fit_model(
                p.setup,
                p.train,
                p.mask,
                p.scales,
                self.held(u),
                start,
                Stop::near(PROFILE_JACOBIANS),
            ) {
                Ok(f) => Fitted {
                    rise: f.lm.rss - p.fit.lm.rss,
                    fitted: Some(f.lm.params),
                },
                // A value whose fit fails (a damping inadmissible at some load, a prediction
                // refused) is outside the interval, as in `crate::fit::profile_interval`.
                Err(_) => Fitted {
                    rise: f64::INFINITY,
                    fitted: None,
                },
            },
        )
    }
}
