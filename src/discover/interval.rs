//! The interval of a refitted candidate's estimate: Wald (delta method), profile likelihood,
//! and the hull of the two that a name rests on (see [`profiled_refit`]).

use super::decide::Refitted;
use super::effects::Candidate;
use super::fit::{fit_model, EffectInFit, Mask};
use super::forward::{predict_many, Setup};
use super::noise::{DiscoveryNoise, Scales};
use super::profile::{Bound, PhaseProfile, Profile, ProfileProblem};
use super::run::row_scales;
use super::run::CandidateResult;
use crate::error::Result;
use crate::fit::{satterthwaite_dof_of, t_quantile_975, LmFit, NoiseModel, Stop};
use nalgebra::{DMatrix, DVector};

/// Covariance of `cand`'s delta (the last `cand.dim()` parameters of a fit, see
/// [`super::fit::ModelFit::lm`]) from a Jacobian `jt` of the fit's residuals in noise-scale
/// units: the inverse Fisher information (J'J)^-1. None when J'J is singular.
fn delta_covariance(cand: Candidate, jt: &DMatrix<f64>) -> Option<(usize, DMatrix<f64>)> {
    let p0 = jt.ncols() - cand.dim();
    let cov = (jt.transpose() * jt).try_inverse()?;
    Some((
        p0,
        cov.view((p0, p0), (cand.dim(), cand.dim())).into_owned(),
    ))
}

/// The variance of the coordinate on which `cand`'s Wald interval is formed (delta method):
/// log b for the backlash, the estimate itself otherwise; at the parameters `params` of a
/// fit whose standardized Jacobian is `jt`. None when J'J is singular.
fn interval_variance(cand: Candidate, params: &[f64], jt: &DMatrix<f64>) -> Option<f64> {
    let (p0, sub) = delta_covariance(cand, jt)?;
    Some(match cand {
        Candidate::Backlash => sub[(0, 0)].max(0.0),
        _ => {
            let g = DVector::from_vec(cand.estimate(&params[p0..]).1);
            (g.transpose() * &sub * &g)[(0, 0)].max(0.0)
        }
    })
}

/// The larger of [`interval_variance`] under the fit's Jacobian and under its secants where
/// taken ([`super::fit::relinearized`]). None when J'J is singular.
fn wald_variance(cand: Candidate, lm: &LmFit) -> Option<f64> {
    let local = interval_variance(cand, &lm.params, &lm.jacobian)?;
    let secant = lm
        .secant_jacobian
        .as_ref()
        .and_then(|s| interval_variance(cand, &lm.params, s));
    Some(secant.map_or(local, |v| v.max(local)))
}

/// 95% Wald interval of `cand`'s estimate from a fit's Jacobian (delta method; delta is the
/// last `cand.dim()` parameters, see [`super::fit::ModelFit::lm`]), `q` standard errors either
/// side ([`RefitNoise::quantile`]): on exp(beta) for the backlash, symmetric for gamma, clipped
/// at zero for the amplitudes. None when J'J is singular.
pub(super) fn wald_ci(cand: Candidate, lm: &LmFit, q: f64) -> Option<(f64, f64)> {
    let half = q * wald_variance(cand, lm)?.sqrt();
    let p0 = lm.params.len() - cand.dim();
    let delta = &lm.params[p0..];
    let est = cand.estimate(delta).0;
    Some(match cand {
        Candidate::Backlash => ((delta[0] - half).exp(), (delta[0] + half).exp()),
        Candidate::DampingLaw => (est - half, est + half),
        _ => ((est - half).max(0.0), est + half),
    })
}

/// 95% Wald arc of a phase-carrying candidate's phase psi = atan2(d1, d0) of its first
/// (A cos psi, A sin psi) pair, degrees (delta method, gradient (-d1, d0) / A^2, `q` standard
/// errors either side): (lo, hi) with psi in [0, 360) between them, so that hi may exceed 360
/// or lo fall below 0; the whole circle (0, 360) when the half-width reaches 180 degrees. None
/// for a candidate without a phase, at zero amplitude or when J'J is singular.
pub(super) fn wald_phase_arc(cand: Candidate, lm: &LmFit, q: f64) -> Option<(f64, f64)> {
    if !cand.has_phase() {
        return None;
    }
    let p0 = lm.params.len() - cand.dim();
    let (x, y) = (lm.params[p0], lm.params[p0 + 1]);
    let a2 = x * x + y * y;
    if a2 == 0.0 {
        return None;
    }
    let g = DVector::from_vec(vec![-y / a2, x / a2]);
    // The larger of the two linearisations' variances, as for the estimate (`wald_variance`).
    let variance = |jt: &DMatrix<f64>| {
        delta_covariance(cand, jt).map(|(_, sub)| {
            let pair = sub.view((0, 0), (2, 2)).into_owned();
            (g.transpose() * pair * &g)[(0, 0)].max(0.0)
        })
    };
    let local = variance(&lm.jacobian)?;
    let v = lm
        .secant_jacobian
        .as_ref()
        .and_then(variance)
        .map_or(local, |s| s.max(local));
    let half = (q * v.sqrt()).to_degrees();
    let psi = y.atan2(x).to_degrees().rem_euclid(360.0);
    Some(if half >= 180.0 {
        (0.0, 360.0)
    } else {
        (psi - half, psi + half)
    })
}

/// The noise a refit's last stage is weighted by ([`super::refit::refit_scales`]: estimated
/// about the refit, or stated) and the model levels of every curve at which its training
/// scales were set.
#[derive(Clone, Debug)]
pub(super) struct RefitNoise {
    pub noise: DiscoveryNoise,
    pub levels: Scales,
}

impl RefitNoise {
    /// The 97.5% quantile of `cand`'s intervals from the fit `lm` on the points `mask` keeps
    /// of the curves `train`: Student-t with the Satterthwaite degrees of freedom of the
    /// estimate's variance ([`crate::fit::satterthwaite_dof_of`], the rule of every interval of
    /// `validate`), the normal's for a stated noise.
    ///
    /// Why: the variance of an effect's estimate rests on the scales at the resonances, which a
    /// handful of points set, so it is itself uncertain. On eps 0.2 sets the degrees of freedom
    /// are 30-50 (q 2.02-2.07): this does not explain why the Wald standard errors there are
    /// about 15% short (standardized errors of standard deviation 1.09-1.13 with it too), nor
    /// do the secants of [`super::fit::relinearized`] (1.238 to 1.228 over 30 seeds).
    pub fn quantile(&self, cand: Candidate, lm: &LmFit, train: &[usize], mask: &Mask) -> f64 {
        let Some(vc) = &self.noise.components else {
            return t_quantile_975(f64::INFINITY);
        };
        let base = row_scales(train, mask, &self.noise.scales(&self.levels));
        let variance_at = |m: &NoiseModel| -> Option<Vec<f64>> {
            let other = DiscoveryNoise {
                model: *m,
                ..self.noise.clone()
            };
            let scales = row_scales(train, mask, &other.scales(&self.levels));
            let mut jt = lm.jacobian.clone();
            for (r, (a, b)) in base.iter().zip(&scales).enumerate().take(jt.nrows()) {
                jt.row_mut(r).scale_mut(a / b);
            }
            interval_variance(cand, &lm.params, &jt).map(|v| vec![v])
        };
        let Some(v0) = interval_variance(cand, &lm.params, &lm.jacobian) else {
            return t_quantile_975(f64::INFINITY);
        };
        let cap = lm.jacobian.nrows().saturating_sub(lm.params.len()).max(1) as f64;
        // A relative part held for the intervals has no variance.
        let relative_free = self.noise.relative_estimated && vc.covariance[1][1] > 0.0;
        let dof = satterthwaite_dof_of(
            vc,
            relative_free,
            &self.noise.model,
            &[v0],
            &variance_at,
            cap,
        );
        t_quantile_975(dof[0])
    }
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
        let q = current.quantile(train);
        let own_wald = wald_ci(c.candidate, &current.fit.lm, q);
        let problem = ProfileProblem {
            setup,
            train,
            mask: &current.mask,
            scales: &current.scales,
            cand: c.candidate,
            fit: &current.fit,
            q,
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
        let wald_arc = wald_phase_arc(c.candidate, &current.fit.lm, q);
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
            ci: over_both_basins(ci, c),
            profile: Some(profile),
            phase_arc,
            method: "hull of the profile-likelihood and Wald intervals",
        };
        return Ok((better, found));
    }
    let current = better.as_ref().unwrap_or(refit);
    let ci = wald_ci(c.candidate, &current.fit.lm, current.quantile(train));
    let found = IntervalFound {
        ci: over_both_basins(ci, c),
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
        noise: current.noise.clone(),
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
    /// ([`phase_arcs`], `q` standard errors either side); nothing for a candidate without a
    /// phase.
    pub(super) fn set_phase(&mut self, lm: &LmFit, delta: &[f64], q: f64) {
        if self.candidate.has_phase() {
            self.phase_deg = Some(Candidate::first_phase(delta).to_degrees().rem_euclid(360.0));
            self.phase_wald95_deg = phase_arcs(self, lm, q);
        }
    }
}

/// The 95% arcs of a refitted candidate's phase (degrees, [`wald_phase_arc`]) from the kept
/// fit `lm`, and the other phase basin's arc too when the phase is undetermined between it and
/// the kept fit ([`super::run::OtherStart`]): the likelihood-ratio confidence set then
/// has a piece in each basin. Empty for a candidate without a phase.
fn phase_arcs(c: &CandidateResult, lm: &LmFit, q: f64) -> Vec<(f64, f64)> {
    let mut arcs: Vec<(f64, f64)> = wald_phase_arc(c.candidate, lm, q).into_iter().collect();
    if let Some(o) = c.other_start.as_ref().filter(|o| o.phase_undetermined()) {
        arcs.extend(o.phase_wald95_deg);
    }
    arcs
}

/// `ci` widened over the other phase basin's Wald interval when the phase is undetermined
/// between it and the kept fit ([`super::run::OtherStart`]).
pub(super) fn over_both_basins(ci: Option<(f64, f64)>, c: &CandidateResult) -> Option<(f64, f64)> {
    match c.other_start.as_ref().filter(|o| o.phase_undetermined()) {
        Some(o) => ci.zip(o.ci95).map(|(a, b)| (a.0.min(b.0), a.1.max(b.1))),
        None => ci,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discover::noise::NoiseOrigin;
    use crate::fit::{estimate_noise, variance_components, Distribution, NoiseData, NoiseFreedom};

    /// The normal quantile.
    const Z: f64 = 1.959_963_984_540_054;

    /// Constant noise estimated from m independent values: its variance sigma^2 has the
    /// maximum-likelihood variance 2 sigma^4 / m, and any estimate's variance is proportional to
    /// sigma^2, so Satterthwaite's degrees of freedom are exactly m (the chi-square's): the
    /// quantile is Student-t's with m dof, whatever the Jacobian. A stated noise gives 1.96.
    #[test]
    fn the_quantile_of_an_estimated_constant_noise_is_students_with_its_count() {
        let m = 20;
        let values: Vec<f64> = (0..m).map(|i| 0.3 * (1.7 * i as f64 + 0.4).sin()).collect();
        let zeros = vec![0.0; m];
        let levels = vec![1.0; m];
        let data = NoiseData {
            correlation: None,
            jacobian: None,
            residuals: &values,
            levels: &levels,
            leverages: &zeros,
        };
        let freedom = NoiseFreedom {
            floor_min: 0.0,
            relative: false,
        };
        let (model, _) = estimate_noise(&data, freedom, Distribution::Gaussian).unwrap();
        let mut noise = DiscoveryNoise::stated(NoiseOrigin::Estimated { floor_min: 0.0 }, model);
        let rows = 60;
        let jacobian = DMatrix::from_fn(rows, 2, |i, j| {
            (0.3 * i as f64 + j as f64).cos() + 0.1 * j as f64
        });
        let lm = LmFit {
            params: vec![0.15, 0.1],
            rss: 0.0,
            residuals: vec![0.0; rows],
            jacobian,
            secant_jacobian: None,
            evaluations: 0,
        };
        let refit = |noise: DiscoveryNoise| RefitNoise {
            noise,
            levels: vec![(0..rows).map(|i| 2.0 + i as f64).collect()],
        };
        let mask = vec![vec![true; rows]];
        let cand = Candidate::MeshStiffnessVariation;
        let stated = refit(noise.clone()).quantile(cand, &lm, &[0], &mask);
        assert!((stated - Z).abs() < 1e-12, "{stated}");
        noise.components = Some(variance_components(&data, freedom, &model));
        let q = refit(noise).quantile(cand, &lm, &[0], &mask);
        let want = t_quantile_975(m as f64);
        assert!((q - want).abs() < 1e-6, "{q} against t(20) {want}");
    }

    /// A fit of a two-parameter delta alone whose Jacobian is diag(1 / sx, 1 / sy): the
    /// covariance is diag(sx^2, sy^2).
    fn fit_at(x: f64, y: f64, sx: f64, sy: f64) -> LmFit {
        LmFit {
            params: vec![x, y],
            rss: 0.0,
            residuals: vec![0.0; 2],
            jacobian: DMatrix::from_diagonal(&DVector::from_vec(vec![1.0 / sx, 1.0 / sy])),
            secant_jacobian: None,
            evaluations: 0,
        }
    }

    #[test]
    fn the_phase_arc_is_the_delta_method_on_atan2() {
        // At (0, 0.2) the phase is 90 deg and only x moves it: se = sx / A = 0.05 rad,
        // half-width 1.96 x 0.05 rad = 5.615 deg; sy (the amplitude's direction) does not count.
        let c = Candidate::MeshStiffnessVariation;
        let (lo, hi) = wald_phase_arc(c, &fit_at(0.0, 0.2, 0.01, 0.5), Z).unwrap();
        assert!((lo - (90.0 - 5.6150)).abs() < 1e-3, "{lo}");
        assert!((hi - (90.0 + 5.6150)).abs() < 1e-3, "{hi}");
        // The phase is reported in [0, 360): -90 deg is 270.
        let (lo, hi) = wald_phase_arc(c, &fit_at(0.0, -0.2, 0.01, 0.01), Z).unwrap();
        assert!((0.5 * (lo + hi) - 270.0).abs() < 1e-9);
        // A standard error of twice the amplitude (2 rad, half-width 225 deg): the arc spans
        // the circle.
        assert_eq!(
            wald_phase_arc(c, &fit_at(0.0, 0.2, 0.4, 0.01), Z),
            Some((0.0, 360.0))
        );
        assert_eq!(wald_phase_arc(c, &fit_at(0.0, 0.0, 0.01, 0.01), Z), None);
        assert_eq!(
            wald_phase_arc(Candidate::DampingLaw, &fit_at(0.0, 0.2, 0.01, 0.01), Z),
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
