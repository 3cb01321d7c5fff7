//! The measurement noise of a discovery run: a scale sigma_ij at every point of every curve,
//! from the engine's noise model (`crate::fit::NoiseModel`: a floor plus a part proportional to
//! the level, Gaussian or Student-t), stated by the data set or estimated from it.
//!
//! Stated noise, in the order `validate munro` takes it (one rule, `validate::noise_setting`):
//! `--noise-um` (a constant), a `dte_pp_sd_um` column on every point, rig.toml `[noise]`
//! (`floor_um`, `relative`); `[noise] reading_um` alone is the estimated floor's lower bound.
//!
//! Estimated noise comes from the Gasser, Sroka & Jennen-Steinmetz (1986) pseudo-residuals of
//! the residuals about a fitted model, not from the fit's residuals themselves: a missing effect
//! leaves a residual that is smooth along the speed axis, which the local second difference
//! removes, while white noise passes it at its full variance. Fitting the noise jointly with M0
//! would let the noise model absorb the very misfit the discovery tests look for (a relative
//! part grows until the resonance misfit is "noise"). The pseudo-likelihood of the
//! pseudo-residuals is evaluated at their exact variance under the model (an "effective level",
//! see [`pseudo_residuals`]); the relative part is kept only when an adjusted likelihood-ratio
//! test asks for it (the pseudo-residuals overlap, which inflates the statistic by the factor
//! [`Pseudo::kappa`]); pseudo-residuals beyond [`TRIM_Z`] are trimmed (a jump the mask missed, an
//! outlier), and when their tails say so the errors are Student-t (see [`TailChoice`]).

use crate::error::{GearError, Result};
use crate::fit::{
    estimate_noise, held_variance_components, Distribution, NoiseData, NoiseFreedom, NoiseModel,
    VarianceComponents,
};
use crate::numeric::Rng;
use serde::Serialize;
use std::borrow::Cow;

/// Pseudo-residuals beyond this many of their own scales are trimmed from the noise estimate:
/// a Gaussian pseudo-residual exceeds it with probability 6e-5, a jump or an outlier does.
pub const TRIM_Z: f64 = 4.0;
/// Trimming rounds at most (the kept set settles in two or three).
const TRIM_ROUNDS: usize = 6;
/// 5% critical value of a likelihood-ratio test of a variance component on its boundary (the
/// relative part at zero, or Gaussian errors as Student-t with infinite dof): a 50:50 mixture of
/// chi^2_0 and chi^2_1 (Self & Liang 1987), whose 95% point is chi^2_1's 90% point.
const BOUNDARY_LR_CRITICAL: f64 = 2.705_543_454_095_404;
/// Degrees of freedom tried for Student-t errors (the likelihood is flat in dof; a grid is
/// enough for the replicates to draw tails of the right weight). At least 3, so that the
/// errors have a standard deviation, which is what the scales of the fits and the intervals
/// are: a systematic misfit can look like tails of 2 dof or fewer (eps 0.2 hidden in Gaussian
/// noise gave dof 2), and an infinite variance would make every interval meaningless.
const T_DOF_GRID: [f64; 5] = [3.0, 4.0, 6.0, 10.0, 20.0];

/// How the noise of a set is known.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum NoiseOrigin {
    /// Stated constant, `--noise-um`.
    StatedOption,
    /// Stated in rig.toml `[noise]`.
    StatedRig,
    /// A `dte_pp_sd_um` column on every point.
    PerPoint,
    /// Estimated from the pseudo-residuals, the floor at least `floor_min`.
    Estimated { floor_min: f64 },
    /// Estimated with M0's fit by restricted maximum likelihood, the floor at least
    /// `floor_min` (the likelihood procedure).
    Fitted { floor_min: f64 },
}

impl NoiseOrigin {
    /// Human wording for the reports.
    pub fn describe(&self) -> String {
        match self {
            NoiseOrigin::StatedOption => "stated (--noise-um)".into(),
            NoiseOrigin::StatedRig => "stated in rig.toml [noise]".into(),
            NoiseOrigin::PerPoint => "stated per point (dte_pp_sd_um column)".into(),
            NoiseOrigin::Estimated { floor_min } if *floor_min > 0.0 => format!(
                "estimated from the pseudo-residuals about M0 (floor at least the stated reading uncertainty {floor_min} µm)"
            ),
            NoiseOrigin::Estimated { .. } => {
                "estimated from the pseudo-residuals about M0 (Gasser et al. 1986)".into()
            }
            NoiseOrigin::Fitted { floor_min } if *floor_min > 0.0 => format!(
                "estimated with M0's fit by restricted maximum likelihood (floor at least the stated reading uncertainty {floor_min} µm)"
            ),
            NoiseOrigin::Fitted { .. } => {
                "estimated with M0's fit by restricted maximum likelihood".into()
            }
        }
    }
}

/// The noise of a discovery run: a model, or stated per-point scales.
#[derive(Clone, Debug, Serialize)]
pub struct DiscoveryNoise {
    pub origin: NoiseOrigin,
    /// The model (for per-point noise: unit floor, no relative part; its distribution is used).
    pub model: NoiseModel,
    /// Stated scale of every point, per curve (per-point noise only).
    #[serde(skip)]
    pub per_point: Option<Vec<Vec<f64>>>,
    /// Whether an estimate carries a relative part (chosen on the data, kept for replicates).
    pub relative_estimated: bool,
    /// The model the bootstrap replicates are drawn from when it is not [`Self::model`]: the
    /// fit with the relative part free (under the chosen distribution), where the test of
    /// `estimate` dropped that part. The replicates are standardized by [`Self::model`]
    /// re-estimated, as the data are.
    ///
    /// Why: a part the test drops is not shown absent. On a coarse grid the few points high on
    /// a resonance hardly inform the relative part, and the test dropped a true 3% of the
    /// level on about a quarter of the sets (relative and quantized families, 300 rpm grid);
    /// replicates drawn from the constant model scattered by the floor at the resonance while
    /// the data scatter by 3% of tens of um, and the Omega = 1 window's test rejected 29-36%
    /// of those null sets (10-13% of all). Dropped tails were tried the same way (Student-t
    /// replicates where the tails test kept Gaussian errors): on 3-dof noise on that grid the
    /// training chi-square still rejected 15/100 (13/100 before), the best dof there being
    /// 10-20, while every Gaussian set's replicates changed (docs/discover-studies.md, "A
    /// coarse grid").
    pub replicate_model: Option<NoiseModel>,
    /// Adjusted likelihood-ratio statistics of the relative part and of Student-t errors (on
    /// the data's pseudo-residuals; estimated noise only).
    pub relative_lr: Option<f64>,
    pub tails_lr: Option<f64>,
    /// Pseudo-residuals used and trimmed (estimated noise only).
    pub pseudo_residuals: usize,
    pub trimmed: usize,
    /// The estimate's variance components (floor^2, relative^2) and their covariance, from
    /// the pseudo-likelihood's information adjusted for the overlap of the pseudo-residuals
    /// (`Pseudo::kappa`): what the intervals' degrees of freedom are taken from (estimated
    /// noise only).
    #[serde(skip)]
    pub components: Option<VarianceComponents>,
}

/// Per curve, per point: the same shape as the curves.
pub type Scales = Vec<Vec<f64>>;

impl DiscoveryNoise {
    /// A stated model.
    pub fn stated(origin: NoiseOrigin, model: NoiseModel) -> Self {
        DiscoveryNoise {
            origin,
            model,
            per_point: None,
            relative_estimated: false,
            replicate_model: None,
            relative_lr: None,
            tails_lr: None,
            pseudo_residuals: 0,
            trimmed: 0,
            components: None,
        }
    }

    /// Stated scales of every point.
    pub fn per_point(scales: Scales) -> Self {
        DiscoveryNoise {
            per_point: Some(scales),
            ..DiscoveryNoise::stated(NoiseOrigin::PerPoint, NoiseModel::constant(1.0))
        }
    }

    /// Whether the noise is estimated from the data (and so re-estimated on each replicate).
    pub fn is_estimated(&self) -> bool {
        matches!(self.origin, NoiseOrigin::Estimated { .. })
    }

    fn sd_factor(&self) -> f64 {
        self.model.distribution.sd_factor()
    }

    /// Standard deviation of the noise at every point at the model levels `levels` (per
    /// curve, per point): the scales of every residual, fit and interval of a run.
    pub fn scales(&self, levels: &[Vec<f64>]) -> Scales {
        levels
            .iter()
            .enumerate()
            .map(|(i, c)| {
                c.iter()
                    .enumerate()
                    .map(|(j, l)| self.scale_at(i, j, *l))
                    .collect()
            })
            .collect()
    }

    /// Standard deviation of the noise at point j of curve i at the model level `level`.
    pub fn scale_at(&self, i: usize, j: usize, level: f64) -> f64 {
        match &self.per_point {
            Some(s) => s[i][j],
            None => self.model.scale(level) * self.sd_factor(),
        }
    }

    /// The noise the bootstrap replicates are drawn from: this one, or its
    /// [`Self::replicate_model`] where there is one (a copy only then: it is asked for once
    /// per replicate, and a per-point noise carries every point's scale).
    pub fn replicates(&self) -> Cow<'_, DiscoveryNoise> {
        match self.replicate_model {
            Some(model) => Cow::Owned(DiscoveryNoise {
                model,
                replicate_model: None,
                ..self.clone()
            }),
            None => Cow::Borrowed(self),
        }
    }

    /// One replicate error of standard deviation `sd`, from the model's distribution.
    pub fn draw(&self, sd: f64, rng: &mut Rng) -> f64 {
        let z = match self.model.distribution {
            Distribution::Gaussian => rng.normal(),
            Distribution::StudentT { dof } => rng.student_t(dof),
        };
        sd / self.sd_factor() * z
    }

    /// The noise of a replicate data set whose residuals about the null curves are `residuals`
    /// (levels `levels`): re-estimated with this estimate's structure (floor bound, relative
    /// part or not, distribution) when estimated, itself when stated.
    pub fn for_replicate(&self, curves: &PseudoInput) -> DiscoveryNoise {
        let NoiseOrigin::Estimated { floor_min } = self.origin else {
            return self.clone();
        };
        let pseudo = pseudo_residuals(curves);
        let freedom = NoiseFreedom {
            floor_min,
            relative: self.relative_estimated,
        };
        match trimmed_fit(&pseudo, freedom, self.model.distribution) {
            Ok((model, _, _)) => DiscoveryNoise {
                model,
                components: None,
                ..self.clone()
            },
            // A replicate too short to estimate from keeps the data's noise.
            Err(_) => self.clone(),
        }
    }
}

/// What a run knows of the noise before it fits: stated, or to be estimated (floor at least
/// `floor_min`, tails as `tails` allows).
#[derive(Clone, Debug)]
pub enum NoiseSpec {
    Stated(Box<DiscoveryNoise>),
    Estimate { floor_min: f64, tails: TailChoice },
}

/// What the pseudo-residuals are taken from: per curve, the speeds, the residuals about a
/// fitted model, the model's levels and which points are kept.
pub struct PseudoInput<'a> {
    pub speeds: &'a [Vec<f64>],
    pub residuals: &'a [Vec<f64>],
    pub levels: &'a [Vec<f64>],
    pub mask: &'a [Vec<bool>],
}

/// Pseudo-residuals with their effective levels, and the variance inflation of their
/// pseudo-likelihood.
#[derive(Clone, Debug, Default)]
pub struct Pseudo {
    pub values: Vec<f64>,
    pub levels: Vec<f64>,
    /// sum_jk R_jk^2 / n for their correlation matrix R under constant noise: the factor by
    /// which the overlap of neighbouring pseudo-residuals (each shares points with four others)
    /// inflates the variance of a pseudo-likelihood score, and so a likelihood-ratio statistic
    /// (first-order adjustment; 1 for independent ones, 1.94 on an even grid).
    pub kappa: f64,
}

/// Gasser, Sroka & Jennen-Steinmetz (1986) pseudo-residuals of the kept points of each curve,
/// three consecutive kept points at a time (a point between excluded ones bridges the gap;
/// the noise is independent across it): for speeds x_{j-1} < x_j < x_{j+1} and residuals r,
///
/// ```text
/// a = (x_{j+1} - x_j) / (x_{j+1} - x_{j-1}),   b = (x_j - x_{j-1}) / (x_{j+1} - x_{j-1}),
/// e_j = (a r_{j-1} + b r_{j+1} - r_j) / sqrt(a^2 + b^2 + 1)
/// ```
///
/// which removes any residual linear in x and has variance sigma^2 under constant noise. Under
/// the noise model its variance is floor^2 + relative^2 L_j^2 with the effective level
/// L_j^2 = (a^2 l_{j-1}^2 + b^2 l_{j+1}^2 + l_j^2) / (a^2 + b^2 + 1).
pub fn pseudo_residuals(input: &PseudoInput) -> Pseudo {
    let mut out = Pseudo::default();
    // Coefficient rows (c_{j-1}, c_j, c_{j+1}) of consecutive pseudo-residuals, for kappa.
    let mut rows: Vec<Vec<[f64; 3]>> = Vec::new();
    for (i, x) in input.speeds.iter().enumerate() {
        let kept: Vec<usize> = (0..x.len()).filter(|&j| input.mask[i][j]).collect();
        let mut curve_rows = Vec::new();
        for w in kept.windows(3) {
            let (p, j, n) = (w[0], w[1], w[2]);
            let span = x[n] - x[p];
            if span <= 0.0 {
                continue;
            }
            let a = (x[n] - x[j]) / span;
            let b = (x[j] - x[p]) / span;
            let norm = (a * a + b * b + 1.0).sqrt();
            let (r, l) = (&input.residuals[i], &input.levels[i]);
            out.values.push((a * r[p] + b * r[n] - r[j]) / norm);
            out.levels
                .push(((a * l[p]).powi(2) + (b * l[n]).powi(2) + l[j].powi(2)).sqrt() / norm);
            curve_rows.push([a / norm, -1.0 / norm, b / norm]);
        }
        rows.push(curve_rows);
    }
    out.kappa = overlap_inflation(&rows);
    out
}

/// sum_jk R_jk^2 / n for pseudo-residuals made of consecutive triples with coefficient rows
/// `rows` (per curve): row j covers points (j, j+1, j+2) of the curve's kept sequence, so rows
/// up to two apart share points.
fn overlap_inflation(rows: &[Vec<[f64; 3]>]) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for curve in rows {
        for (j, rj) in curve.iter().enumerate() {
            n += 1;
            sum += 1.0; // R_jj = 1: each row has unit norm
            for lag in 1..=2 {
                if let Some(rk) = curve.get(j + lag) {
                    // Row j covers offsets 0,1,2 from j; row j+lag covers lag, lag+1, lag+2.
                    let cov: f64 = (lag..3).map(|o| rj[o] * rk[o - lag]).sum();
                    sum += 2.0 * cov * cov;
                }
            }
        }
    }
    if n == 0 {
        1.0
    } else {
        sum / n as f64
    }
}

/// Maximum pseudo-likelihood noise model of the pseudo-residuals `keep` selects, under
/// `dist`, and its negative log-likelihood.
fn fit_kept(
    pseudo: &Pseudo,
    keep: &[bool],
    freedom: NoiseFreedom,
    dist: Distribution,
) -> Result<(NoiseModel, f64)> {
    with_kept(pseudo, keep, |data| estimate_noise(data, freedom, dist))
}

/// [`fit_kept`] with the pseudo-residuals beyond [`TRIM_Z`] of the fitted scale trimmed,
/// iterated until the kept set settles (Gaussian errors; Student-t errors down-weight their own
/// outliers and trim nothing). Returns the model, its negative log-likelihood and the kept set.
fn trimmed_fit(
    pseudo: &Pseudo,
    freedom: NoiseFreedom,
    dist: Distribution,
) -> Result<(NoiseModel, f64, Vec<bool>)> {
    let n = pseudo.values.len();
    let mut keep = vec![true; n];
    let mut fit = fit_kept(pseudo, &keep, freedom, dist)?;
    if matches!(dist, Distribution::StudentT { .. }) {
        return Ok((fit.0, fit.1, keep));
    }
    for _ in 0..TRIM_ROUNDS {
        let next: Vec<bool> = (0..n)
            .map(|k| (pseudo.values[k] / fit.0.scale(pseudo.levels[k])).abs() <= TRIM_Z)
            .collect();
        if next == keep || next.iter().filter(|k| **k).count() < 3 {
            break;
        }
        keep = next;
        fit = fit_kept(pseudo, &keep, freedom, dist)?;
    }
    Ok((fit.0, fit.1, keep))
}

/// How the tails of the errors are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TailChoice {
    /// Gaussian errors.
    Gaussian,
    /// Student-t errors when the adjusted likelihood-ratio test on the pseudo-residuals rejects
    /// Gaussian ones at 5%.
    Auto,
}

/// Estimate the noise from the pseudo-residuals of `input` (floor at least `floor_min`): the
/// floor-plus-relative model trimmed at [`TRIM_Z`]; on its kept pseudo-residuals the constant
/// model, and the relative part kept when the adjusted likelihood ratio (divided by
/// [`Pseudo::kappa`]) exceeds the boundary test's 5% point; with [`TailChoice::Auto`], Student-t
/// errors (dof profiled on a grid, untrimmed) when they beat the untrimmed Gaussian model by the
/// same test.
pub fn estimate(input: &PseudoInput, floor_min: f64, tails: TailChoice) -> Result<DiscoveryNoise> {
    let pseudo = pseudo_residuals(input);
    if pseudo.values.len() < 10 {
        return Err(GearError::Numerical(format!(
            "the noise cannot be estimated from {} pseudo-residuals (three consecutive kept points make one); state it with --noise-um or rig.toml [noise]",
            pseudo.values.len()
        )));
    }
    let free = |relative| NoiseFreedom {
        floor_min,
        relative,
    };
    let gauss = Distribution::Gaussian;
    let (general, nll_general, keep) = trimmed_fit(&pseudo, free(true), gauss)?;
    let (_, nll_constant) = fit_kept(&pseudo, &keep, free(false), gauss)?;
    let relative_lr = 2.0 * (nll_constant - nll_general).max(0.0) / pseudo.kappa;
    let use_relative = relative_lr > BOUNDARY_LR_CRITICAL && general.relative > 0.0;
    let freedom = free(use_relative);
    let (mut model, _, mut kept) = if use_relative {
        (general, nll_general, keep)
    } else {
        trimmed_fit(&pseudo, freedom, gauss)?
    };
    // The model the replicates are drawn from where the relative part is dropped: the chosen
    // distribution with that part free (see `DiscoveryNoise::replicate_model`).
    let mut unrestricted = general;
    let mut tails_lr = None;
    if tails == TailChoice::Auto {
        let all = vec![true; pseudo.values.len()];
        let (_, nll_gauss) = fit_kept(&pseudo, &all, freedom, gauss)?;
        let mut best_t: Option<(NoiseModel, f64)> = None;
        for dof in T_DOF_GRID {
            let fit = fit_kept(&pseudo, &all, freedom, Distribution::StudentT { dof })?;
            if best_t.as_ref().is_none_or(|b| fit.1 < b.1) {
                best_t = Some(fit);
            }
        }
        if let Some((t, nll_t)) = best_t {
            let lr = 2.0 * (nll_gauss - nll_t).max(0.0) / pseudo.kappa;
            tails_lr = Some(lr);
            if lr > BOUNDARY_LR_CRITICAL {
                model = t;
                if !use_relative {
                    unrestricted = fit_kept(&pseudo, &all, free(true), t.distribution)?.0;
                }
                kept = all;
            }
        }
    }
    let replicate_model = (!use_relative && unrestricted.relative > 0.0).then_some(unrestricted);
    let trimmed = kept.iter().filter(|k| !**k).count();
    let components = components_of(&pseudo, &kept, freedom, &model);
    Ok(DiscoveryNoise {
        origin: NoiseOrigin::Estimated { floor_min },
        model,
        per_point: None,
        relative_estimated: use_relative,
        replicate_model,
        relative_lr: Some(relative_lr),
        tails_lr,
        pseudo_residuals: pseudo.values.len(),
        trimmed,
        components: Some(components),
    })
}

/// The variance components of `model` fitted to the pseudo-residuals `keep` selects, their
/// covariance adjusted for the pseudo-residuals' overlap ([`Pseudo::kappa`]); a component held
/// at its boundary ([`held_variance_components`]) has zero variance.
fn components_of(
    pseudo: &Pseudo,
    keep: &[bool],
    freedom: NoiseFreedom,
    model: &NoiseModel,
) -> VarianceComponents {
    with_kept(pseudo, keep, |data| {
        held_variance_components(data, freedom, model)
    })
    .inflated(pseudo.kappa)
}

/// `f` of the pseudo-residuals `keep` selects, as the engine's noise data (no leverage: they
/// are not a fit's residuals).
fn with_kept<T>(pseudo: &Pseudo, keep: &[bool], f: impl FnOnce(&NoiseData) -> T) -> T {
    let pick = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .zip(keep)
            .filter(|(_, k)| **k)
            .map(|(x, _)| *x)
            .collect()
    };
    let (values, levels) = (pick(&pseudo.values), pick(&pseudo.levels));
    let leverages = vec![0.0; values.len()];
    f(&NoiseData {
        residuals: &values,
        levels: &levels,
        leverages: &leverages,
        correlation: None,
        jacobian: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Speeds, residuals, levels and mask of a test set.
    type TestSet = (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<bool>>);

    /// Residuals drawn from a model on a resonance-like level curve over `curves` curves of an
    /// uneven speed grid, with a smooth misfit `misfit(x)` added.
    fn set(truth: NoiseModel, seed: u64, misfit: impl Fn(f64) -> f64) -> TestSet {
        let mut rng = Rng::new(seed);
        let mut speeds = Vec::new();
        let mut residuals = Vec::new();
        let mut levels = Vec::new();
        for c in 0..4 {
            let x: Vec<f64> = (0..81)
                .map(|k| 1000.0 + 50.0 * k as f64 + 20.0 * ((k * 7 + c) % 5) as f64)
                .collect();
            let l: Vec<f64> = x
                .iter()
                .map(|s| (1.0 + c as f64) * 2.0 / ((1.0 - (s / 3000.0).powi(2)).abs() + 0.05))
                .collect();
            let r: Vec<f64> = l
                .iter()
                .zip(&x)
                .map(|(l, s)| {
                    let z = match truth.distribution {
                        Distribution::Gaussian => rng.normal(),
                        Distribution::StudentT { dof } => rng.student_t(dof),
                    };
                    truth.scale(*l) * z + misfit(*s)
                })
                .collect();
            speeds.push(x);
            levels.push(l);
            residuals.push(r);
        }
        let mask = speeds.iter().map(|x| vec![true; x.len()]).collect();
        (speeds, residuals, levels, mask)
    }

    fn estimated(
        truth: NoiseModel,
        seed: u64,
        misfit: impl Fn(f64) -> f64,
        tails: TailChoice,
    ) -> DiscoveryNoise {
        let (speeds, residuals, levels, mask) = set(truth, seed, misfit);
        let input = PseudoInput {
            speeds: &speeds,
            residuals: &residuals,
            levels: &levels,
            mask: &mask,
        };
        estimate(&input, 0.0, tails).unwrap()
    }

    /// On an even grid the pseudo-residuals are (r_{j-1} - 2 r_j + r_{j+1}) / sqrt 6, whose
    /// neighbours correlate by -2/3 and second neighbours by 1/6: kappa = 1 + 2 (4/9 + 1/36)
    /// = 1.944 (away from the curve ends).
    #[test]
    fn overlap_inflation_on_an_even_grid() {
        let x: Vec<f64> = (0..2001).map(|k| k as f64).collect();
        let zeros = vec![vec![0.0; x.len()]];
        let mask = vec![vec![true; x.len()]];
        let p = pseudo_residuals(&PseudoInput {
            speeds: &[x],
            residuals: &zeros,
            levels: &zeros,
            mask: &mask,
        });
        assert!(
            (p.kappa - (1.0 + 2.0 * (4.0 / 9.0 + 1.0 / 36.0))).abs() < 2e-3,
            "{}",
            p.kappa
        );
    }

    /// A residual linear in the speed leaves no pseudo-residual, on an uneven grid too.
    #[test]
    fn a_linear_residual_leaves_nothing() {
        let x = vec![vec![1.0, 2.5, 3.0, 4.7, 6.0, 6.1]];
        let r = vec![x[0].iter().map(|s| 3.0 - 0.4 * s).collect::<Vec<f64>>()];
        let mask = vec![vec![true; 6]];
        let p = pseudo_residuals(&PseudoInput {
            speeds: &x,
            residuals: &r,
            levels: &r,
            mask: &mask,
        });
        assert_eq!(p.values.len(), 4);
        assert!(p.values.iter().all(|e| e.abs() < 1e-12), "{:?}", p.values);
    }

    /// Floor plus relative noise on an uneven grid with a smooth misfit of 20 floors added (a
    /// missing effect): both parts recovered within 15%, the relative part kept, Gaussian
    /// errors kept. Constant noise: the relative part dropped, the floor within 10%.
    #[test]
    fn recovers_the_noise_model_under_a_smooth_misfit() {
        let truth = NoiseModel {
            floor: 0.15,
            relative: 0.03,
            distribution: Distribution::Gaussian,
            correlation_length: 0.0,
        };
        let misfit = |s: f64| 3.0 * (s / 700.0).sin();
        let n = estimated(truth, 5, misfit, TailChoice::Auto);
        assert!(n.relative_estimated, "{n:?}");
        assert!((n.model.floor / 0.15 - 1.0).abs() < 0.15, "{n:?}");
        assert!((n.model.relative / 0.03 - 1.0).abs() < 0.15, "{n:?}");
        assert_eq!(n.model.distribution, Distribution::Gaussian, "{n:?}");
        let c = estimated(NoiseModel::constant(0.2), 6, misfit, TailChoice::Auto);
        assert!(!c.relative_estimated, "{c:?}");
        assert!((c.model.floor / 0.2 - 1.0).abs() < 0.1, "{c:?}");
    }

    /// Student-t errors of 3 dof are recognised as heavy-tailed.
    #[test]
    fn heavy_tails_are_recognised() {
        let truth = NoiseModel {
            floor: 0.15,
            relative: 0.03,
            distribution: Distribution::StudentT { dof: 3.0 },
            correlation_length: 0.0,
        };
        let n = estimated(truth, 8, |_| 0.0, TailChoice::Auto);
        assert!(
            matches!(n.model.distribution, Distribution::StudentT { .. }),
            "{n:?}"
        );
    }
}
