//! The discovery workflow (issue 5): fit M0 on the training loads, test the residuals, rank the
//! candidate effects by a score statistic, test each with a bootstrap-calibrated likelihood
//! ratio, refit the leading ones, decide (a name, "none", "ambiguous" or "unexplained"), and
//! measure the gap before and after on training and held-out loads.

use super::decide::{Decision, Refitted, Rounds};
use super::effects::{Candidate, LIBRARY};
use super::fit::{
    fit_model, fit_ste, linear_start, ste_from_low_speed, EffectInFit, Mask, ModelFit,
};
use super::forward::{
    aperiodic_pp_range, jumps_between, predict_many, CurvePrediction, Globals, Setup, MIN_ZETA,
};
use super::linearized::{detection_names, Linearized, Statistics};
use super::noise::{
    estimate as estimate_noise, DiscoveryNoise, NoiseOrigin, NoiseSpec, PseudoInput, Scales,
    TailChoice,
};
use super::probes::{library_probes, probe_dictionary};
use super::stats::{bootstrap_p, chi2_sf, holm};
use super::windows::{windows, Window};
use crate::data::MunroData;
use crate::error::{GearError, Result};
use crate::fit::{LmFit, Stop};
use crate::numeric::min_max;
use crate::progress::Progress;
use crate::validate::MunroNoise;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::Serialize;

/// Settings of a discovery run.
#[derive(Clone, Debug)]
pub struct DiscoverOptions {
    /// Parametric bootstrap replicates under M0.
    pub bootstrap: usize,
    /// Seed of the bootstrap.
    pub seed: u64,
    /// Stated measurement noise (um, a constant); None takes the data set's statement
    /// (`dte_pp_sd_um`, rig.toml `[noise]`) or estimates it (see `super::noise`).
    pub noise_um: Option<f64>,
    /// Whether estimated noise may have Student-t tails (chosen by the data) or is Gaussian.
    pub tails: TailChoice,
    /// Family-wise error rate of the whole decision; half goes to the detection tests and half
    /// to the candidate tests (Bonferroni across the two families, Holm within each).
    pub alpha: f64,
    /// Significant candidates refitted with the full nonlinear model, leading by score first
    /// (a refit costs a few hundred simulated sweeps; a non-significant one is not needed); the
    /// significant one with the largest dictionary LR is refitted as well when these miss it,
    /// and every other significant one when these leave the discrepancy unexplained.
    pub refit_top: usize,
    /// Levenberg-Marquardt iterations of a candidate refit.
    pub refit_iterations: usize,
    /// |cos| between two candidates' fitted residual directions above which they are ambiguous.
    pub collinear_cos: f64,
    /// Profile the phase of the phase-carrying candidate a decision rests on as well
    /// (`super::profile::ProfileProblem::phase_arc`: up to twelve more all-load fits, tens
    /// of seconds with a stiffness variation); off, its phase has the Wald arc only.
    pub phase_profile: bool,
    /// Which procedure decides.
    pub procedure: Procedure,
    /// The errors' correlation along speed (the likelihood procedure only).
    pub correlation: super::training::Correlation,
}

/// The procedure of a discovery run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Procedure {
    /// Score-ranked probes with bootstrap-calibrated detection tests (the current default).
    Tests,
    /// One likelihood: every fit by the estimation engine, likelihood ratios calibrated by a
    /// parametric bootstrap, a name only if it predicts the held-out loads
    /// (`super::procedure`).
    Likelihood,
}

impl Default for DiscoverOptions {
    fn default() -> Self {
        DiscoverOptions {
            bootstrap: 1999,
            seed: 12345,
            noise_um: None,
            tails: TailChoice::Auto,
            alpha: 0.05,
            refit_top: 2,
            refit_iterations: 12,
            collinear_cos: 0.95,
            phase_profile: false,
            procedure: Procedure::Tests,
            correlation: super::training::Correlation::Auto,
        }
    }
}

/// One candidate's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct CandidateResult {
    pub name: &'static str,
    #[serde(skip)]
    pub candidate: Candidate,
    /// Whether the data can determine it (see `note`).
    pub identifiable: bool,
    pub note: Option<String>,
    /// Why the candidate failed, when something inside it did (a probe or a refit whose
    /// model leaves its valid range, a sweep that does not settle, a fit that does not
    /// converge): it is reported "failed, because ..." without an estimate, and the run goes
    /// on with the others ([`CandidateResult::fail`]).
    pub failed: Option<String>,
    /// Score statistic max_k (r . d_k)^2 / |d_k|^2 over the probes (projected residual r).
    pub score: f64,
    /// Its chi-square(dim) tail, Wilson-Hilferty; for ranking only.
    pub score_p_approx: f64,
    /// Likelihood-ratio statistic over the probe dictionary (linearised nuisance refit).
    pub lr: f64,
    /// Bootstrap p-value of `lr` under M0, and Holm-adjusted across identifiable candidates.
    pub p_value: Option<f64>,
    pub p_holm: Option<f64>,
    /// What `estimate` is.
    pub estimate_name: &'static str,
    /// Refitted estimate with a 95% interval (over both basins when the phase is undetermined,
    /// see [`OtherStart`]); None unless refitted. The Wald interval (delta method), or for the
    /// effect a decision rests on the hull of the profile-likelihood and Wald intervals (see
    /// `ci95_method` and `profiled_refit`).
    pub estimate: Option<f64>,
    pub ci95: Option<(f64, f64)>,
    /// How `ci95` was found.
    pub ci95_method: &'static str,
    /// The Wald and profile-likelihood intervals behind a hull `ci95` (a profile side is None
    /// where the profile did not rise within its fits).
    pub wald_ci95: Option<(f64, f64)>,
    pub profile_ci95: Option<(Option<f64>, Option<f64>)>,
    /// The 97.5% quantile its intervals are formed with: Student-t with the Satterthwaite
    /// degrees of freedom of the estimate's variance when the noise is estimated, 1.96 when
    /// stated (`super::interval::RefitNoise::quantile`).
    pub interval_quantile: Option<f64>,
    /// Refitted delta and the refit's drop in residual sum of squares (sigma^2 units).
    pub delta: Option<Vec<f64>>,
    pub refit_lr: Option<f64>,
    /// Zeta and omega_n (Hz) of the refit, which move with the effect.
    pub refit_zeta: Option<f64>,
    pub refit_omega_n_hz: Option<f64>,
    /// A phase-carrying candidate's best refit in another phase basin (a distinct minimum:
    /// each phase outside the other's Wald arc), when one ended there.
    pub other_start: Option<OtherStart>,
    /// A refitted phase-carrying candidate's phase psi of its first (A cos psi, A sin psi)
    /// pair, degrees in [0, 360): the stiffness variation's against the STE, the 2nd STE
    /// harmonic's against the first (of the harmonic, on its own time scale), the torque
    /// ripple's against the mesh.
    pub phase_deg: Option<f64>,
    /// Its 95% Wald arcs, degrees, (lo, hi) with the phase between (hi may exceed 360, lo fall
    /// below 0): one, or two when the phase is undetermined between two basins
    /// ([`OtherStart::phase_undetermined`]); (0, 360) when the arc spans the circle.
    pub phase_wald95_deg: Vec<(f64, f64)>,
    /// With [`DiscoverOptions::phase_profile`], for the candidate a decision rests on: the
    /// phase's 95% arc from its profile likelihood, the hull with its own Wald arc, in the
    /// convention of `phase_wald95_deg` (the other basin's Wald arc, when the phase is
    /// undetermined, stays in `phase_wald95_deg`).
    pub phase_profile95_deg: Option<(f64, f64)>,
}

/// The fit a phase-carrying candidate's refit reached from the other phase basin and did not keep
/// (see `refit_candidate`): where it ended, and how much worse it fits the training loads.
/// When the two are distinct minima within chi2(0.95; 1) of each other, the candidate's
/// reported interval is the hull of both fits' intervals: the likelihood-ratio confidence set
/// then has a piece in each basin, and the kept fit's Wald interval covers only its own.
#[derive(Clone, Debug, Serialize)]
pub struct OtherStart {
    pub delta: Vec<f64>,
    /// Its -2 log-likelihood minus the kept fit's, both before the last stage (on the same
    /// points), each with the last stage's noise model evaluated at its own predicted level
    /// (`super::refit::Refit::other_basin`); with equal levels, the increase of the weighted
    /// residual sum of squares in sigma^2. Below chi2(0.95; 1) = 3.84, the training loads do not
    /// determine the phase.
    pub deviance_increase: f64,
    /// Its own 95% Wald interval of the estimate.
    pub ci95: Option<(f64, f64)>,
    /// Its own 95% Wald arc of the phase, degrees (see [`CandidateResult::phase_wald95_deg`]).
    pub phase_wald95_deg: Option<(f64, f64)>,
}

impl CandidateResult {
    /// A candidate with nothing found yet.
    pub(super) fn untested(candidate: Candidate, identifiable: bool) -> Self {
        CandidateResult {
            name: candidate.name(),
            candidate,
            identifiable,
            note: None,
            failed: None,
            score: f64::NAN,
            score_p_approx: f64::NAN,
            lr: f64::NAN,
            p_value: None,
            p_holm: None,
            estimate_name: candidate.estimate_name(),
            estimate: None,
            ci95: None,
            ci95_method: "Wald",
            wald_ci95: None,
            profile_ci95: None,
            interval_quantile: None,
            delta: None,
            refit_lr: None,
            refit_zeta: None,
            refit_omega_n_hz: None,
            other_start: None,
            phase_deg: None,
            phase_wald95_deg: Vec::new(),
            phase_profile95_deg: None,
        }
    }

    /// Record that the candidate failed `because` (a clause: "its refit failed: ..."), and
    /// drop what a refit of it had found: a failed candidate has no estimate to report.
    pub(super) fn fail(&mut self, because: String) {
        self.failed = Some(because);
        self.estimate = None;
        self.ci95 = None;
        self.ci95_method = "Wald";
        self.wald_ci95 = None;
        self.profile_ci95 = None;
        self.interval_quantile = None;
        self.delta = None;
        self.refit_lr = None;
        self.refit_zeta = None;
        self.refit_omega_n_hz = None;
        self.other_start = None;
        self.phase_deg = None;
        self.phase_wald95_deg.clear();
        self.phase_profile95_deg = None;
    }
}

impl OtherStart {
    /// Whether it fits within chi2(0.95; 1) = 3.84 of the kept fit (-2 log L) (it is a distinct
    /// minimum from it: `super::refit::distinct_minima`).
    pub fn phase_undetermined(&self) -> bool {
        self.deviance_increase < super::ambiguity::CHI2_95_1DF
    }
}

/// A detection test.
#[derive(Clone, Debug, Serialize)]
pub struct TestResult {
    pub name: String,
    pub statistic: f64,
    pub p_value: Option<f64>,
    pub p_holm: Option<f64>,
}

/// Residual size of a model on a set of loads.
#[derive(Clone, Debug, Serialize)]
pub struct Gap {
    /// RMS residual over the compared points, um.
    pub rms_um: f64,
    /// Largest RMS residual within one Omega window, um, and that window.
    pub worst_window_rms_um: f64,
    pub worst_window: Option<String>,
    pub points: usize,
    /// (load N, RMS um, points) per load: one load on another branch of coexisting steady
    /// states can dominate the RMS, and this shows which.
    pub per_load: Vec<(f64, f64, usize)>,
}

/// Gap on training and held-out loads.
#[derive(Clone, Debug, Serialize)]
pub struct GapSet {
    pub training: Gap,
    pub held_out: Option<Gap>,
}

/// Residual curve of one load for the plots: (speed rpm, Omega, residual um, kept).
#[derive(Clone, Debug, Serialize)]
pub struct ResidualCurve {
    pub load_n: f64,
    pub training: bool,
    pub points: Vec<(f64, f64, f64, bool)>,
}

/// The points of one load excluded from the tests, described: where M0 predicts non-period-1
/// motion (or a jump) a point-wise residual says nothing (a chaotic pp is one observation
/// window's sample and depends on the history), but a measured pp far outside every pp M0
/// produces there is a discrepancy the tests cannot see: the report shows both ranges.
#[derive(Clone, Debug, Serialize)]
pub struct ExcludedPoints {
    pub load_n: f64,
    pub points: usize,
    /// Of those, points where M0 predicts non-period-1 motion (the rest straddle a jump).
    pub non_period1: usize,
    /// Smallest and largest measured pp DTE over the excluded points, um.
    pub measured_range_um: (f64, f64),
    /// Smallest and largest M0 prediction (its first observation window) over the same
    /// points, um.
    pub predicted_range_um: (f64, f64),
    /// Smallest and largest M0 pp DTE over the same points, um: the predicted pp, and at a
    /// chaotic or aperiodic point also the pp of each of 32 later observation windows
    /// (`super::forward::aperiodic_pp_range`), since the measured pp there is one window out
    /// of that distribution.
    pub model_range_um: (f64, f64),
    /// The same over M0 and the models at the ends of its 95% confidence region in zeta and
    /// omega_n (`confidence_ends`), um; computed only when a measured point lies far outside
    /// `model_range_um` at some load, and None otherwise or when no end could be predicted.
    pub region_range_um: Option<(f64, f64)>,
    /// Where the ends that widened `region_range_um` were clamped (`CLAMPED_ZETA`,
    /// `CLAMPED_OMEGA_N`, `CLAMPED_STE`): past those the region is the linearisation's, not
    /// the data's, and with zeta at the floor an end's resonance can reach almost any pp, so a
    /// point within the range says less. Empty when none was (or no range was widened).
    pub region_clamped: Vec<&'static str>,
    /// Excluded points whose measured pp lies outside the widest range computed
    /// (`region_range_um`, else `model_range_um`) by more than 3 noise scales (at its largest
    /// pp) plus 10% of that pp: a gross disagreement, beyond the noise, beyond any window of
    /// the motion of any fit the data allow, and beyond the onset of non-period-1 motion moving
    /// a little with the parameters.
    pub outside_model_range: usize,
}

/// STE amplitude (um) of curve `i` under `fit`: fitted with it on a training curve, fitted
/// alone (`held`) on a held-out one.
fn curve_ste(i: usize, train: &[usize], fit: &ModelFit, held: &[HeldFit]) -> Option<f64> {
    match train.iter().position(|&t| t == i) {
        Some(k) => fit.ste_um.get(k).copied(),
        None => held.iter().find(|h| h.0 == i).map(|h| h.1),
    }
}

/// [`ExcludedPoints`] of every load that has excluded points, with M0's range over the
/// predicted pp and, at its non-periodic points, over their observation windows; where a
/// measured point lies far outside that, also over the models at the ends of M0's confidence
/// region ([`confidence_ends`]).
fn excluded_by_load(setup: &Setup, m0: &M0Fit, train: &[usize]) -> Result<Vec<ExcludedPoints>> {
    let dropped: Vec<(usize, Vec<usize>)> = m0
        .mask
        .iter()
        .enumerate()
        .map(|(i, m)| (i, (0..m.len()).filter(|&j| !m[j]).collect::<Vec<_>>()))
        .filter(|(_, d)| !d.is_empty())
        .collect();
    let mut at_m0 = Vec::with_capacity(dropped.len());
    for (i, d) in &dropped {
        let ste = m0_ste(setup, m0, train, *i)?;
        at_m0.push(model_range(setup, *i, &m0.m0, ste, &m0.f0[*i], d)?);
    }
    let far = |ranges: &[(f64, f64)]| -> Vec<usize> {
        dropped
            .iter()
            .zip(ranges)
            .map(|((i, d), &r)| far_from(setup, &m0.noise, *i, d, r))
            .collect()
    };
    let far_at_m0 = far(&at_m0);
    let mut region = None;
    let mut clamped: Vec<&'static str> = Vec::new();
    if far_at_m0.iter().any(|&n| n > 0) {
        let mut widened = at_m0.clone();
        let mut reached = 0;
        for end in confidence_ends(m0, train) {
            // The ends only widen the range: one whose prediction fails (its zeta at the
            // floor, say) is left out rather than ending the run.
            let Ok(ranges) = ranges_at(setup, m0, &end.fit, train, &dropped) else {
                continue;
            };
            for (r, e) in widened.iter_mut().zip(ranges) {
                *r = (r.0.min(e.0), r.1.max(e.1));
            }
            for c in end.clamped {
                if !clamped.contains(&c) {
                    clamped.push(c);
                }
            }
            reached += 1;
        }
        region = (reached > 0).then_some(widened);
    }
    let outside = region.as_deref().map_or(far_at_m0, far);
    Ok(dropped
        .iter()
        .enumerate()
        .map(|(k, (i, d))| {
            let c = &setup.curves[*i];
            let p = &m0.f0[*i];
            ExcludedPoints {
                load_n: c.load_n,
                points: d.len(),
                non_period1: d.iter().filter(|&&j| !p.period1[j]).count(),
                measured_range_um: min_max(d.iter().map(|&j| c.dte_pp_um[j]))
                    .unwrap_or((f64::NAN, f64::NAN)),
                predicted_range_um: min_max(d.iter().map(|&j| p.dte_pp_um[j]))
                    .unwrap_or((f64::NAN, f64::NAN)),
                model_range_um: at_m0[k],
                region_range_um: region.as_ref().map(|r| r[k]),
                region_clamped: clamped.clone(),
                outside_model_range: outside[k],
            }
        })
        .collect())
}

/// M0's STE amplitude (um) of curve `i`: fitted with M0 on a training load, alone on a
/// held-out one.
fn m0_ste(setup: &Setup, m0: &M0Fit, train: &[usize], i: usize) -> Result<f64> {
    curve_ste(i, train, &m0.m0, &m0.held0).ok_or_else(|| {
        GearError::Numerical(format!(
            "no M0 STE amplitude for load {} N",
            setup.curves[i].load_n
        ))
    })
}

/// [`model_range`] of each load of `dropped` (curve, excluded points) under `end`: a training
/// load with `end`'s STE, a held-out one with its STE fitted again at `end`'s zeta and
/// omega_n (from M0's, under M0's final noise scales).
fn ranges_at(
    setup: &Setup,
    m0: &M0Fit,
    end: &ModelFit,
    train: &[usize],
    dropped: &[(usize, Vec<usize>)],
) -> Result<Vec<(f64, f64)>> {
    dropped
        .par_iter()
        .map(|(i, d)| {
            let ste = match curve_ste(*i, train, end, &[]) {
                Some(e) => e,
                None => {
                    let start = m0_ste(setup, m0, train, *i)?;
                    let g = end.globals;
                    fit_ste(setup, *i, &m0.mask, &m0.scales, g, &end.effect, start)?.0
                }
            };
            let pred = super::forward::predict(setup, *i, end.globals, ste, &end.effect)?;
            model_range(setup, *i, end, ste, &pred, d)
        })
        .collect()
}

/// Smallest and largest pp DTE of `fit` (curve `i` predicted as `pred`, STE `ste` um) over the
/// points `dropped`: the predicted pp, and at a chaotic or aperiodic point the pp of each
/// observation window as well ([`aperiodic_pp_range`]).
fn model_range(
    setup: &Setup,
    i: usize,
    fit: &ModelFit,
    ste: f64,
    pred: &CurvePrediction,
    dropped: &[usize],
) -> Result<(f64, f64)> {
    let windows = aperiodic_pp_range(setup, i, fit.globals, ste, &fit.effect, pred)?;
    let predicted = min_max(dropped.iter().map(|&j| pred.dte_pp_um[j])).ok_or_else(|| {
        GearError::Numerical(format!(
            "no excluded point at load {} N",
            setup.curves[i].load_n
        ))
    })?;
    Ok(dropped
        .iter()
        .filter_map(|&j| windows[j])
        .fold(predicted, |(lo, hi), (a, b)| (lo.min(a), hi.max(b))))
}

/// Of the points `dropped` of curve `i`, those whose measured pp lies outside the model range
/// `range` (um) by more than 3 noise scales (at its largest pp) plus 10% of that pp.
pub(super) fn far_from(
    setup: &Setup,
    noise: &DiscoveryNoise,
    i: usize,
    dropped: &[usize],
    range: (f64, f64),
) -> usize {
    let top = range.1.abs();
    let margin = |j: usize| 3.0 * noise.scale_at(i, j, top) + 0.1 * top;
    dropped
        .iter()
        .filter(|&&j| {
            let v = setup.curves[i].dte_pp_um[j];
            v > range.1 + margin(j) || v < range.0 - margin(j)
        })
        .count()
}

/// chi2(0.95; 2) = -2 ln 0.05: the 95% joint confidence region of M0's two shared parameters.
const CHI2_95_2DOF: f64 = 5.991_464_547_107_979;

/// M0 at the ends of the 95% confidence region of its shared parameters (zeta, omega_n) along
/// each of them, the training STE amplitudes at their conditional best (the points
/// theta +- c Sigma e_k / sqrt(Sigma_kk), c^2 = chi2(0.95; 2), Sigma the inverse Fisher
/// information of M0's training fit under the final noise; linearised, so parameter points,
/// not refits): the models the data allow that move the resonances most. The excluded-points rule asks whether any fit the data allow reaches a
/// measured point, not whether the fitted M0 does. On a coarse grid M0's damping is poorly
/// determined (300 rpm grid, null seed 4: zeta 0.0249 against a true 0.0175), and a point just
/// beyond the fitted M0's range lies within that of a fit the data allow. Empty when the
/// information is singular. An end's zeta is clamped at the fits' floor [`MIN_ZETA`], its
/// omega_n at half M0's, an STE amplitude at a tenth of M0's: past those the region is the
/// linearisation's, not the data's.
fn confidence_ends(m0: &M0Fit, train: &[usize]) -> Vec<RegionEnd> {
    let mut j = m0.lin.jac_train.clone();
    for (r, s) in row_scales(train, &m0.mask, &m0.scales).iter().enumerate() {
        j.row_mut(r).unscale_mut(*s);
    }
    let Some(cov) = (j.transpose() * &j).try_inverse() else {
        return Vec::new();
    };
    let theta = &m0.m0.lm.params;
    let c = CHI2_95_2DOF.sqrt();
    let mut ends = Vec::with_capacity(4);
    for k in 0..2 {
        let sd = cov[(k, k)].max(0.0).sqrt();
        if !(sd > 0.0 && sd.is_finite()) {
            continue;
        }
        for sign in [-1.0, 1.0] {
            let p: Vec<f64> = theta
                .iter()
                .enumerate()
                .map(|(r, &t)| t + sign * c * cov[(r, k)] / sd)
                .collect();
            let mut clamped = Vec::new();
            // `value` held at least at `bound`, and `why` recorded where that moved it.
            let mut at_least = |value: f64, bound: f64, why: &'static str| {
                let held = value.max(bound);
                if held != value && !clamped.contains(&why) {
                    clamped.push(why);
                }
                held
            };
            let mut end = m0.m0.clone();
            end.globals = Globals {
                zeta: at_least(p[0], MIN_ZETA, CLAMPED_ZETA),
                omega_n_hz: at_least(p[1], 0.5 * theta[1], CLAMPED_OMEGA_N),
            };
            // The STE's sign is a phase the model ignores (it takes |e|).
            end.ste_um = p[2..]
                .iter()
                .zip(&theta[2..])
                .map(|(&e, &e0)| at_least(e.abs(), 0.1 * e0.abs(), CLAMPED_STE))
                .collect();
            ends.push(RegionEnd { fit: end, clamped });
        }
    }
    ends
}

/// How an end of M0's confidence region was clamped ([`confidence_ends`]), in the report's words.
pub const CLAMPED_ZETA: &str = "zeta at the fits' floor";
pub const CLAMPED_OMEGA_N: &str = "omega_n at half M0's";
pub const CLAMPED_STE: &str = "an STE amplitude at a tenth of M0's";

/// A model at an end of M0's confidence region, and where its parameters were clamped (empty:
/// the end as the linearisation gives it).
struct RegionEnd {
    fit: ModelFit,
    clamped: Vec<&'static str>,
}

/// Excluded points, over all loads, far outside M0's range, widened over its confidence
/// region where computed (see [`ExcludedPoints::outside_model_range`]).
fn far_outside(excluded: &[ExcludedPoints]) -> usize {
    excluded.iter().map(|e| e.outside_model_range).sum()
}

/// Everything a discovery run found.
#[derive(Clone, Debug, Serialize)]
pub struct Discovery {
    /// A candidate name, "none", "ambiguous" or "unexplained".
    pub effect: String,
    pub ambiguous_with: Vec<String>,
    /// The best candidate when the effect is "unexplained" (it did not remove the discrepancy on
    /// the training loads: chi-square after its refit still significant).
    pub closest_candidate: Option<String>,
    /// A discrepancy is detected: by the tests (`detected_by_tests`) or by excluded points far
    /// outside M0's range ([`Discovery::detected_by_excluded_points`]).
    pub detected: bool,
    /// Some test of M0, a detection test or a candidate's own, is significant after Holm over
    /// all of them at alpha / 2.
    pub detected_by_tests: bool,
    /// Candidates significant on their own tests on a set where no discrepancy is detected:
    /// not refitted and not named, since a name needs a detected discrepancy (every name the
    /// null studies gave without one was false).
    pub significant_undetected: Vec<String>,
    /// When the answer is "ambiguous" because the held-out loads prefer another candidate
    /// than the training loads: that candidate (its refit predicts the held-out loads, the
    /// leading one's does not).
    pub held_out_prefers: Option<String>,
    /// Detection tests under M0, their `p_holm` over every test of M0 (these and the
    /// candidates' own), the family `detected_by_tests` decides on.
    pub detection: Vec<TestResult>,
    /// Detection tests on the residuals after adding the chosen effect (same null distribution),
    /// Holm-adjusted among themselves.
    pub post_fit: Vec<TestResult>,
    pub candidates: Vec<CandidateResult>,
    /// The noise the tests and fits use: stated, or estimated (floor, relative part, tails).
    pub noise: DiscoveryNoise,
    /// Smallest and largest noise scale over the kept points (um), at M0's levels.
    pub noise_range_um: (f64, f64),
    pub zeta_m0: f64,
    pub omega_n_hz_m0: f64,
    /// The rig's design load (N), to which the damping law and the torque ripple refer.
    pub design_load_n: f64,
    pub training_loads_n: Vec<f64>,
    pub held_out_loads_n: Vec<f64>,
    /// STE amplitude (um) fitted alone at each held-out load: (load N, before, after).
    pub held_out_ste_um: Vec<(f64, f64, f64)>,
    pub excluded_points: usize,
    /// Per load with excluded points: how the data there compare with M0 (not tested).
    pub excluded_by_load: Vec<ExcludedPoints>,
    pub gap_before: GapSet,
    /// Gap with the best refitted candidate: the named effect, or, when the answer is
    /// "unexplained" or "ambiguous", the candidate that came closest (`gap_after_model` says
    /// which); M0's own gap when no candidate was refitted.
    pub gap_after: GapSet,
    pub gap_after_model: String,
    pub windows: Vec<Window>,
    pub residuals_before: Vec<ResidualCurve>,
    /// Residuals with the leading significant candidate refitted (M0's when there is none).
    pub residuals_after: Vec<ResidualCurve>,
    pub bootstrap: usize,
    /// The errors' correlation along speed of M0's fit (likelihood procedure).
    pub noise_correlation: Option<crate::fit::CorrelationFit>,
    /// Whether the best candidate predicts the held-out loads better than M0 (likelihood
    /// procedure, with held-out loads).
    pub prediction_check: Option<PredictionCheck>,
}

/// The held-out loads' log-likelihood under M0 and under the best candidate (each with the
/// loads' STE fitted alone, under the training loads' noise): a name must predict.
#[derive(Clone, Debug, Serialize)]
pub struct PredictionCheck {
    pub candidate: &'static str,
    pub held_out_log_likelihood_m0: f64,
    pub held_out_log_likelihood_candidate: f64,
}

impl PredictionCheck {
    /// Whether the candidate predicts the held-out loads better than M0.
    pub fn candidate_predicts(&self) -> bool {
        self.held_out_log_likelihood_candidate > self.held_out_log_likelihood_m0
    }
}

/// The candidate an answer rests on: the named one, else the closest, else the first of the
/// ambiguous ones (None when the answer names no candidate).
fn leading_candidate(
    effect: &str,
    closest: Option<&str>,
    ambiguous_with: &[String],
) -> Option<&'static str> {
    let in_library = |name: &str| LIBRARY.iter().map(|c| c.name()).find(|n| *n == name);
    in_library(effect)
        .or_else(|| closest.and_then(in_library))
        .or_else(|| ambiguous_with.first().and_then(|a| in_library(a)))
}

impl Discovery {
    /// The refitted candidate the answer rests on, whose refit the post-fit tests and the
    /// gap after are about; None without a refit.
    pub fn leading_refit(&self) -> Option<&'static str> {
        let refitted = !self.post_fit.is_empty();
        refitted
            .then(|| {
                leading_candidate(
                    &self.effect,
                    self.closest_candidate.as_deref(),
                    &self.ambiguous_with,
                )
            })
            .flatten()
    }

    /// The candidates a decision rested on (their profile-likelihood interval was taken), in
    /// library order: more than one when a profile demoted its candidate and the decision was
    /// made again.
    pub fn decided_on(&self) -> Vec<&'static str> {
        self.candidates
            .iter()
            .filter(|c| c.profile_ci95.is_some())
            .map(|c| c.name)
            .collect()
    }

    /// Excluded points, over all loads, whose measured pp lies far outside M0's range there
    /// (see [`ExcludedPoints::outside_model_range`]): the run warns when there are any.
    pub fn excluded_far_outside(&self) -> usize {
        far_outside(&self.excluded_by_load)
    }

    /// Some excluded point lies far outside every pp M0, or a model at the ends of its
    /// confidence region, predicts at its load. Not a calibrated test: on 600 null seeds on
    /// the 50 rpm grid and 200 on a 300 rpm grid it fired on none, while a chaotic or subharmonic region
    /// whose measured pp is far from anything M0 produces is a discrepancy the point-wise tests
    /// cannot see.
    pub fn detected_by_excluded_points(&self) -> bool {
        self.excluded_far_outside() > 0
    }

    /// M0's fitted zeta sits at the fits' lower bound `MIN_ZETA` (within 5%): M0 reaches for
    /// the least damping it may use, itself a sign that it lacks something (on the hidden-eps
    /// sets M0 lands there, with the true zeta 0.0175; on null sets it does not).
    pub fn m0_zeta_at_lower_bound(&self) -> bool {
        self.zeta_m0 < 1.05 * MIN_ZETA
    }

    /// No training curve at the design load (within 0.5%): M0 is fitted to the highest load
    /// in its place.
    pub fn design_load_missing(&self) -> bool {
        !self
            .training_loads_n
            .iter()
            .any(|l| (l / self.design_load_n - 1.0).abs() <= 0.005)
    }
}

/// Training loads: every other load from the highest (the design load) down; the rest are
/// held out (with one load there is nothing to hold out).
pub fn split(n: usize) -> (Vec<usize>, Vec<usize>) {
    let train = (0..n).filter(|i| i % 2 == 0).collect();
    let held = (0..n).filter(|i| i % 2 == 1).collect();
    (train, held)
}

/// All predictions of a model: training curves with their fitted STE, held-out curves with an
/// STE fitted alone (from `held_start`, else the quasi-static estimate). Returns predictions of
/// every curve and, per held-out curve, its STE amplitude and sensitivity column.
pub(super) fn predict_all(
    setup: &Setup,
    fit: &ModelFit,
    train: &[usize],
    held: &[usize],
    mask: &Mask,
    scales: &Scales,
    held_start: Option<&[HeldFit]>,
) -> Result<(Vec<CurvePrediction>, Vec<HeldFit>)> {
    let mut preds: Vec<Option<CurvePrediction>> = vec![None; setup.curves.len()];
    for (p, &i) in predict_many(setup, train, fit.globals, &fit.ste_um, &fit.effect)?
        .into_iter()
        .zip(train)
    {
        preds[i] = Some(p);
    }
    let held_fits: Vec<Result<(HeldFit, CurvePrediction)>> = held
        .par_iter()
        .map(|&i| {
            let start = held_start
                .and_then(|h| h.iter().find(|x| x.0 == i))
                .map_or_else(|| ste_from_low_speed(setup, i, fit.globals), |x| x.1);
            let (e, lm) = fit_ste(setup, i, mask, scales, fit.globals, &fit.effect, start)?;
            let p = super::forward::predict(setup, i, fit.globals, e, &fit.effect)?;
            // The sensitivity of the curve (um per um of STE) from that of its standardized
            // residuals.
            let kept = (0..mask[i].len()).filter(|&j| mask[i][j]);
            let sens = DVector::from_iterator(
                lm.jacobian.nrows(),
                lm.jacobian
                    .column(0)
                    .iter()
                    .zip(kept)
                    .map(|(d, j)| -d * scales[i][j]),
            );
            Ok(((i, e, sens), p))
        })
        .collect();
    let mut held_out = Vec::new();
    for h in held_fits {
        let (hf, p) = h?;
        preds[hf.0] = Some(p);
        held_out.push(hf);
    }
    let preds = preds
        .into_iter()
        .map(|p| p.ok_or_else(|| GearError::Numerical("a load was not predicted".into())))
        .collect::<Result<Vec<_>>>()?;
    Ok((preds, held_out))
}

/// A held-out curve's index, fitted STE (um) and its sensitivity (um per um of STE) on its
/// kept points.
pub(super) type HeldFit = (usize, f64, DVector<f64>);

/// Widest interval between two speeds, relative to the higher, across which any change of
/// regime with a step over 10 noise scales drops both points: the studies' grids (50 and
/// 100 rpm, 1.7-3.3% at Munro's resonance) and the rule they were calibrated with. A boundary
/// there is within a few per cent of both points, about what a refit moves it by; kept, such
/// points changed M0 a lot (on a DOP853-made eps 0.2 set, relative noise, seed 3, M0's zeta
/// went from 0.060 to 0.024 and the stiffness variation was no longer found).
const NARROW_INTERVAL: f64 = 0.05;

/// Mask: drop points whose predicted steady state is not period-1 (chaotic, subharmonic: the
/// measured pp there depends on history beyond the model) and the two points around every
/// predicted jump larger than 10 noise scales (at the higher of the two levels): a change of
/// impact regime (Fig. 9: none, single-sided, double-sided) between neighbouring speeds. A
/// jump displaced by one grid step would dominate every statistic without saying anything
/// about a missing effect. Across an interval wider than [`NARROW_INTERVAL`] the change must
/// also be discontinuous in the sweep ([`jumps_between`]): a coarse grid's change along one
/// continuous branch (on a 500 rpm grid, the design load's resonance peak, at which the teeth
/// separate for a moment) moves smoothly with the parameters and carries zeta; dropping its
/// three points left M0 without zeta, which ran to its floor. `curves[k]` is the curve
/// `preds[k]` predicts.
pub(super) fn make_mask(
    setup: &Setup,
    preds: &[CurvePrediction],
    curves: &[usize],
    noise: &DiscoveryNoise,
) -> Result<Mask> {
    preds
        .par_iter()
        .zip(curves)
        .map(|(p, &i)| {
            let n = p.dte_pp_um.len();
            let mut m: Vec<bool> = p.period1.clone();
            for j in 1..n {
                // A jump is a change of contact regime with a step in pp; a resonance peak
                // in contact is steep too but smooth in the parameters, and it carries zeta.
                // The jump onto the back flank keeps the teeth separated on both sides: on a
                // rattle-regime set (b x 0.7, seed 16, 945 N) single-sided impacts at 30 um
                // jump to double-sided ones at 157 um, and a refit whose jump came one speed
                // early kept the point between, 120 um off, which alone made it "unexplained".
                let regime_changed = p.separated[j] != p.separated[j - 1]
                    || p.back_contact[j] != p.back_contact[j - 1];
                let (a, b) = (p.dte_pp_um[j - 1], p.dte_pp_um[j]);
                let top = a.abs().max(b.abs());
                let step = 10.0 * noise.scale_at(i, j, top).max(noise.scale_at(i, j - 1, top));
                let speeds = &setup.curves[i].speeds_rpm;
                let narrow = speeds[j] - speeds[j - 1] <= NARROW_INTERVAL * speeds[j];
                if regime_changed
                    && (b - a).abs() > step
                    && (narrow || jumps_between(p, speeds, j, step)?)
                {
                    m[j] = false;
                    m[j - 1] = false;
                }
            }
            Ok(m)
        })
        .collect()
}

pub(super) fn gap(
    setup: &Setup,
    idx: &[usize],
    preds: &[CurvePrediction],
    mask: &Mask,
    omega: &[Vec<f64>],
    ws: &[Window],
) -> Gap {
    let mut all = Vec::new();
    let mut per_w = vec![Vec::new(); ws.len()];
    let mut per_load = Vec::new();
    let mut per_load_res: Vec<Vec<f64>> = Vec::new();
    for &i in idx {
        let mut this = Vec::new();
        for (j, y) in setup.curves[i].dte_pp_um.iter().enumerate() {
            if mask[i][j] {
                let r = y - preds[i].dte_pp_um[j];
                all.push(r);
                this.push(r);
                for (k, w) in ws.iter().enumerate() {
                    if w.contains(omega[i][j]) {
                        per_w[k].push(r);
                    }
                }
            }
        }
        per_load_res.push(this);
    }
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    for (&i, v) in idx.iter().zip(&per_load_res) {
        per_load.push((setup.curves[i].load_n, rms(v), v.len()));
    }
    let worst = per_w
        .iter()
        .enumerate()
        .filter(|(_, v)| v.len() >= 3)
        .map(|(k, v)| (k, rms(v)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    Gap {
        rms_um: rms(&all),
        worst_window_rms_um: worst.map_or(0.0, |w| w.1),
        worst_window: worst.map(|w| ws[w.0].label.to_string()),
        points: all.len(),
        per_load,
    }
}

pub(super) fn residual_curves(
    setup: &Setup,
    train: &[usize],
    preds: &[CurvePrediction],
    mask: &Mask,
    omega: &[Vec<f64>],
) -> Vec<ResidualCurve> {
    setup
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| ResidualCurve {
            load_n: c.load_n,
            training: train.contains(&i),
            points: (0..c.speeds_rpm.len())
                .map(|j| {
                    (
                        c.speeds_rpm[j],
                        omega[i][j],
                        c.dte_pp_um[j] - preds[i].dte_pp_um[j],
                        mask[i][j],
                    )
                })
                .collect(),
        })
        .collect()
}

/// Detection p-values of `s` against the replicates (NaN statistics skipped), Holm-adjusted over
/// the family of these tests and `others` (raw p-values of further tests of the same null), and
/// the smallest adjusted p-value of the whole family.
///
/// Under M0 the family is every test of M0: the detection tests and the candidates' own tests
/// all test the same null (M0 explains the curves), so a discrepancy is detected when Holm over
/// all of them rejects at alpha / 2. A targeted test sees what the omnibus ones miss: a damping
/// law (gamma -1 on five loads, 100 rpm grid, constant noise) gave its candidate test p = 0.001
/// on 10 of 10 seeds while the detection tests alone reached Holm's level on 3, and with
/// detection by those alone it was named on 3/10 (relative noise 0/10) where it had been 18/20.
/// The null names without a detected discrepancy that led to that rule (constant noise, seeds
/// 1053, 1174, 1267) had candidate p-values of 0.004-0.006, above Holm's threshold over every
/// test. After a refit the family is the detection tests alone (`others` empty).
pub(super) fn detection_tests(
    names: &[String],
    s: &Statistics,
    reps: &[Statistics],
    others: &[f64],
) -> (Vec<TestResult>, f64) {
    let p: Vec<Option<f64>> = s
        .detection
        .iter()
        .enumerate()
        .map(|(k, &t)| {
            if t.is_nan() {
                return None;
            }
            let null: Vec<f64> = reps
                .iter()
                .map(|r| r.detection[k])
                .filter(|x| !x.is_nan())
                .collect();
            Some(bootstrap_p(t, &null))
        })
        .collect();
    let family: Vec<f64> = p.iter().flatten().chain(others).copied().collect();
    let adj = holm(&family);
    let least = adj.iter().copied().fold(1.0, f64::min);
    let mut it = adj.into_iter();
    let tests = names
        .iter()
        .zip(&s.detection)
        .zip(&p)
        .map(|((n, &t), p)| TestResult {
            name: n.clone(),
            statistic: t,
            p_value: *p,
            p_holm: p.and_then(|_| it.next()),
        })
        .collect();
    (tests, least)
}

/// M0 fitted to the training curves with everything the tests need fixed under the null.
pub(super) struct M0Fit {
    pub m0: ModelFit,
    pub mask: Mask,
    /// Predictions of every curve (held-out ones with their STE fitted alone).
    pub f0: Vec<CurvePrediction>,
    pub held0: Vec<HeldFit>,
    /// Omega of every point at the fitted omega_n.
    pub omega: Vec<Vec<f64>>,
    /// The noise (stated, or estimated about this fit) and its scale at every point at M0's
    /// levels: the weights of every later fit and test.
    pub noise: DiscoveryNoise,
    pub scales: Scales,
    /// The linearised statistics at this fit, without candidate probes.
    pub lin: Linearized,
}

/// Residuals of the curves about predictions, every point (um).
fn residuals_about(setup: &Setup, preds: &[CurvePrediction]) -> Vec<Vec<f64>> {
    setup
        .curves
        .iter()
        .zip(preds)
        .map(|(c, p)| {
            c.dte_pp_um
                .iter()
                .zip(&p.dte_pp_um)
                .map(|(y, f)| y - f)
                .collect()
        })
        .collect()
}

/// The noise of the data about predictions `preds` on the points `mask` keeps: stated, or
/// estimated from the pseudo-residuals (see [`super::noise`]).
pub(super) fn noise_about(
    setup: &Setup,
    spec: &NoiseSpec,
    preds: &[CurvePrediction],
    mask: &Mask,
) -> Result<DiscoveryNoise> {
    match spec {
        NoiseSpec::Stated(n) => Ok((**n).clone()),
        NoiseSpec::Estimate { floor_min, tails } => {
            let speeds: Vec<Vec<f64>> = setup.curves.iter().map(|c| c.speeds_rpm.clone()).collect();
            let levels: Vec<Vec<f64>> = preds.iter().map(|p| p.dte_pp_um.clone()).collect();
            let residuals = residuals_about(setup, preds);
            estimate_noise(
                &PseudoInput {
                    speeds: &speeds,
                    residuals: &residuals,
                    levels: &levels,
                    mask,
                },
                *floor_min,
                *tails,
            )
        }
    }
}

/// The noise before any fit: stated, or a constant from the second differences of the curves
/// (Gasser et al. 1986, median-based), for the first fit's weights.
fn first_noise(setup: &Setup, spec: &NoiseSpec) -> Result<DiscoveryNoise> {
    match spec {
        NoiseSpec::Stated(n) => Ok((**n).clone()),
        NoiseSpec::Estimate { floor_min, .. } => {
            let measured: Vec<Vec<f64>> =
                setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
            let s = super::stats::noise_from_differences(&measured)
                .filter(|s| *s > 0.0)
                .ok_or_else(|| {
                    GearError::Numerical("cannot estimate the noise from the curves".into())
                })?;
            Ok(DiscoveryNoise::stated(
                NoiseOrigin::Estimated {
                    floor_min: *floor_min,
                },
                crate::fit::NoiseModel::constant(s.max(*floor_min)),
            ))
        }
    }
}

/// The model Jacobian (um per parameter) of a fit's kept rows from the Jacobian of its
/// standardized residuals (y - f) / sigma: row r times -sigma_r.
pub(super) fn model_jacobian(lm: &LmFit, row_scales: &[f64]) -> DMatrix<f64> {
    let mut j = lm.jacobian.clone();
    for (r, s) in row_scales.iter().enumerate() {
        j.row_mut(r).scale_mut(-s);
    }
    j
}

/// Each held-out curve's sensitivity to zeta and omega_n at fit `m0` (its STE held at its
/// own fit), on its kept points: forward differences of the simulated curve with the engine's
/// steps (1e-4 of the value, at least of the parameter's typical size).
fn held_globals(
    setup: &Setup,
    m0: &ModelFit,
    held0: &[HeldFit],
    f0: &[CurvePrediction],
    mask: &Mask,
) -> Result<Vec<(usize, DMatrix<f64>)>> {
    let g = m0.globals;
    let hz = 1e-4 * g.zeta.max(0.005);
    let hw = 1e-4 * g.omega_n_hz.max(10.0);
    held0
        .par_iter()
        .map(|(i, e, _)| {
            let kept: Vec<usize> = (0..mask[*i].len()).filter(|&j| mask[*i][j]).collect();
            let mut out = DMatrix::zeros(kept.len(), 2);
            for (col, (gp, h)) in [
                (
                    Globals {
                        zeta: g.zeta + hz,
                        ..g
                    },
                    hz,
                ),
                (
                    Globals {
                        omega_n_hz: g.omega_n_hz + hw,
                        ..g
                    },
                    hw,
                ),
            ]
            .into_iter()
            .enumerate()
            {
                let p = super::forward::predict(setup, *i, gp, *e, &m0.effect)?;
                for (r, &j) in kept.iter().enumerate() {
                    out[(r, col)] = (p.dte_pp_um[j] - f0[*i].dte_pp_um[j]) / h;
                }
            }
            Ok((*i, out))
        })
        .collect()
}

/// Scales of the rows of a fit on curves `idx`: their kept points in order.
pub(super) fn row_scales(idx: &[usize], mask: &Mask, scales: &Scales) -> Vec<f64> {
    idx.iter()
        .flat_map(|&i| {
            (0..mask[i].len())
                .filter(move |&j| mask[i][j])
                .map(move |j| scales[i][j])
        })
        .collect()
}

/// Fit M0: closed-form start at the highest load, then the simulated up-sweeps, first on every
/// point weighted by the first noise ([`first_noise`]), then, with the noise estimated about
/// that fit (or stated), again on the points the mask keeps; held-out STE amplitudes fitted
/// alone; the noise estimated once more about the final curves (one step of generalised least
/// squares with an estimated variance function, Carroll & Ruppert 1988, Sec. 2.3).
pub(super) fn fit_m0(
    setup: &Setup,
    train: &[usize],
    held: &[usize],
    spec: &NoiseSpec,
    progress: &dyn Progress,
) -> Result<M0Fit> {
    let n_curves = setup.curves.len();
    let (g0, e0) = linear_start(setup, train[0])?;
    let mut start = vec![g0.zeta, g0.omega_n_hz, e0];
    start.extend(train[1..].iter().map(|&i| ste_from_low_speed(setup, i, g0)));
    let all: Mask = setup
        .curves
        .iter()
        .map(|c| vec![true; c.speeds_rpm.len()])
        .collect();
    let measured: Vec<Vec<f64>> = setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
    let noise0 = first_noise(setup, spec)?;
    let scales0 = noise0.scales(&measured);
    let m0 = fit_model(
        setup,
        train,
        &all,
        &scales0,
        EffectInFit::None,
        &start,
        Stop::converged(25),
    )?;
    progress.advance(1);
    // Held-out STE from the quasi-static end for the mask; fitted afterwards.
    let pre_ste: Vec<f64> = (0..n_curves)
        .map(|i| {
            curve_ste(i, train, &m0, &[])
                .unwrap_or_else(|| ste_from_low_speed(setup, i, m0.globals))
        })
        .collect();
    let every: Vec<usize> = (0..n_curves).collect();
    let pre = predict_many(setup, &every, m0.globals, &pre_ste, &m0.effect)?;
    let pre_mask = make_mask(setup, &pre, &every, &noise0)?;
    let noise1 = noise_about(setup, spec, &pre, &pre_mask)?
        .replicates()
        .into_owned();
    let mask = make_mask(setup, &pre, &every, &noise1)?;
    let pre_levels: Vec<Vec<f64>> = pre.iter().map(|p| p.dte_pp_um.clone()).collect();
    let scales1 = noise1.scales(&pre_levels);
    let m0 = fit_model(
        setup,
        train,
        &mask,
        &scales1,
        EffectInFit::None,
        &m0.lm.params.clone(),
        Stop::converged(30),
    )?;
    let (f0, held0) = predict_all(setup, &m0, train, held, &mask, &scales1, None)?;
    let noise = noise_about(setup, spec, &f0, &mask)?;
    let levels: Vec<Vec<f64>> = f0.iter().map(|p| p.dte_pp_um.clone()).collect();
    let scales = noise.scales(&levels);
    progress.advance(1);
    let omega: Vec<Vec<f64>> = setup
        .curves
        .iter()
        .map(|c| {
            c.speeds_rpm
                .iter()
                .map(|s| setup.dim.omega(*s, m0.globals.omega_n_hz))
                .collect()
        })
        .collect();
    let lin = Linearized {
        f0: levels,
        mask: mask.clone(),
        speeds: setup.curves.iter().map(|c| c.speeds_rpm.clone()).collect(),
        train: train.to_vec(),
        jac_train: model_jacobian(&m0.lm, &row_scales(train, &mask, &scales1)),
        held_sens: held0.iter().map(|(i, _, s)| (*i, s.clone())).collect(),
        held_globals: held_globals(setup, &m0, &held0, &f0, &mask)?,
        omega: omega.clone(),
        windows: windows(),
        probes: Vec::new(),
        zero: None,
        noise: noise.clone(),
    };
    Ok(M0Fit {
        m0,
        mask,
        f0,
        held0,
        omega,
        noise,
        scales,
        lin,
    })
}

/// Run the discovery workflow on a Munro-style data set. Reads the curves and the rig's stated
/// geometry only: never `[source.truth]`.
pub fn discover(
    data: &MunroData,
    opts: &DiscoverOptions,
    progress: &dyn Progress,
) -> Result<Discovery> {
    let setup = Setup::from_munro(data)?;
    discover_setup(&setup, opts, progress)
}

/// Most bootstrap replicates a run may ask for: 99999 keep a run within minutes (each
/// replicate re-estimates the noise and projects every probe) and resolve p-values to 1e-5.
pub const MAX_BOOTSTRAP: usize = 99_999;

/// The most tests Holm's correction for detection runs over: the training and held-out
/// chi-squares, the runs test, one per Omega window, and every library candidate's own test.
pub fn holm_tests_at_most() -> usize {
    3 + windows().len() + LIBRARY.len()
}

/// The fewest replicates B at which the smallest Monte Carlo p-value, 1 / (B + 1), times the
/// number of tests ([`holm_tests_at_most`]) falls below alpha / 2, the detection threshold:
/// 520 at alpha 0.05. With fewer, nothing can ever be detected: at 399 replicates the least
/// Holm-adjusted p of 11 tests was 0.0275, and a set whose noise was stated at a third of its
/// scatter (every test at its least p) was answered "none".
pub fn least_bootstrap(alpha: f64) -> usize {
    let m = holm_tests_at_most() as f64;
    let mut b = ((2.0 * m / alpha).floor() as usize).saturating_sub(1);
    // At most two steps: b starts within one of the bound.
    while m / (b as f64 + 1.0) >= alpha / 2.0 {
        b += 1;
    }
    b
}

/// The options' ranges, checked before any work: alpha in (0, 0.5]; enough replicates that
/// a p-value can pass Holm's correction ([`least_bootstrap`]); at most [`MAX_BOOTSTRAP`]; a
/// stated noise positive and finite.
pub(crate) fn check_options(opts: &DiscoverOptions) -> Result<()> {
    if opts.procedure == Procedure::Likelihood {
        return check_likelihood_options(opts);
    }
    if !(opts.alpha > 0.0 && opts.alpha <= 0.5) {
        return Err(GearError::param(
            "alpha",
            opts.alpha,
            "alpha must be in (0, 0.5]",
        ));
    }
    let least = least_bootstrap(opts.alpha);
    if opts.bootstrap < least || opts.bootstrap > MAX_BOOTSTRAP {
        return Err(GearError::Unsupported(format!(
            "--bootstrap {}: the bootstrap needs {least} to {MAX_BOOTSTRAP} replicates at alpha {} (the least p-value 1 / (B + 1), times the {} tests Holm's correction runs over, must be below alpha / 2)",
            opts.bootstrap,
            opts.alpha,
            holm_tests_at_most()
        )));
    }
    if let Some(s) = opts.noise_um {
        if !(s > 0.0 && s < 1e3) {
            return Err(GearError::param(
                "noise_um",
                s,
                "a stated noise must be in (0, 1000) um",
            ));
        }
    }
    Ok(())
}

/// The likelihood procedure's options: alpha in (0, 0.5]; enough replicates that the least
/// p-value, 1 / (B + 1), times the candidates Holm's correction runs over is below alpha; a
/// stated noise positive and finite.
fn check_likelihood_options(opts: &DiscoverOptions) -> Result<()> {
    let least = (LIBRARY.len() as f64 / opts.alpha).ceil() as usize;
    if opts.bootstrap < least || opts.bootstrap > MAX_BOOTSTRAP {
        return Err(GearError::Unsupported(format!(
            "--bootstrap {}: the bootstrap needs {least} to {MAX_BOOTSTRAP} replicates at alpha {} (the least p-value 1 / (B + 1), times the {} candidates Holm's correction runs over, must be below alpha)",
            opts.bootstrap,
            opts.alpha,
            LIBRARY.len()
        )));
    }
    check_options(&DiscoverOptions {
        bootstrap: least_bootstrap(opts.alpha),
        procedure: Procedure::Tests,
        ..opts.clone()
    })
}

/// What the run knows of the noise: `--noise-um`, else what the data set states (per-point
/// column, rig.toml `[noise]`), else an estimate (floor at least a stated reading uncertainty).
fn noise_spec(setup: &Setup, opts: &DiscoverOptions) -> Result<NoiseSpec> {
    if let Some(s) = opts.noise_um {
        return Ok(NoiseSpec::Stated(Box::new(DiscoveryNoise::stated(
            NoiseOrigin::StatedOption,
            crate::fit::NoiseModel::constant(s),
        ))));
    }
    Ok(match &setup.noise {
        MunroNoise::PerPoint => {
            let scales: Option<Scales> = setup.curves.iter().map(|c| c.sd_um.clone()).collect();
            let scales = scales.ok_or_else(|| {
                GearError::Numerical("a per-point noise needs dte_pp_sd_um on every point".into())
            })?;
            NoiseSpec::Stated(Box::new(DiscoveryNoise::per_point(scales)))
        }
        MunroNoise::Stated(m) => {
            NoiseSpec::Stated(Box::new(DiscoveryNoise::stated(NoiseOrigin::StatedRig, *m)))
        }
        MunroNoise::Estimate { floor_min } => NoiseSpec::Estimate {
            floor_min: *floor_min,
            tails: opts.tails,
        },
    })
}

/// Whether M0's training curves `f0` touch the back flank at a kept point. In single-sided
/// impacts the teeth fly through the gap and return to the same flank: the other flank, 2b
/// away, is never reached, so b only enters with back-side contact. That contact may come from
/// a probe with a smaller b where M0 at the stated b has none (a rattle-regime set with b x 0.7
/// does this), so the guard is the probes' effect on the curves, like every other candidate's;
/// M0's own back contact only names the reason.
fn back_contact_in(train: &[usize], f0: &[CurvePrediction], mask: &Mask) -> bool {
    train.iter().any(|&i| {
        f0[i]
            .back_contact
            .iter()
            .zip(&mask[i])
            .any(|(s, m)| *s && *m)
    })
}

/// Each candidate before any refit: identifiable when its largest standardized probe `dict`
/// moves the fitted curves by the noise, its score and dictionary LR (`observed`), the LR's
/// bootstrap p-value against the replicates `reps`, Holm-adjusted across the identifiable
/// candidates. A candidate whose probes failed (`failed`, by candidate) has no probes, no
/// test and no identifiability.
fn candidate_results(
    dict: &[Vec<DVector<f64>>],
    failed: &[Option<String>],
    observed: &Statistics,
    reps: &[Statistics],
    back_contact: bool,
) -> Vec<CandidateResult> {
    let mut cands: Vec<CandidateResult> = LIBRARY
        .iter()
        .enumerate()
        .map(|(c, &cand)| {
            let biggest = dict[c].iter().map(|d| d.norm_squared()).fold(0.0, f64::max);
            let (identifiable, note) = if failed[c].is_some() {
                (false, None)
            } else if biggest >= 1.0 {
                (true, None)
            } else if cand == Candidate::Backlash && !back_contact {
                (false, Some("not identifiable: no back-side contact (double-sided impact) in the training curves, at the stated b or at any probed b; in contact or with single-sided impacts the response in um does not depend on b".to_string()))
            } else {
                (false, Some("not identifiable: its largest probe changes the fitted curves by less than the noise".to_string()))
            };
            let lr = observed.lr[c].0;
            let null: Vec<f64> = reps.iter().map(|r| r.lr[c].0).collect();
            CandidateResult {
                name: cand.name(),
                candidate: cand,
                identifiable,
                note,
                failed: failed[c].clone(),
                score: observed.score[c],
                score_p_approx: chi2_sf(observed.score[c], 1.0),
                lr,
                p_value: identifiable.then(|| bootstrap_p(lr, &null)),
                p_holm: None,
                estimate_name: cand.estimate_name(),
                estimate: None,
                ci95: None,
                ci95_method: "Wald",
                wald_ci95: None,
                profile_ci95: None,
                interval_quantile: None,
                delta: None,
                refit_lr: None,
                refit_zeta: None,
                refit_omega_n_hz: None,
                other_start: None,
                phase_deg: None,
                phase_wald95_deg: Vec::new(),
                phase_profile95_deg: None,
            }
        })
        .collect();
    let ps: Vec<f64> = cands.iter().filter_map(|c| c.p_value).collect();
    let mut adj = holm(&ps).into_iter();
    for c in cands.iter_mut().filter(|c| c.p_value.is_some()) {
        c.p_holm = adj.next();
    }
    cands
}

/// Whether a candidate's Holm-adjusted p-value is below alpha / 2 (the level per side): only
/// such a candidate can be named.
pub(super) fn significant(c: &CandidateResult, alpha: f64) -> bool {
    c.p_holm.is_some_and(|p| p < alpha / 2.0)
}

/// Whether a candidate is significant on its own test before Holm's correction but not after:
/// a rival for the held-out split of a name (see [`Rounds::held_out_rivals`]), never named.
pub(super) fn rival(c: &CandidateResult, alpha: f64) -> bool {
    c.p_value.is_some_and(|p| p < alpha / 2.0) && !significant(c, alpha)
}

/// The candidates refitted first, and the names of those significant on a set without a
/// detected discrepancy (listed, not refitted).
///
/// Refit the leading significant candidates by score, and the one with the largest
/// dictionary LR. The score is the local (delta -> 0) statistic; where M0 is far off and an
/// effect acts through a threshold, the finite probes see more: on a rattle-regime set
/// (true b x 0.7) the backlash had the largest LR of all five and ranked third by score.
/// Only once a discrepancy is detected: a name needs one. Every name the null studies gave
/// without one was false (constant noise, seeds 1053, 1174, 1267: each detection p-value
/// above 0.05; a torque ripple or damping law refit settling on a ledge of the jumping pp
/// response), and none of the ~120 correct names of the recovery studies came without one.
fn first_refits(
    cands: &[CandidateResult],
    detected: bool,
    opts: &DiscoverOptions,
) -> (Vec<usize>, Vec<String>) {
    let significant = |c: &CandidateResult| significant(c, opts.alpha);
    let mut order: Vec<usize> = (0..cands.len())
        .filter(|&c| detected && significant(&cands[c]))
        .collect();
    let significant_undetected: Vec<String> = cands
        .iter()
        .filter(|c| !detected && significant(c))
        .map(|c| c.name.to_string())
        .collect();
    let by_lr = order
        .iter()
        .copied()
        .max_by(|&a, &b| cands[a].lr.total_cmp(&cands[b].lr));
    order.sort_by(|&a, &b| cands[b].score.total_cmp(&cands[a].score));
    let mut refit: Vec<usize> = order.into_iter().take(opts.refit_top.max(1)).collect();
    if let Some(c) = by_lr.filter(|c| !refit.contains(c)) {
        refit.push(c);
    }
    (refit, significant_undetected)
}

/// [`discover`] on an already built setup.
pub fn discover_setup(
    setup: &Setup,
    opts: &DiscoverOptions,
    progress: &dyn Progress,
) -> Result<Discovery> {
    check_options(opts)?;
    if opts.procedure == Procedure::Likelihood {
        return super::procedure::discover_by_likelihood(setup, opts, progress);
    }
    let n_curves = setup.curves.len();
    let (train, held) = split(n_curves);
    let measured: Vec<Vec<f64>> = setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
    let spec = noise_spec(setup, opts)?;
    progress.start(4 + library_probes().len() as u64, "discovery steps");

    // Past M0 a failure belongs to a candidate (see `CandidateResult::failed`); M0's own ends
    // the run, saying so.
    let m0_fit = fit_m0(setup, &train, &held, &spec, progress)
        .map_err(m0_failed("its fit to the training loads"))?;
    let excluded = excluded_by_load(setup, &m0_fit, &train)
        .map_err(m0_failed("its range at the points excluded from the tests"))?;
    let M0Fit {
        m0,
        mask,
        f0,
        held0,
        omega,
        noise,
        scales,
        mut lin,
    } = m0_fit;
    let ws = lin.windows.clone();

    // 2. Probe dictionary at the M0 fit (training curves).
    let probes = probe_dictionary(setup, &train, &m0, &mask, &f0, &scales, progress);
    let (dict_delta, seen_at_design, probes_failed) =
        (probes.deltas, probes.seen_at_design, probes.failed);
    lin.probes = probes.raw;
    // The probes standardized by the data's noise and projected off the weighted M0 Jacobian.
    let dict = lin.weighted_probes(&scales);

    // 3. Observed statistics and the bootstrap under M0.
    let observed = lin.statistics(&measured);
    let reps = lin.bootstrap(opts.bootstrap, opts.seed);
    progress.advance(1);
    let names = detection_names(&ws);

    // 4. Candidates: identifiability, score rank, bootstrap LR p-values, Holm.
    let mut cands = candidate_results(
        &dict,
        &probes_failed,
        &observed,
        &reps,
        back_contact_in(&train, &f0, &mask),
    );
    // Detection: Holm over every test of M0, the candidates' own included.
    let candidate_p: Vec<f64> = cands.iter().filter_map(|c| c.p_value).collect();
    let (detection, least_p) = detection_tests(&names, &observed, &reps, &candidate_p);
    let detected_by_tests = least_p < opts.alpha / 2.0;
    let detected = detected_by_tests || far_outside(&excluded) > 0;

    let (refit, significant_undetected) = first_refits(&cands, detected, opts);
    let rounds = Rounds {
        setup,
        opts,
        train: &train,
        held: &held,
        measured: &measured,
        m0: &m0,
        mask: &mask,
        f0: &f0,
        held0: &held0,
        noise: &noise,
        scales: &scales,
        spec: &spec,
        lin: &lin,
        dict: &dict,
        dict_delta: &dict_delta,
        seen_at_design: &seen_at_design,
        observed: &observed,
        names: &names,
        detected,
    };
    let mut refits: Vec<Refitted> = Vec::new();
    let decision = rounds.settle(&refit, &mut cands, &mut refits);
    progress.advance(1);
    let tests = TestsOfM0 {
        detection,
        detected_by_tests,
        significant_undetected,
        excluded,
    };
    let found = discovery_of(&rounds, &omega, decision, tests, cands);
    progress.advance(1);
    progress.finish();
    Ok(found)
}

/// An error of the null model M0 itself, in `what`: it ends the run, since every test and
/// candidate is taken against M0, and the message says it was M0's.
fn m0_failed(what: &'static str) -> impl Fn(GearError) -> GearError {
    move |e| {
        GearError::Numerical(format!(
            "the null model M0 failed in {what}, so nothing can be tested against it: {e}"
        ))
    }
}

/// What the tests of M0 found, beside [`Rounds::detected`].
struct TestsOfM0 {
    detection: Vec<TestResult>,
    detected_by_tests: bool,
    significant_undetected: Vec<String>,
    excluded: Vec<ExcludedPoints>,
}

/// The run's findings from its rounds' `decision`: the answer, the gap before (M0) and after
/// (the leading candidate's refit, or M0 when none was refitted) on the training and held-out
/// curves, and the residual curves; `omega` is every point's Omega at M0's omega_n.
fn discovery_of(
    r: &Rounds,
    omega: &[Vec<f64>],
    decision: Decision,
    tests: TestsOfM0,
    cands: Vec<CandidateResult>,
) -> Discovery {
    let Decision {
        effect,
        ambiguous_with,
        closest,
        post_fit,
        mut after_preds,
        compare_mask,
        refit_preds,
        refit_held,
        named_ci: _,
        better_refit: _,
        rests_on: _,
        held_out_prefers,
    } = decision;
    let (setup, train, held) = (r.setup, r.train, r.held);
    let ws = &r.lin.windows;
    let after_name = leading_candidate(&effect, closest.as_deref(), &ambiguous_with);
    let gap_after_model = match (after_name, refit_preds.is_some()) {
        (Some(n), true) => format!("M0 + {n}"),
        _ => {
            after_preds = r.f0.to_vec();
            "M0, no candidate refitted".to_string()
        }
    };
    let gap_set = |preds: &[CurvePrediction]| GapSet {
        training: gap(setup, train, preds, &compare_mask, omega, ws),
        held_out: (!held.is_empty()).then(|| gap(setup, held, preds, &compare_mask, omega, ws)),
    };
    let kept_scales = r
        .scales
        .iter()
        .zip(r.mask)
        .flat_map(|(s, m)| s.iter().zip(m).filter(|(_, k)| **k).map(|(s, _)| *s));
    let noise_range_um = min_max(kept_scales).unwrap_or((0.0, 0.0));
    Discovery {
        ambiguous_with,
        closest_candidate: closest,
        detected: r.detected,
        detected_by_tests: tests.detected_by_tests,
        significant_undetected: tests.significant_undetected,
        held_out_prefers,
        post_fit,
        noise: r.noise.clone(),
        noise_range_um,
        zeta_m0: r.m0.globals.zeta,
        omega_n_hz_m0: r.m0.globals.omega_n_hz,
        design_load_n: setup.design_load_n,
        training_loads_n: train.iter().map(|&i| setup.curves[i].load_n).collect(),
        held_out_loads_n: held.iter().map(|&i| setup.curves[i].load_n).collect(),
        held_out_ste_um: r
            .held0
            .iter()
            .map(|(i, e0, _)| {
                let after = refit_held
                    .as_ref()
                    .and_then(|h| h.iter().find(|x| x.0 == *i))
                    .map_or(*e0, |x| x.1);
                (setup.curves[*i].load_n, *e0, after)
            })
            .collect(),
        excluded_points: r.mask.iter().flatten().filter(|m| !**m).count(),
        excluded_by_load: tests.excluded,
        gap_before: gap_set(r.f0),
        gap_after: gap_set(&after_preds),
        gap_after_model,
        residuals_before: residual_curves(setup, train, r.f0, &compare_mask, omega),
        residuals_after: residual_curves(
            setup,
            train,
            refit_preds.as_deref().unwrap_or(&after_preds),
            &compare_mask,
            omega,
        ),
        windows: ws.clone(),
        detection: tests.detection,
        candidates: cands,
        effect,
        bootstrap: r.opts.bootstrap,
        noise_correlation: None,
        prediction_check: None,
    }
}

#[cfg(test)]
mod tests {
    use super::{holm_tests_at_most, least_bootstrap, make_mask, OtherStart};
    use crate::discover::forward::CurvePrediction;

    /// A jump from single-sided impacts (30 um) onto the back flank (157 um) drops the points
    /// on both sides although the teeth are separated on both; a jump out of contact does the
    /// same; a step in back contact smaller than 10 sigma, and a large step within one regime
    /// (a resonance peak), keep their points; a non-period-1 point is dropped. Without the
    /// model a regime change cannot be refined and counts as a jump.
    #[test]
    fn mask_drops_the_points_around_a_jump_onto_the_back_flank() {
        let p = CurvePrediction {
            dte_pp_um: vec![20.0, 28.0, 30.0, 157.0, 162.0, 162.5, 300.0, 10.0, 9.0],
            period1: vec![true, true, true, true, true, true, true, true, false],
            separated: vec![false, true, true, true, true, true, true, false, false],
            back_contact: vec![false, false, false, true, true, false, false, false, false],
            aperiodic_start: vec![None; 9],
            neighbour_starts: Vec::new(),
            sweep_model: None,
        };
        let setup = crate::discover::forward::Setup::new(
            crate::data::munro_rig().dimensional().unwrap(),
            3780.0,
            vec![crate::discover::forward::Curve {
                load_n: 3780.0,
                speeds_rpm: (0..9).map(|k| 1000.0 + 100.0 * k as f64).collect(),
                dte_pp_um: vec![1.0; 9],
                sd_um: None,
            }],
            crate::validate::MunroNoise::Estimate { floor_min: 0.0 },
        );
        let noise = super::DiscoveryNoise::stated(
            super::NoiseOrigin::StatedOption,
            crate::fit::NoiseModel::constant(0.15),
        );
        let m = make_mask(&setup, &[p], &[0], &noise).unwrap();
        assert_eq!(
            m[0],
            vec![false, false, false, false, true, true, false, false, false]
        );
    }

    /// A distinct minimum within 3.84 sigma^2 leaves the phase undetermined; one 5 sigma^2
    /// worse does not.
    /// 13 tests (3 detection, 5 windows, 5 candidates) at alpha 0.05: 13 / 521 = 0.02495 is
    /// below 0.025, 13 / 520 is not; at alpha 0.01, 2600 (13 / 2600 = 0.005 is not below
    /// 0.005).
    #[test]
    fn the_least_bootstrap_lets_the_least_p_pass_holm() {
        assert_eq!(holm_tests_at_most(), 13);
        assert_eq!(least_bootstrap(0.05), 520);
        assert_eq!(least_bootstrap(0.01), 2600);
        for alpha in [0.5, 0.1, 0.05, 0.02, 0.01, 0.001] {
            let b = least_bootstrap(alpha);
            assert!(13.0 / (b as f64 + 1.0) < alpha / 2.0, "{alpha}");
            assert!(13.0 / b as f64 >= alpha / 2.0, "{alpha}");
        }
    }

    #[test]
    fn phase_is_undetermined_only_within_the_threshold() {
        let at = |deviance_increase: f64| OtherStart {
            delta: vec![-0.1, 0.0],
            deviance_increase,
            ci95: None,
            phase_wald95_deg: None,
        };
        assert!(at(1.0).phase_undetermined());
        assert!(at(3.8).phase_undetermined());
        assert!(!at(5.0).phase_undetermined());
    }
}
