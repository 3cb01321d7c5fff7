//! What a discovery run is asked (its options) and what it found: the answer, each candidate's
//! test and size, M0's fit and errors, and the gaps before and after on training and held-out
//! loads. Immutable once made; `crate::report::write_discovery` writes it.

use super::effects::{Candidate, Effect};
use super::forward::MIN_ZETA;
use super::noise::{DiscoveryNoise, TailChoice};
use super::training::Correlation;
use super::windows::Window;
use crate::error::{GearError, Result};
use crate::fit::CorrelationFit;
use serde::Serialize;

/// Settings of a discovery run.
#[derive(Clone, Debug)]
pub struct DiscoverOptions {
    /// Parametric bootstrap replicates under M0.
    pub bootstrap: usize,
    /// Seed of the bootstrap.
    pub seed: u64,
    /// Stated measurement noise (um, a constant); None takes the data set's statement
    /// (`dte_pp_sd_um`, rig.toml `[noise]`) or estimates it with M0's fit.
    pub noise_um: Option<f64>,
    /// Whether estimated noise may have Student-t tails (chosen by the data) or is Gaussian.
    pub tails: TailChoice,
    /// The errors' correlation along speed within a curve.
    pub correlation: Correlation,
    /// Family-wise error rate of the candidates' tests (Holm).
    pub alpha: f64,
    /// An effect (a study's hidden truth) whose test's power the run states ([`PowerBound`]).
    pub power_at: Option<Effect>,
}

impl Default for DiscoverOptions {
    fn default() -> Self {
        DiscoverOptions {
            bootstrap: 399,
            seed: 12345,
            noise_um: None,
            tails: TailChoice::Auto,
            correlation: Correlation::Auto,
            alpha: 0.05,
            power_at: None,
        }
    }
}

/// Most bootstrap replicates a run may ask for.
pub const MAX_BOOTSTRAP: usize = 99_999;

/// The fewest replicates at which the least Monte Carlo p-value, 1 / (B + 1), times the
/// number of candidates Holm's correction runs over is below alpha: with fewer, nothing could
/// ever be named.
pub fn least_bootstrap(alpha: f64) -> usize {
    (super::effects::LIBRARY.len() as f64 / alpha).floor() as usize
}

/// The options' ranges, checked before any work: alpha in (0, 0.5]; enough replicates
/// ([`least_bootstrap`]) and at most [`MAX_BOOTSTRAP`]; a stated noise in (0, 1000) um.
pub fn check_options(opts: &DiscoverOptions) -> Result<()> {
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
            "--bootstrap {}: the bootstrap needs {least} to {MAX_BOOTSTRAP} replicates at alpha {} (the least p-value 1 / (B + 1), times the {} candidates Holm's correction runs over, must be below alpha)",
            opts.bootstrap,
            opts.alpha,
            super::effects::LIBRARY.len()
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

/// One candidate's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct CandidateResult {
    pub name: &'static str,
    #[serde(skip)]
    pub candidate: Candidate,
    /// Whether some probe of it moves the training curves, beyond what M0's own parameters
    /// can do, by a tenth of the noise (else it is not tested; see `note`).
    pub identifiable: bool,
    pub note: Option<String>,
    /// Why its fit failed: it is reported "failed, because ..." and the run goes on.
    pub failed: Option<String>,
    /// Why its prediction of the held-out loads failed: it is then not named.
    pub prediction_failed: Option<String>,
    /// 2 (log L of its fit - log L of M0's), each with its own noise.
    pub lr: f64,
    /// Bootstrap p-value of `lr` under M0, and Holm-adjusted across the tested candidates.
    pub p_value: Option<f64>,
    pub p_holm: Option<f64>,
    /// What `estimate` is.
    pub estimate_name: &'static str,
    /// The named effect's size with its 95% interval (profile likelihood, Wald where the
    /// profile failed: `ci95_method`), and both intervals.
    pub estimate: Option<f64>,
    pub ci95: Option<(f64, f64)>,
    pub ci95_method: &'static str,
    pub wald_ci95: Option<(f64, f64)>,
    pub profile_ci95: Option<(Option<f64>, Option<f64>)>,
    /// Its fitted delta, zeta and omega_n (Hz), which move with the effect.
    pub delta: Option<Vec<f64>>,
    pub zeta: Option<f64>,
    pub omega_n_hz: Option<f64>,
    /// The named phase-carrying effect's phase psi of its first (A cos psi, A sin psi) pair,
    /// degrees: the stiffness variation's against the STE, the 2nd STE harmonic's against the
    /// first, the torque ripple's against the mesh; and its 95% Wald arc (lo, hi).
    pub phase_deg: Option<f64>,
    pub phase_wald95_deg: Option<(f64, f64)>,
}

/// A test with its bootstrap p-value, and its Holm-adjusted one where it joins the family.
#[derive(Clone, Debug, Serialize)]
pub struct TestResult {
    pub name: String,
    pub statistic: f64,
    pub p_value: Option<f64>,
    pub p_holm: Option<f64>,
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

/// The points of one load left out of the likelihood (non-period-1 or at a jump, where a
/// point-wise residual says nothing), described: a measured pp far outside every pp M0
/// produces there is a disagreement the likelihood cannot see, so the report shows both ranges.
#[derive(Clone, Debug, Serialize)]
pub struct ExcludedPoints {
    pub load_n: f64,
    pub points: usize,
    /// Of those, points where M0 predicts non-period-1 motion (the rest straddle a jump).
    pub non_period1: usize,
    /// Smallest and largest measured pp DTE over the excluded points, um.
    pub measured_range_um: (f64, f64),
    /// Smallest and largest M0 prediction (its first observation window) there, um.
    pub predicted_range_um: (f64, f64),
    /// Smallest and largest M0 pp DTE there, um, with every observation window's at a
    /// non-periodic point (`super::forward::aperiodic_pp_range`), of which a measured pp is one.
    pub model_range_um: (f64, f64),
    /// Excluded points whose measured pp lies outside `model_range_um` by more than 3 noise
    /// scales (at its largest pp) plus 10% of that pp.
    pub outside_model_range: usize,
}

/// The power of a candidate's likelihood-ratio test against an effect of a given size, to first
/// order and asymptotically (Cox & Hinkley 1974, Sec. 9.3): non-central chi-square with the
/// candidate's degrees of freedom, non-centrality the squared change of the training curves
/// (whitened by M0's noise) that M0's own parameters cannot make. A study's rate is compared to it.
#[derive(Clone, Debug, Serialize)]
pub struct PowerBound {
    pub candidate: String,
    /// The effect's parameters (the candidate's coordinates).
    pub delta: Vec<f64>,
    /// Non-centrality lambda.
    pub noncentrality: f64,
    /// The test's level: alpha over the candidates (Holm's first step).
    pub level: f64,
    /// P(chi'^2_k(lambda) > the chi^2_k point at 1 - level).
    pub power: f64,
}

/// Everything a discovery run found.
#[derive(Clone, Debug, Serialize)]
pub struct Discovery {
    /// A candidate name, "none", "ambiguous" or "unexplained".
    pub effect: String,
    /// The best candidate's rivals (within the training loads' likelihood support of it) that
    /// the held-out loads do not tell from it.
    pub ambiguous_with: Vec<String>,
    /// The best candidate when the effect is "ambiguous" or "unexplained".
    pub closest_candidate: Option<String>,
    /// Why M0 does not explain the curves although no candidate passes: then "unexplained".
    pub misfit: Option<String>,
    /// M0's chi-square of innovations against its bootstrap replicates'.
    pub goodness_of_fit: TestResult,
    /// M0's prediction of the held-out loads against its bootstrap replicates: in Holm's
    /// family, it can make the answer "unexplained".
    pub held_out_prediction: Option<TestResult>,
    pub candidates: Vec<CandidateResult>,
    /// Whether the best passing candidate predicts the held-out loads better than M0.
    pub prediction_check: Option<PredictionCheck>,
    /// M0's noise (stated or fitted) and its errors' correlation along speed.
    pub noise: DiscoveryNoise,
    pub noise_correlation: Option<CorrelationFit>,
    /// The STEs stated with an uncertainty (`[ste] sd_um`), each with M0's fit of it: (load N,
    /// the measurement's fit), the training loads' from M0's fit (parameter 2 + k), then the
    /// held-out loads' from each one's STE fit under M0 (parameter 0).
    pub stated_ste: Vec<(f64, crate::fit::MeasurementFit)>,
    /// Smallest and largest noise scale over the kept points, um.
    pub noise_range_um: (f64, f64),
    pub zeta_m0: f64,
    pub omega_n_hz_m0: f64,
    pub design_load_n: f64,
    pub training_loads_n: Vec<f64>,
    pub held_out_loads_n: Vec<f64>,
    /// (load N, STE um under M0, STE um under the model the gap after is of) per held-out load.
    pub held_out_ste_um: Vec<(f64, f64, f64)>,
    /// Points left out of the likelihood, all loads, and per load.
    pub excluded_points: usize,
    pub excluded_by_load: Vec<ExcludedPoints>,
    pub gap_before: GapSet,
    pub gap_after: GapSet,
    pub gap_after_model: String,
    pub windows: Vec<Window>,
    pub residuals_before: Vec<ResidualCurve>,
    pub residuals_after: Vec<ResidualCurve>,
    pub bootstrap: usize,
    /// The power of the test of [`DiscoverOptions::power_at`], when asked for and computable.
    pub power_bound: Option<PowerBound>,
}

impl Discovery {
    /// The named candidate's result, if the answer is a name.
    pub fn named(&self) -> Option<&CandidateResult> {
        self.candidates.iter().find(|c| c.name == self.effect)
    }

    /// Excluded points, over all loads, whose measured pp lies far outside M0's range there
    /// (see [`ExcludedPoints::outside_model_range`]): the run warns when there are any.
    pub fn excluded_far_outside(&self) -> usize {
        self.excluded_by_load
            .iter()
            .map(|e| e.outside_model_range)
            .sum()
    }

    /// M0's fitted zeta sits at the fits' lower bound `MIN_ZETA` (within 5%): M0 reaches for
    /// the least damping it may use, itself a sign that it lacks something.
    pub fn m0_zeta_at_lower_bound(&self) -> bool {
        self.zeta_m0 < 1.05 * MIN_ZETA
    }

    /// No training curve at the design load (within 0.5%): the highest load stands in for it.
    pub fn design_load_missing(&self) -> bool {
        !self
            .training_loads_n
            .iter()
            .any(|l| (l / self.design_load_n - 1.0).abs() <= 0.005)
    }
}
