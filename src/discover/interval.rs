//! The interval of a refitted candidate's estimate: Wald (delta method), profile likelihood,
//! and the hull of the two that a name rests on (see [`profiled_refit`]).

use super::decide::Refitted;
use super::effects::Candidate;
use super::fit::{fit_model, EffectInFit};
use super::forward::{predict_many, Setup};
use super::profile::{Bound, PhaseProfile, Profile, ProfileProblem};
use super::run::CandidateResult;
use crate::error::Result;
use crate::fit::{LmFit, Stop};
use nalgebra::{DMatrix, DVector};

/// Covariance of `cand`'s delta (the last `cand.dim()` parameters of a fit, see
/// [`super::fit::ModelFit::lm`]) from the fit's Jacobian: the inverse Fisher information
/// (J'J)^-1 of residuals in noise-scale units. None when J'J is singular.
fn delta_covariance(cand: Candidate, lm: &LmFit) -> Option<(usize, DMatrix<f64>)> {
    let p0 = lm.params.len() - cand.dim();
    let jt = &lm.jacobian;
    let cov = (jt.transpose() * jt).try_inverse()?;
    Some((
        p0,
        cov.view((p0, p0), (cand.dim(), cand.dim())).into_owned(),
    ))
}

/// 95% Wald interval of `cand`'s estimate from a fit's Jacobian (delta method; delta is the
/// last `cand.dim()` parameters, see [`super::fit::ModelFit::lm`]): on exp(beta) for the backlash,
/// symmetric for gamma, clipped at zero for the amplitudes. None when J'J is singular.
pub(super) fn wald_ci(cand: Candidate, lm: &LmFit) -> Option<(f64, f64)> {
    let (p0, sub) = delta_covariance(cand, lm)?;
    let delta = &lm.params[p0..];
    let (est, grad) = cand.estimate(delta);
    let g = DVector::from_vec(grad);
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

/// 95% Wald arc of a phase-carrying candidate's phase psi = atan2(d1, d0) of its first
/// (A cos psi, A sin psi) pair, degrees (delta method, gradient (-d1, d0) / A^2): (lo, hi)
/// with psi in [0, 360) between them, so that hi may exceed 360 or lo fall below 0; the
/// whole circle (0, 360) when the half-width reaches 180 degrees. None for a candidate
/// without a phase, at zero amplitude or when J'J is singular.
pub(super) fn wald_phase_arc(cand: Candidate, lm: &LmFit) -> Option<(f64, f64)> {
    if !cand.has_phase() {
        return None;
    }
    let (p0, sub) = delta_covariance(cand, lm)?;
    let (x, y) = (lm.params[p0], lm.params[p0 + 1]);
    let a2 = x * x + y * y;
    if a2 == 0.0 {
        return None;
    }
    let g = DVector::from_vec(vec![-y / a2, x / a2]);
    let pair = sub.view((0, 0), (2, 2)).into_owned();
    let half = (1.96 * (g.transpose() * pair * &g)[(0, 0)].max(0.0).sqrt()).to_degrees();
    let psi = y.atan2(x).to_degrees().rem_euclid(360.0);
    Some(if half >= 180.0 {
        (0.0, 360.0)
    } else {
        (psi - half, psi + half)
    })
}

/// Whether the phase `deg` (degrees, any turn) lies on the arc `(lo, hi)` of
/// [`wald_phase_arc`].
pub(super) fn on_phase_arc(deg: f64, (lo, hi): (f64, f64)) -> bool {
    (deg - lo).rem_euclid(360.0) <= hi - lo
}

/// Refits a profile may restart from a better point before its interval is taken.
const PROFILE_RESTARTS: usize = 2;

/// The refit `refit` of candidate `c` with its 95% profile-likelihood interval
/// ([`super::profile`]) on its own points and noise scales, from its Wald interval as first
/// guesses. Where a profile point fits better than the refit, the refit continues from there
/// (at most [`PROFILE_RESTARTS`] times) and the better refit is returned too.
///
/// With `phase_profile`, a phase-carrying candidate's phase is profiled too
/// ([`ProfileProblem::phase_arc`]), and a better point found there restarts the refit as well.
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
    phase_profile: bool,
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
        let (lo, hi) = match problem.interval(own_wald)? {
            Profile::Interval(lo, hi) => (lo, hi),
            Profile::Better(start) => {
                match continued(setup, train, current, c.candidate, &start, iters)? {
                    Some(b) => better = Some(b),
                    None => break,
                }
                continue;
            }
        };
        let wald_arc = wald_phase_arc(c.candidate, &current.fit.lm);
        let phase_arc = if phase_profile && c.candidate.has_phase() {
            let half = wald_arc.map(|(a, b)| (0.5 * (b - a)).to_radians());
            match problem.phase_arc(half)? {
                PhaseProfile::Arc(lo, hi) => Some(phase_hull(
                    Candidate::first_phase(&current.fit.effect.delta),
                    (lo, hi),
                    wald_arc,
                )),
                PhaseProfile::Better(start) => {
                    match continued(setup, train, current, c.candidate, &start, iters)? {
                        Some(b) => better = Some(b),
                        None => break,
                    }
                    continue;
                }
            }
        } else {
            None
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
            phase_arc,
            method: "hull of the profile-likelihood and Wald intervals",
        };
        return Ok((better, found));
    }
    let current = better.as_ref().unwrap_or(refit);
    let ci = wald_ci(c.candidate, &current.fit.lm);
    let found = IntervalFound {
        ci: over_both_basins(ci, c, &current.fit.effect.delta),
        profile: None,
        phase_arc: None,
        method: "Wald (the profile kept finding better fits)",
    };
    Ok((better, found))
}

/// The fit of `current`'s candidate continued from `start`, a profile point that fitted
/// better; None when the continued fit ends no lower than `current`.
fn continued(
    setup: &Setup,
    train: &[usize],
    current: &Refitted,
    cand: Candidate,
    start: &[f64],
    iters: usize,
) -> Result<Option<Refitted>> {
    let f = fit_model(
        setup,
        train,
        &current.mask,
        &current.scales,
        EffectInFit::Fitted(cand),
        start,
        Stop::converged(iters / 2 + 1),
    )?;
    if f.lm.rss >= current.fit.lm.rss {
        return Ok(None);
    }
    let train_preds = predict_many(setup, train, f.globals, &f.ste_um, &f.effect)?;
    Ok(Some(Refitted {
        cand: current.cand,
        fit: f,
        mask: current.mask.clone(),
        train_preds,
        scales: current.scales.clone(),
    }))
}

/// The 95% arc of a phase estimated at `psi` (rad) in degrees, in the convention of
/// [`wald_phase_arc`]: the hull of the profile's sides `(lo, hi)` (rad from psi; None a side
/// without bound, which then reaches half a turn) and the Wald arc, as the amplitude's interval
/// is the hull of its profile and Wald intervals; the whole circle when the sides meet.
fn phase_hull(
    psi: f64,
    (lo, hi): (Option<f64>, Option<f64>),
    wald: Option<(f64, f64)>,
) -> (f64, f64) {
    let centre = psi.to_degrees().rem_euclid(360.0);
    let mut below = lo.map_or(180.0, |l| -l.to_degrees());
    let mut above = hi.map_or(180.0, |h| h.to_degrees());
    if let Some((a, b)) = wald {
        below = below.max(centre - a);
        above = above.max(b - centre);
    }
    if below + above >= 360.0 {
        (0.0, 360.0)
    } else {
        (centre - below, centre + above)
    }
}

/// The interval of the estimate a decision rests on, and how it was found.
#[derive(Clone, Copy, Debug)]
pub(super) struct IntervalFound {
    pub ci: Option<(f64, f64)>,
    /// The profile-likelihood interval's sides (None: the profile did not rise within its
    /// fits on that side).
    pub profile: Option<(Option<f64>, Option<f64>)>,
    /// The phase's 95% arc, degrees, the hull of its profile-likelihood and Wald arcs
    /// ([`phase_hull`]), when the phase was profiled.
    pub phase_arc: Option<(f64, f64)>,
    pub method: &'static str,
}

impl IntervalFound {
    /// Whether the refit settled: its profile was taken, rather than a better fit found after
    /// every restart.
    pub fn settled(&self) -> bool {
        self.profile.is_some()
    }
}

impl CandidateResult {
    /// Record the phase of a phase-carrying refit `lm` ending at `delta` and its 95% arcs
    /// ([`phase_arcs`]); nothing for a candidate without a phase.
    pub(super) fn set_phase(&mut self, lm: &LmFit, delta: &[f64]) {
        if self.candidate.has_phase() {
            self.phase_deg = Some(Candidate::first_phase(delta).to_degrees().rem_euclid(360.0));
            self.phase_wald95_deg = phase_arcs(self, lm, delta);
        }
    }
}

/// The 95% arcs of a refitted candidate's phase (degrees, [`wald_phase_arc`]) from the kept
/// fit `lm`, and the other phase basin's arc too when the phase is undetermined between it and
/// the kept fit's `delta` ([`super::run::OtherStart`]): the likelihood-ratio confidence set then
/// has a piece in each basin. Empty for a candidate without a phase.
fn phase_arcs(c: &CandidateResult, lm: &LmFit, delta: &[f64]) -> Vec<(f64, f64)> {
    let mut arcs: Vec<(f64, f64)> = wald_phase_arc(c.candidate, lm).into_iter().collect();
    if let Some(o) = c
        .other_start
        .as_ref()
        .filter(|o| o.phase_undetermined(delta))
    {
        arcs.extend(o.phase_wald95_deg);
    }
    arcs
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A fit of a two-parameter delta alone whose Jacobian is diag(1 / sx, 1 / sy): the
    /// covariance is diag(sx^2, sy^2).
    fn fit_at(x: f64, y: f64, sx: f64, sy: f64) -> LmFit {
        LmFit {
            params: vec![x, y],
            rss: 0.0,
            residuals: vec![0.0; 2],
            jacobian: DMatrix::from_diagonal(&DVector::from_vec(vec![1.0 / sx, 1.0 / sy])),
            evaluations: 0,
        }
    }

    #[test]
    fn the_phase_arc_is_the_delta_method_on_atan2() {
        // At (0, 0.2) the phase is 90 deg and only x moves it: se = sx / A = 0.05 rad,
        // half-width 1.96 x 0.05 rad = 5.615 deg; sy (the amplitude's direction) does not count.
        let c = Candidate::MeshStiffnessVariation;
        let (lo, hi) = wald_phase_arc(c, &fit_at(0.0, 0.2, 0.01, 0.5)).unwrap();
        assert!((lo - (90.0 - 5.6150)).abs() < 1e-3, "{lo}");
        assert!((hi - (90.0 + 5.6150)).abs() < 1e-3, "{hi}");
        // The phase is reported in [0, 360): -90 deg is 270.
        let (lo, hi) = wald_phase_arc(c, &fit_at(0.0, -0.2, 0.01, 0.01)).unwrap();
        assert!((0.5 * (lo + hi) - 270.0).abs() < 1e-9);
        // A standard error of twice the amplitude (2 rad, half-width 225 deg): the arc spans
        // the circle.
        assert_eq!(
            wald_phase_arc(c, &fit_at(0.0, 0.2, 0.4, 0.01)),
            Some((0.0, 360.0))
        );
        assert_eq!(wald_phase_arc(c, &fit_at(0.0, 0.0, 0.01, 0.01)), None);
        assert_eq!(
            wald_phase_arc(Candidate::DampingLaw, &fit_at(0.0, 0.2, 0.01, 0.01)),
            None
        );
    }

    #[test]
    fn the_phase_arc_is_the_hull_of_profile_and_wald_and_may_close_the_circle() {
        let psi = 100_f64.to_radians();
        let r = |deg: f64| Some(deg.to_radians());
        // Profile 80 .. 130 around 100, Wald 95 .. 105: the profile's sides.
        let (lo, hi) = phase_hull(psi, (r(-20.0), r(30.0)), Some((95.0, 105.0)));
        assert!(
            (lo - 80.0).abs() < 1e-9 && (hi - 130.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        // A Wald side wider than the profile's is kept.
        let (lo, hi) = phase_hull(psi, (r(-20.0), r(3.0)), Some((95.0, 110.0)));
        assert!(
            (lo - 80.0).abs() < 1e-9 && (hi - 110.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        // A side without bound reaches half a turn; an estimate near 360 keeps hi above it.
        let near_top = 350_f64.to_radians();
        let (lo, hi) = phase_hull(near_top, (r(-10.0), None), None);
        assert!(
            (lo - 340.0).abs() < 1e-9 && (hi - 530.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        assert!(on_phase_arc(10.0, (lo, hi)) && !on_phase_arc(330.0, (lo, hi)));
        // Both sides without bound: the whole circle.
        assert_eq!(phase_hull(psi, (None, None), None), (0.0, 360.0));
    }

    #[test]
    fn a_phase_lies_on_an_arc_across_zero_in_any_turn() {
        let arc = (350.0, 370.0);
        for deg in [355.0, 5.0, -5.0, 725.0, 350.0, 370.0] {
            assert!(on_phase_arc(deg, arc), "{deg}");
        }
        for deg in [20.0, 340.0, 180.0] {
            assert!(!on_phase_arc(deg, arc), "{deg}");
        }
        assert!(on_phase_arc(123.0, (0.0, 360.0)));
    }
}
