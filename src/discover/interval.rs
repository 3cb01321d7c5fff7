//! The interval of a refitted candidate's estimate: Wald (delta method), profile likelihood,
//! and the hull of the two that a name rests on (see [`profiled_refit`]).

use super::decide::Refitted;
use super::effects::Candidate;
use super::fit::{fit_model, EffectInFit};
use super::forward::{predict_many, Setup};
use super::profile::{Bound, Profile, ProfileProblem};
use super::run::CandidateResult;
use crate::error::Result;
use crate::fit::{LmFit, Stop};
use nalgebra::{DMatrix, DVector};

/// 95% Wald interval of `cand`'s estimate from a fit's Jacobian (delta method; delta is the
/// last `cand.dim()` parameters, see [`super::fit::ModelFit::lm`]): on exp(beta) for the backlash,
/// symmetric for gamma, clipped at zero for the amplitudes. None when J'J is singular.
pub(super) fn wald_ci(cand: Candidate, lm: &LmFit) -> Option<(f64, f64)> {
    let p0 = lm.params.len() - cand.dim();
    let delta = &lm.params[p0..];
    let (est, grad) = cand.estimate(delta);
    let jt = &lm.jacobian;
    let cov = (jt.transpose() * jt).try_inverse()?;
    let g = DVector::from_vec(grad);
    let sub: DMatrix<f64> = cov.view((p0, p0), (cand.dim(), cand.dim())).into_owned();
    let var = (g.transpose() * &sub * &g)[(0, 0)].max(0.0);
    Some(match cand {
        Candidate::Backlash => {
            let sb = sub[(0, 0)].max(0.0).sqrt();
            ((delta[0] - 1.96 * sb).exp(), (delta[0] + 1.96 * sb).exp())
        }
        Candidate::DampingLaw => (est - 1.96 * var.sqrt(), est + 1.96 * var.sqrt()),
        _ => ((est - 1.96 * var.sqrt()).max(0.0), est + 1.96 * var.sqrt()),
    })
}

/// Refits a profile may restart from a better point before its interval is taken.
const PROFILE_RESTARTS: usize = 2;

/// The refit `refit` of candidate `c` with its 95% profile-likelihood interval
/// ([`super::profile`]) on its own points and noise scales, from its Wald interval as first
/// guesses. Where a profile point fits better than the refit, the refit continues from there
/// (at most [`PROFILE_RESTARTS`] times) and the better refit is returned too.
///
/// The interval reported is the hull of the profile and Wald intervals: each is too narrow in
/// its own way. The Wald interval next to a fold (a torque ripple on a null set: Wald
/// [0.0212, 0.0221], profile [0.0023, 0.0224]); the profile where its fits, warm-started along
/// the profile, stop on ledges of the jumping pp response above their own minimum (eps 0.2
/// set of study seed 11, relative noise: Wald [0.187, 0.204], profile [0.193, 0.198], truth
/// 0.2). Over 17 eps 0.2 seeds the Wald interval covered 14, the profile 14, the hull 16.
/// The interval spans both phase basins when the phase is undetermined, as the Wald interval
/// does.
pub(super) fn profiled_refit(
    setup: &Setup,
    train: &[usize],
    refit: &Refitted,
    c: &CandidateResult,
    iters: usize,
) -> Result<(Option<Refitted>, IntervalFound)> {
    let mut better: Option<Refitted> = None;
    for _ in 0..=PROFILE_RESTARTS {
        let current = better.as_ref().unwrap_or(refit);
        let own_wald = wald_ci(c.candidate, &current.fit.lm);
        let problem = ProfileProblem {
            setup,
            train,
            mask: &current.mask,
            scales: &current.scales,
            cand: c.candidate,
            fit: &current.fit,
        };
        let (lo, hi) = match problem.interval(own_wald) {
            Profile::Interval(lo, hi) => (lo, hi),
            Profile::Better(start) => {
                let f = fit_model(
                    setup,
                    train,
                    &current.mask,
                    &current.scales,
                    EffectInFit::Fitted(c.candidate),
                    &start,
                    Stop::converged(iters / 2 + 1),
                )?;
                if f.lm.rss >= current.fit.lm.rss {
                    break;
                }
                let train_preds = predict_many(setup, train, f.globals, &f.ste_um, &f.effect)?;
                better = Some(Refitted {
                    cand: current.cand,
                    fit: f,
                    mask: current.mask.clone(),
                    train_preds,
                    scales: current.scales.clone(),
                });
                continue;
            }
        };
        let side = |b: Bound| match b {
            Bound::At(v) => Some(v),
            Bound::Zero => Some(0.0),
            Bound::Open => None,
        };
        let profile = (side(lo), side(hi));
        // The hull of both: each is too narrow in its own way (see the doc comment).
        let ci = own_wald.map(|(a, b)| {
            (
                profile.0.map_or(a, |p| p.min(a)),
                profile.1.map_or(b, |p| p.max(b)),
            )
        });
        let found = IntervalFound {
            ci: over_both_basins(ci, c, &current.fit.effect.delta),
            profile: Some(profile),
            method: "hull of the profile-likelihood and Wald intervals",
        };
        return Ok((better, found));
    }
    let current = better.as_ref().unwrap_or(refit);
    let ci = wald_ci(c.candidate, &current.fit.lm);
    let found = IntervalFound {
        ci: over_both_basins(ci, c, &current.fit.effect.delta),
        profile: None,
        method: "Wald (the profile kept finding better fits)",
    };
    Ok((better, found))
}

/// The interval of the estimate a decision rests on, and how it was found.
#[derive(Clone, Copy, Debug)]
pub(super) struct IntervalFound {
    pub ci: Option<(f64, f64)>,
    /// The profile-likelihood interval's sides (None: the profile did not rise within its
    /// fits on that side).
    pub profile: Option<(Option<f64>, Option<f64>)>,
    pub method: &'static str,
}

impl IntervalFound {
    /// Whether the refit settled: its profile was taken, rather than a better fit found after
    /// every restart.
    pub fn settled(&self) -> bool {
        self.profile.is_some()
    }
}

/// `ci` widened over the other phase basin's Wald interval when the phase is undetermined
/// between it and the kept fit's `delta` ([`super::run::OtherStart`]).
pub(super) fn over_both_basins(
    ci: Option<(f64, f64)>,
    c: &CandidateResult,
    delta: &[f64],
) -> Option<(f64, f64)> {
    match c
        .other_start
        .as_ref()
        .filter(|o| o.phase_undetermined(delta))
    {
        Some(o) => ci.zip(o.ci95).map(|(a, b)| (a.0.min(b.0), a.1.max(b.1))),
        None => ci,
    }
}
