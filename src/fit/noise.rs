//! The measurement-noise model, part of the likelihood of every fit: the scale of the error at
//! a point grows with the level of the curve there,
//!
//! ```text
//! sigma_i^2 = floor^2 + (relative * mu_i)^2
//! ```
//!
//! (a constant floor, e.g. a pixel of a digitized figure or the instrument's resolution, plus a
//! part proportional to the response: near a resonance the scatter of measured DTE is several
//! times the floor), with Gaussian errors or, for data with outliers, Student-t errors of `dof`
//! degrees of freedom and scale sigma_i (Lange, Little & Taylor 1989). mu_i is the model's value
//! at the point (Carroll & Ruppert 1988, ch. 2: the variance function of the mean, not of the
//! observation, whose own error would bias the weights).
//!
//! Its parameters are estimated from the residuals of a fit with the mean held
//! (pseudo-likelihood, Carroll & Ruppert 1988, Sec. 3.2) by the restricted likelihood, whose
//! term 1/2 log det of the fit's information keeps the p fitted parameters from biasing the
//! noise low ([`restricted_term`]); residuals that are no fit's (discover's pseudo-residuals)
//! are divided by sqrt(1 - h_ii) instead.
//!
//! The errors of one curve may be correlated along speed (docs/correlated-errors.md,
//! [`super::correlation`]): the model's `correlation_length`, estimated by profiling the
//! likelihood over it ([`estimate_length`]).

use super::correlation::{length_bounds, Axis, Correlation};
use crate::error::{GearError, Result};
use crate::numeric::Rng;
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra::DMatrix;
use serde::Serialize;
use statrs::function::gamma::ln_gamma;

/// Error distribution of the noise model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Distribution {
    Gaussian,
    /// Student-t with `dof` degrees of freedom (heavy tails; the fit down-weights outliers).
    StudentT {
        dof: f64,
    },
}

impl Distribution {
    /// Standard deviation over the scale: 1 for Gaussian errors, sqrt(dof / (dof - 2)) for
    /// Student-t ones (dof > 2).
    pub fn sd_factor(self) -> f64 {
        match self {
            Distribution::Gaussian => 1.0,
            Distribution::StudentT { dof } => (dof / (dof - 2.0)).sqrt(),
        }
    }
}

/// Noise scale as a function of the level: sigma^2 = floor^2 + (relative * level)^2.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NoiseModel {
    /// Constant part, in the data's unit (> 0).
    pub floor: f64,
    /// Part proportional to the level (>= 0, dimensionless).
    pub relative: f64,
    pub distribution: Distribution,
    /// Length (rpm) of the errors' correlation along speed within a curve,
    /// exp(-|s_i - s_j| / length); 0 for independent errors (docs/correlated-errors.md).
    pub correlation_length: f64,
}

impl NoiseModel {
    /// Gaussian noise of one standard deviation everywhere.
    pub fn constant(sd: f64) -> NoiseModel {
        NoiseModel {
            floor: sd,
            relative: 0.0,
            distribution: Distribution::Gaussian,
            correlation_length: 0.0,
        }
    }

    /// Scale sigma at a level (the standard deviation for Gaussian errors).
    pub fn scale(&self, level: f64) -> f64 {
        (self.floor * self.floor + (self.relative * level).powi(2)).sqrt()
    }

    /// One error drawn at a level.
    pub fn draw(&self, level: f64, rng: &mut Rng) -> f64 {
        let z = match self.distribution {
            Distribution::Gaussian => rng.normal(),
            Distribution::StudentT { dof } => rng.student_t(dof),
        };
        self.scale(level) * z
    }

    /// Log-likelihood of standardized residuals z_i = r_i / sigma_i with scales sigma_i.
    pub fn log_likelihood(&self, residuals: &[f64], scales: &[f64]) -> f64 {
        log_likelihood(self.distribution, residuals, scales)
    }
}

/// Signed root of the deviance of a standardized residual z under `dist`:
/// sign(z) sqrt(2 (log f(0) - log f(z))), so that the sum of their squares is -2 log L up to a
/// constant (the scales held). z itself for Gaussian errors; sign(z) sqrt((dof + 1)
/// ln(1 + z^2 / dof)) for Student-t errors (McCullagh & Nelder 1989, Sec. 2.4.3), which is
/// smooth through z = 0 (slope sqrt((dof + 1) / dof)), so least squares can minimise it.
pub fn deviance_residual(dist: Distribution, z: f64) -> f64 {
    match dist {
        Distribution::Gaussian => z,
        Distribution::StudentT { dof } => z.signum() * ((dof + 1.0) * (z * z / dof).ln_1p()).sqrt(),
    }
}

/// Log-likelihood of residuals r_i with scales s_i under `dist`.
pub fn log_likelihood(dist: Distribution, residuals: &[f64], scales: &[f64]) -> f64 {
    let ln2pi = (2.0 * std::f64::consts::PI).ln();
    match dist {
        Distribution::Gaussian => residuals
            .iter()
            .zip(scales)
            .map(|(r, s)| -0.5 * ln2pi - s.ln() - 0.5 * (r / s).powi(2))
            .sum(),
        Distribution::StudentT { dof: v } => {
            let c = ln_gamma(0.5 * (v + 1.0))
                - ln_gamma(0.5 * v)
                - 0.5 * (v * std::f64::consts::PI).ln();
            residuals
                .iter()
                .zip(scales)
                .map(|(r, s)| c - s.ln() - 0.5 * (v + 1.0) * (1.0 + (r / s).powi(2) / v).ln())
                .sum()
        }
    }
}

/// -log L of residuals r_i with scales s_i under `dist` and, where given, their correlation
/// along speed (docs/correlated-errors.md): the innovations' -log L plus sum log s_i plus
/// 1/2 sum log(1 - phi_k^2). With independent errors -[`log_likelihood`].
pub fn neg_log_likelihood(
    dist: Distribution,
    residuals: &[f64],
    scales: &[f64],
    correlation: Option<Correlation>,
) -> f64 {
    match correlation.filter(|c| c.length > 0.0) {
        None => -log_likelihood(dist, residuals, scales),
        Some(c) => {
            let z: Vec<f64> = residuals.iter().zip(scales).map(|(r, s)| r / s).collect();
            let e = c.innovations(&z);
            -log_likelihood(dist, &e, &vec![1.0; e.len()])
                + scales.iter().map(|s| s.ln()).sum::<f64>()
                + c.half_log_det()
        }
    }
}

/// The restricted likelihood's term 1/2 log det(G'G), G the model's Jacobian `jacobian`
/// (times the information factor of Student-t errors under `dist`)
/// standardized by `scales` and decorrelated along speed like the residuals (columns the
/// model does not see left out): added to -log L of the residuals at the fit, it is -log of the
/// likelihood of the residuals' error contrasts (REML, Patterson & Thompson 1971; for a model
/// nonlinear in its parameters at its linearisation, Harville 1977). Maximum likelihood with the
/// mean's parameters estimated biases the noise low: the scale by the fitted parameters' share
/// of the residuals (what the leverage correction removes), and a correlation length the more,
/// since the fitted curve absorbs the slow part of correlated errors.
pub fn restricted_term(
    dist: Distribution,
    jacobian: &DMatrix<f64>,
    scales: &[f64],
    correlation: Option<Correlation>,
) -> f64 {
    let keep: Vec<usize> = (0..jacobian.ncols())
        .filter(|&c| jacobian.column(c).norm() > 0.0)
        .collect();
    // No parameter moves the curve here (e.g. a trial step where the model's curve is flat
    // in every parameter): there is nothing for the restriction to take out.
    if keep.is_empty() {
        return 0.0;
    }
    // Student-t errors carry (dof + 1) / (dof + 3) of the Gaussian information per point (the
    // Fisher information of the fit's intervals): without it the term would favour large dof.
    let factor = match dist {
        Distribution::Gaussian => 1.0,
        Distribution::StudentT { dof } => (dof + 1.0) / (dof + 3.0),
    };
    let mut info = standardized_gram(jacobian, &keep, scales, correlation);
    // Columns scaled to unit norm, so that the rank cut below does not depend on the
    // parameters' units; their norms return as 2 sum log |g_c|.
    let norms: Vec<f64> = (0..keep.len()).map(|c| info[(c, c)].sqrt()).collect();
    for a in 0..keep.len() {
        for b in 0..keep.len() {
            if norms[a] > 0.0 && norms[b] > 0.0 {
                info[(a, b)] *= factor / (norms[a] * norms[b]);
            }
        }
    }
    let log_norms: f64 = norms.iter().filter(|n| **n > 0.0).map(|n| n.ln()).sum();
    0.5 * log_det_above_cut(info) + log_norms
}

/// log det of a symmetric positive semi-definite matrix over its eigenvalues above 1e-12 of the
/// largest (the directions the data do not determine left out). By Cholesky when its
/// determinant proves every eigenvalue above the cut (lambda_min >= det / trace^(p-1), lambda_max
/// <= trace), which is the usual case and several times cheaper than the eigenvalues; by the
/// eigenvalues otherwise.
fn log_det_above_cut(a: DMatrix<f64>) -> f64 {
    const CUT: f64 = 1e-12;
    let p = a.nrows() as i32;
    let trace = a.trace();
    if let Some(l) = a.clone().cholesky() {
        let log_det: f64 = l.l_dirty().diagonal().iter().map(|d| 2.0 * d.ln()).sum();
        if log_det - f64::from(p - 1) * trace.ln() > (CUT * trace).ln() {
            return log_det;
        }
    }
    let eigen = a.symmetric_eigenvalues();
    let top = eigen.iter().fold(0.0f64, |a, b| a.max(*b));
    eigen
        .iter()
        .filter(|v| **v > CUT * top)
        .map(|v| v.ln())
        .sum::<f64>()
}

/// G'G for the columns `keep` of the Jacobian, G standardized by `scales` and decorrelated
/// along speed like the residuals.
fn standardized_gram(
    jacobian: &DMatrix<f64>,
    keep: &[usize],
    scales: &[f64],
    correlation: Option<Correlation>,
) -> DMatrix<f64> {
    let mut g = DMatrix::from_fn(jacobian.nrows(), keep.len(), |i, c| {
        jacobian[(i, keep[c])] / scales[i]
    });
    if let Some(c) = correlation.filter(|c| c.length > 0.0) {
        g = c.innovations_of_columns(&g);
    }
    // G'G without forming G' (the noise search evaluates this hundreds of times per fit).
    g.tr_mul(&g)
}

/// Weight of a point in the iteratively reweighted fit under `dist`, relative to 1 / sigma^2:
/// 1 for Gaussian errors, (dof + 1) / (dof + z^2) for Student-t (the E-step of Lange, Little &
/// Taylor 1989, eq. 4).
pub fn robust_weight(dist: Distribution, z: f64) -> f64 {
    match dist {
        Distribution::Gaussian => 1.0,
        Distribution::StudentT { dof } => (dof + 1.0) / (dof + z * z),
    }
}

/// Which noise parameters are estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseFreedom {
    /// The floor may not go below this (a digitized set's reading uncertainty; 0 otherwise).
    pub floor_min: f64,
    /// Estimate the relative part (false: floor only, constant noise).
    pub relative: bool,
}

/// Residuals as the noise estimate sees them: r_i, the model's level mu_i there, the leverage
/// h_ii of the point (of its innovation, with correlated errors) in the fit, the errors'
/// correlation along speed, held (None: independent), and the model's Jacobian at the fit
/// (n x p), where there is one: the noise is then estimated by the restricted likelihood
/// ([`restricted_term`]) instead of the leverage correction.
pub struct NoiseData<'a> {
    pub residuals: &'a [f64],
    pub levels: &'a [f64],
    pub leverages: &'a [f64],
    pub correlation: Option<Correlation<'a>>,
    pub jacobian: Option<&'a DMatrix<f64>>,
}

impl NoiseData<'_> {
    /// The held correlation length (0: independent).
    fn length(&self) -> f64 {
        self.correlation.map_or(0.0, |c| c.length)
    }
}

struct NegLogLik<'a> {
    data: &'a NoiseData<'a>,
    freedom: NoiseFreedom,
    dist: Distribution,
    /// The correlation length estimated too, on this axis (the last coordinate, ln L); None:
    /// held as `data` holds it.
    free_length: Option<&'a Axis>,
}

impl NegLogLik<'_> {
    /// (floor, relative) from the optimiser's unconstrained coordinates: floor =
    /// sqrt(floor_min^2 + e^2a), relative = e^b.
    fn model(&self, x: &[f64]) -> NoiseModel {
        let floor = (self.freedom.floor_min.powi(2) + (2.0 * x[0]).exp()).sqrt();
        let relative = if self.freedom.relative {
            x[1].exp()
        } else {
            0.0
        };
        NoiseModel {
            floor,
            relative,
            distribution: self.dist,
            correlation_length: match (self.free_length, x.last()) {
                (Some(axis), Some(u)) => {
                    let (lo, hi) = length_bounds(axis).unwrap_or((0.0, f64::INFINITY));
                    u.exp().clamp(0.5 * lo, hi)
                }
                _ => self.data.length(),
            },
        }
    }

    /// -log L of the residuals, each (each innovation, with correlated errors) divided by
    /// sqrt(1 - h); or, given the model's Jacobian, their restricted -log L.
    fn value(&self, m: &NoiseModel) -> f64 {
        let d = self.data;
        let scales: Vec<f64> = d.levels.iter().map(|l| m.scale(*l)).collect();
        let correlation = match self.free_length {
            Some(axis) => Some(Correlation {
                axis,
                length: m.correlation_length,
            }),
            None => d.correlation,
        };
        if let Some(j) = d.jacobian {
            return neg_log_likelihood(self.dist, d.residuals, &scales, correlation)
                + restricted_term(self.dist, j, &scales, correlation);
        }
        // Residuals that are no fit's (discover's pseudo-residuals), independent: each divided
        // by sqrt(1 - h).
        let adjusted: Vec<f64> = d
            .residuals
            .iter()
            .zip(d.leverages)
            .map(|(r, h)| r / (1.0 - h.clamp(0.0, 0.99)).sqrt())
            .collect();
        -log_likelihood(self.dist, &adjusted, &scales)
    }
}

impl CostFunction for NegLogLik<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Self::Param) -> std::result::Result<f64, argmin::core::Error> {
        let v = self.value(&self.model(x));
        Ok(if v.is_finite() { v } else { f64::MAX })
    }
}

/// The relative part below which it is reported as zero: a tenth of a per mille of the level
/// is far below any instrument's, and the likelihood is flat there.
const RELATIVE_NEGLIGIBLE: f64 = 1e-4;

/// Maximum-likelihood noise model for the residuals with the mean held, under `dist`, and
/// its negative log-likelihood. Nelder-Mead (argmin) on (ln floor, ln relative) from a floor
/// at the residuals' median absolute deviation and a relative part of 1% and 10%.
pub fn estimate_noise(
    data: &NoiseData,
    freedom: NoiseFreedom,
    dist: Distribution,
) -> Result<(NoiseModel, f64)> {
    estimate_noise_on(data, freedom, dist, None, None)
}

/// [`estimate_noise`] started from a noise model `near` the optimum (the previous step's of a
/// reweighted fit): one search from there instead of two from the residuals' spread. The
/// likelihood in (ln floor, ln relative) has one minimum on every set tried; a start near it
/// saves most of the search.
pub fn estimate_noise_near(
    data: &NoiseData,
    freedom: NoiseFreedom,
    dist: Distribution,
    near: &NoiseModel,
) -> Result<(NoiseModel, f64)> {
    estimate_noise_on(data, freedom, dist, None, Some(near))
}

/// [`estimate_noise`] with the correlation length estimated too, on `axis`, jointly in one
/// Nelder-Mead search (its start the median step, where neighbours correlate by 1/e; ten times
/// cheaper than profiling the length over inner fits), and compared with independent errors,
/// the better kept.
pub fn estimate_noise_and_length(
    data: &NoiseData,
    freedom: NoiseFreedom,
    dist: Distribution,
    axis: &Axis,
) -> Result<(NoiseModel, f64)> {
    let held = NoiseData {
        correlation: None,
        ..*data
    };
    let independent = estimate_noise(&held, freedom, dist)?;
    let Some((lo, _)) = length_bounds(axis) else {
        return Ok(independent);
    };
    // A length below the bounds' least (neighbours correlated by under e^-10) is independent
    // errors: kept, it would flip with rounding between reweighting steps.
    match estimate_noise_on(data, freedom, dist, Some(axis), None) {
        Ok(c) if c.1 < independent.1 && c.0.correlation_length > lo => Ok(c),
        _ => Ok(independent),
    }
}

fn estimate_noise_on(
    data: &NoiseData,
    freedom: NoiseFreedom,
    dist: Distribution,
    free_length: Option<&Axis>,
    near: Option<&NoiseModel>,
) -> Result<(NoiseModel, f64)> {
    let n = data.residuals.len();
    if n < 3 || data.levels.len() != n || data.leverages.len() != n {
        return Err(GearError::Numerical(
            "the noise model needs at least 3 residuals".into(),
        ));
    }
    let mut abs: Vec<f64> = data.residuals.iter().map(|r| r.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let mad = 1.4826 * abs[n / 2];
    let level_scale = data.levels.iter().map(|l| l.abs()).fold(0.0, f64::max);
    let floor0 = mad.max(1e-6 * level_scale).max(1e-300);
    let problem = NegLogLik {
        data,
        freedom,
        dist,
        free_length,
    };
    let length0 = free_length.and_then(Axis::median_step);
    let mut best: Option<(Vec<f64>, f64)> = None;
    // Starts (ln floor coordinate, relative part) and the simplex's step: from the residuals'
    // spread two relative parts a decade apart; near a known model that model, a smaller step.
    let (starts, step): (Vec<(f64, f64)>, f64) = match near {
        Some(m) => {
            let a = 0.5
                * (m.floor.powi(2) - freedom.floor_min.powi(2))
                    .max(1e-300)
                    .ln();
            (vec![(a, m.relative.max(RELATIVE_NEGLIGIBLE))], 0.1)
        }
        None if freedom.relative => (vec![(floor0.ln(), 0.01), (floor0.ln(), 0.1)], 0.5),
        None => (vec![(floor0.ln(), 0.0)], 0.5),
    };
    for (a0, rel0) in starts {
        let mut x0 = if freedom.relative {
            vec![a0, rel0.ln()]
        } else {
            vec![a0]
        };
        x0.extend(length0.map(f64::ln));
        let mut simplex = vec![x0.clone()];
        for i in 0..x0.len() {
            let mut v = x0.clone();
            v[i] += step;
            simplex.push(v);
        }
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(1e-10)
            .map_err(|e| GearError::Numerical(format!("noise model: {e}")))?;
        let res = Executor::new(
            NegLogLik {
                data,
                freedom,
                dist,
                free_length,
            },
            solver,
        )
        .configure(|s| s.max_iters(2000))
        .run()
        .map_err(|e| GearError::Numerical(format!("noise model: {e}")))?;
        let x = res
            .state()
            .best_param
            .clone()
            .ok_or_else(|| GearError::Numerical("noise model: no optimum".into()))?;
        let c = res.state().best_cost;
        if best.as_ref().is_none_or(|(_, b)| c < *b) {
            best = Some((x, c));
        }
    }
    let (x, _) = best.ok_or_else(|| GearError::Numerical("noise model: no optimum".into()))?;
    let mut m = problem.model(&x);
    if m.relative < RELATIVE_NEGLIGIBLE {
        m.relative = 0.0;
    }
    let nll = problem.value(&m);
    if !(nll.is_finite() && m.floor > 0.0) {
        return Err(GearError::Numerical(
            "the noise model could not be estimated from the residuals".into(),
        ));
    }
    Ok((m, nll))
}

/// Noise models with their negative log-likelihood at a held correlation length (rpm): the
/// inner fit of [`estimate_length`] and [`length_interval`].
pub type AtLength<'a> = &'a dyn Fn(f64) -> Result<(NoiseModel, f64)>;

/// Points of the coarse search over ln L, and golden-section steps after it (0.618^30 of two
/// grid cells: far below what any report prints).
const LENGTH_GRID: usize = 10;
const LENGTH_REFINE: usize = 30;

/// The noise model with its correlation length estimated too: -log L profiled over the length
/// (`at_length` refits the other noise parameters at each), on a grid of ln L over
/// [`length_bounds`] and refined by golden section about its least point, then compared with
/// independent errors (L = 0), the better kept. An axis whose curves have one point each has
/// no length to estimate.
pub fn estimate_length(axis: &Axis, at_length: AtLength) -> Result<(NoiseModel, f64)> {
    let independent = at_length(0.0)?;
    let Some((lo, hi)) = length_bounds(axis) else {
        return Ok(independent);
    };
    let (a, b) = (lo.ln(), hi.ln());
    let u_of = |k: usize| a + (b - a) * k as f64 / (LENGTH_GRID - 1) as f64;
    let nll = |u: f64| {
        at_length(u.exp())
            .map(|f| f.1)
            .ok()
            .filter(|v| !v.is_nan())
            .unwrap_or(f64::INFINITY)
    };
    let values: Vec<f64> = (0..LENGTH_GRID).map(|k| nll(u_of(k))).collect();
    let k = (0..LENGTH_GRID)
        .min_by(|&i, &j| values[i].total_cmp(&values[j]))
        .unwrap_or(0);
    let (mut x0, mut x1) = (
        u_of(k.saturating_sub(1)),
        u_of((k + 1).min(LENGTH_GRID - 1)),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (x1 - g * (x1 - x0), x0 + g * (x1 - x0));
    let (mut fc, mut fd) = (nll(c), nll(d));
    for _ in 0..LENGTH_REFINE {
        if fc < fd {
            x1 = d;
            (d, fd) = (c, fc);
            c = x1 - g * (x1 - x0);
            fc = nll(c);
        } else {
            x0 = c;
            (c, fc) = (d, fd);
            d = x0 + g * (x1 - x0);
            fd = nll(d);
        }
    }
    let candidates = [(u_of(k), values[k]), (c, fc), (d, fd)];
    let (u, f) = candidates
        .into_iter()
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap_or((u_of(k), values[k]));
    if f < independent.1 {
        at_length(u.exp())
    } else {
        Ok(independent)
    }
}

/// The profile-likelihood 95% interval of a correlation length estimated at `fitted`
/// (-log L `nll`): where -log L, the other noise parameters refitted, rises by 1.92 (chi^2_1's
/// 95% point over 2), by bisection in ln L. The lower end is 0 where independent errors lie
/// within that; the upper end None where the profile stays within it up to [`length_bounds`]'
/// largest length (a drift longer than the curves: not told from an offset).
pub fn length_interval(
    axis: &Axis,
    (fitted, nll): (f64, f64),
    at_length: AtLength,
) -> (f64, Option<f64>) {
    const RISE: f64 = 1.920_729_410_347_062;
    let Some((lo, hi)) = length_bounds(axis) else {
        return (0.0, None);
    };
    if fitted <= 0.0 {
        return (0.0, Some(fitted));
    }
    let above = |l: f64| at_length(l).map_or(true, |f| f.1 - nll > RISE);
    let crossing = |inside: f64, outside: f64| {
        let (mut a, mut b) = (inside.ln(), outside.ln());
        for _ in 0..40 {
            let m = 0.5 * (a + b);
            if above(m.exp()) {
                b = m;
            } else {
                a = m;
            }
        }
        (0.5 * (a + b)).exp()
    };
    let lower = if above(0.0) && fitted > lo {
        crossing(fitted, lo)
    } else {
        0.0
    };
    let upper = (fitted < hi && above(hi)).then(|| crossing(fitted, hi));
    (lower, upper)
}

/// The noise model's variance components (floor^2, relative^2) and their covariance from the
/// observed information of the pseudo-likelihood (numerical Hessian). Variance components
/// rather than standard deviations because a relative part at zero is a boundary where the
/// likelihood's slope in `relative` vanishes but not in `relative^2` (its information there is
/// finite, so its uncertainty is seen); differences in it are one-sided at zero. The relative
/// entries are zero when it is not estimated; infinite where the information is not positive
/// definite.
#[derive(Clone, Debug)]
pub struct VarianceComponents {
    /// floor^2 and relative^2.
    pub value: [f64; 2],
    pub covariance: [[f64; 2]; 2],
    /// Step of the differences in relative^2 (for derivatives taken on the same side).
    pub step: [f64; 2],
}

impl VarianceComponents {
    /// The covariance multiplied by `factor`: for a composite likelihood of correlated terms
    /// whose score variance is `factor` times its Hessian, the Godambe information is the
    /// Hessian over `factor` (Varin, Reid & Firth 2011, Sec. 2.3; first order).
    pub fn inflated(mut self, factor: f64) -> Self {
        for row in self.covariance.iter_mut() {
            for v in row.iter_mut() {
                *v *= factor;
            }
        }
        self
    }
}

/// Second derivatives of the negative log-likelihood in the variance components (floor^2,
/// relative^2) at a fitted model, and the steps they were taken with.
struct Curvatures {
    value: [f64; 2],
    step: [f64; 2],
    /// d2/da2, d2/dt2, d2/da dt (a = floor^2, t = relative^2); the last two zero when the
    /// relative part is not estimated.
    d2: [f64; 3],
}

fn curvatures(data: &NoiseData, freedom: NoiseFreedom, m: &NoiseModel) -> Curvatures {
    let f = |a: f64, t: f64| {
        let mm = NoiseModel {
            floor: a.max(0.0).sqrt(),
            relative: t.max(0.0).sqrt(),
            ..*m
        };
        NegLogLik {
            data,
            freedom,
            dist: m.distribution,
            free_length: None,
        }
        .value(&mm)
    };
    let a = m.floor * m.floor;
    let t = m.relative * m.relative;
    let ha = 1e-4 * a;
    let f0 = f(a, t);
    let d2a = (f(a + ha, t) - 2.0 * f0 + f(a - ha, t)) / (ha * ha);
    if !freedom.relative {
        return Curvatures {
            value: [a, 0.0],
            step: [ha, 0.0],
            d2: [d2a, 0.0, 0.0],
        };
    }
    // The relative^2 that makes the relative part equal the floor at the largest level.
    let level_max = data.levels.iter().map(|l| l.abs()).fold(0.0, f64::max);
    let ht = 1e-3 * t.max(a / level_max.max(1e-300).powi(2));
    let (t_lo, t_hi) = if t > ht {
        (t - ht, t + ht)
    } else {
        (t, t + 2.0 * ht)
    };
    let t_mid = 0.5 * (t_lo + t_hi);
    let d2t = (f(a, t_hi) - 2.0 * f(a, t_mid) + f(a, t_lo)) / (ht * ht);
    let d2at =
        (f(a + ha, t_hi) - f(a + ha, t_lo) - f(a - ha, t_hi) + f(a - ha, t_lo)) / (4.0 * ha * ht);
    Curvatures {
        value: [a, t],
        step: [ha, ht],
        d2: [d2a, d2t, d2at],
    }
}

/// The inverse of the curvatures `c` of both components (the relative part's only where
/// `relative`): infinite where the information is not positive definite.
fn full_covariance(c: &Curvatures, relative: bool) -> [[f64; 2]; 2] {
    let [d2a, d2t, d2at] = c.d2;
    if !relative {
        let v = if d2a > 0.0 { 1.0 / d2a } else { f64::INFINITY };
        return [[v, 0.0], [0.0, 0.0]];
    }
    let det = d2a * d2t - d2at * d2at;
    if det > 0.0 && d2a > 0.0 {
        [[d2t / det, -d2at / det], [-d2at / det, d2a / det]]
    } else {
        [[f64::INFINITY, 0.0], [0.0, f64::INFINITY]]
    }
}

/// Whether the floor of `m` ended at its lower bound `freedom.floor_min` (a stated reading
/// uncertainty), within 0.05%: the optimiser's floor sqrt(floor_min^2 + e^2x) reaches the bound
/// only as x runs to minus infinity, and stops a little above it.
pub fn floor_at_bound(freedom: NoiseFreedom, m: &NoiseModel) -> bool {
    freedom.floor_min > 0.0 && m.floor <= freedom.floor_min * (1.0 + 5e-4)
}

/// [`VarianceComponents`] of a fitted noise model.
pub fn variance_components(
    data: &NoiseData,
    freedom: NoiseFreedom,
    m: &NoiseModel,
) -> VarianceComponents {
    let c = curvatures(data, freedom, m);
    VarianceComponents {
        value: c.value,
        covariance: full_covariance(&c, freedom.relative),
        step: c.step,
    }
}

/// [`variance_components`] for the degrees of freedom of intervals (Satterthwaite): where the
/// information of the two is not positive definite, the component at its boundary (the one
/// carrying the smaller share of the variance at the largest level: a floor estimated at a
/// micro-fraction of the noise, a relative part at the floor's scale) is held, with zero
/// variance, as a relative part estimated at zero is, and the other's variance is the inverse of
/// its own curvature. Left infinite, every interval's degrees of freedom fell to 1 (quantile
/// 12.7): on 3 of 40 eps 0.2 sets of `discover`, whose floor was estimated at 1e-6 um under a
/// relative part of 3%.
///
/// A floor that ended at its lower bound ([`floor_at_bound`]) is held there the same way: the
/// likelihood still falls towards the smaller floors the bound forbids, so its curvature there
/// is no measure of the floor's spread (it was negative on a digitized set whose scatter of
/// 0.15 um lay under a stated reading uncertainty of 0.3 um, and every interval's degrees of
/// freedom fell to 1, widening it eightfold).
pub fn held_variance_components(
    data: &NoiseData,
    freedom: NoiseFreedom,
    m: &NoiseModel,
) -> VarianceComponents {
    let c = curvatures(data, freedom, m);
    let inverse = |d: f64| if d > 0.0 { 1.0 / d } else { f64::INFINITY };
    if floor_at_bound(freedom, m) {
        let relative = if freedom.relative {
            inverse(c.d2[1])
        } else {
            0.0
        };
        return VarianceComponents {
            value: c.value,
            covariance: [[0.0, 0.0], [0.0, relative]],
            step: c.step,
        };
    }
    let full = full_covariance(&c, freedom.relative);
    let covariance = if !freedom.relative || full.iter().flatten().all(|v| v.is_finite()) {
        full
    } else {
        let [d2a, d2t, _] = c.d2;
        let level_max = data.levels.iter().map(|l| l.abs()).fold(0.0, f64::max);
        let floor_smaller = c.value[0] < c.value[1] * level_max * level_max;
        if (floor_smaller && d2t > 0.0) || d2a <= 0.0 {
            [[0.0, 0.0], [0.0, inverse(d2t)]]
        } else {
            [[inverse(d2a), 0.0], [0.0, 0.0]]
        }
    };
    VarianceComponents {
        value: c.value,
        covariance,
        step: c.step,
    }
}

/// 95% Wald intervals of the floor and the relative part, formed on the variance components
/// ([`variance_components`]) and mapped back by the square root: the relative part's lower end
/// is 0 where relative^2's interval reaches zero, the floor's never below `floor_min`.
pub fn noise_intervals(
    data: &NoiseData,
    freedom: NoiseFreedom,
    m: &NoiseModel,
) -> ((f64, f64), Option<(f64, f64)>) {
    // A floor held at its bound leaves the relative part's spread to its own curvature.
    let vc = if floor_at_bound(freedom, m) {
        held_variance_components(data, freedom, m)
    } else {
        variance_components(data, freedom, m)
    };
    let ci = |k: usize| {
        let se = vc.covariance[k][k].sqrt();
        (
            (vc.value[k] - 1.96 * se).max(0.0).sqrt(),
            (vc.value[k] + 1.96 * se).sqrt(),
        )
    };
    let f = ci(0);
    (
        (f.0.max(freedom.floor_min), f.1),
        freedom.relative.then(|| ci(1)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Cholesky path of the restricted term's log det equals the eigenvalues' sum where it
    /// is taken, and a direction the data do not determine (a zero eigenvalue) is left out,
    /// as the eigenvalue path does.
    #[test]
    fn log_det_by_cholesky_equals_the_eigenvalues_and_leaves_out_a_null_direction() {
        let b = DMatrix::from_fn(40, 4, |i, c| {
            ((i * (c + 3)) as f64 * 0.37).sin() + 0.1 * c as f64
        });
        let a = b.tr_mul(&b);
        let by_eigen: f64 = a
            .clone()
            .symmetric_eigenvalues()
            .iter()
            .map(|v| v.ln())
            .sum();
        assert!((log_det_above_cut(a.clone()) - by_eigen).abs() < 1e-10 * by_eigen.abs().max(1.0));
        // A fifth column equal to the first: rank 4, its log det that of the four directions.
        let b5 = DMatrix::from_fn(40, 5, |i, c| b[(i, if c == 4 { 0 } else { c })]);
        let a5 = b5.tr_mul(&b5);
        let e5 = a5.clone().symmetric_eigenvalues();
        let top = e5.iter().fold(0.0f64, |m, v| m.max(*v));
        let kept: f64 = e5
            .iter()
            .filter(|v| **v > 1e-12 * top)
            .map(|v| v.ln())
            .sum();
        assert_eq!(e5.iter().filter(|v| **v > 1e-12 * top).count(), 4);
        assert!((log_det_above_cut(a5) - kept).abs() < 1e-9 * kept.abs().max(1.0));
    }

    /// The floor-plus-relative fit of residuals at levels (no leverage), and its intervals.
    fn fitted(residuals: &[f64], levels: &[f64]) -> (NoiseModel, (f64, f64), Option<(f64, f64)>) {
        let leverages = vec![0.0; residuals.len()];
        let data = NoiseData {
            residuals,
            levels,
            leverages: &leverages,
            correlation: None,
            jacobian: None,
        };
        let freedom = NoiseFreedom {
            floor_min: 0.0,
            relative: true,
        };
        let (m, _) = estimate_noise(&data, freedom, Distribution::Gaussian).unwrap();
        let (fi, ri) = noise_intervals(&data, freedom, &m);
        (m, fi, ri)
    }

    /// Residuals drawn from a known floor-plus-relative model on levels 0-50 (as a resonance
    /// curve's): the estimate is within a few standard errors of the truth, and the truth is
    /// inside both intervals.
    #[test]
    fn recovers_floor_and_relative_part() {
        let truth = NoiseModel {
            floor: 0.15,
            relative: 0.03,
            distribution: Distribution::Gaussian,
            correlation_length: 0.0,
        };
        let mut rng = Rng::new(11);
        let n = 2000;
        let levels: Vec<f64> = (0..n)
            .map(|i| 50.0 * (i as f64 / n as f64).powi(3))
            .collect();
        let residuals: Vec<f64> = levels.iter().map(|l| truth.draw(*l, &mut rng)).collect();
        let (m, fi, ri) = fitted(&residuals, &levels);
        let ri = ri.unwrap();
        assert!(fi.0 < 0.15 && fi.1 > 0.15, "{m:?} {fi:?}");
        assert!(ri.0 < 0.03 && ri.1 > 0.03, "{m:?} {ri:?}");
        assert!((m.relative - 0.03).abs() < 0.004, "{m:?}");
    }

    /// With constant noise, the relative part goes to (near) zero and its interval reaches 0.
    #[test]
    fn constant_noise_gives_a_relative_part_near_zero() {
        let mut rng = Rng::new(3);
        let n = 1000;
        let levels: Vec<f64> = (0..n).map(|i| 40.0 * i as f64 / n as f64).collect();
        let residuals: Vec<f64> = (0..n).map(|_| 0.2 * rng.normal()).collect();
        let (m, _, ri) = fitted(&residuals, &levels);
        assert!((m.floor - 0.2).abs() < 0.02, "{m:?}");
        assert!(ri.unwrap().0 == 0.0 && m.relative < 0.003, "{m:?} {ri:?}");
    }

    /// The floor respects a stated reading uncertainty as its lower bound.
    #[test]
    fn floor_never_goes_below_the_reading_uncertainty() {
        let residuals = vec![0.01, -0.02, 0.015, -0.01, 0.005, 0.02, -0.015];
        let levels = vec![1.0; 7];
        let leverages = vec![0.0; 7];
        let data = NoiseData {
            residuals: &residuals,
            levels: &levels,
            leverages: &leverages,
            correlation: None,
            jacobian: None,
        };
        let freedom = NoiseFreedom {
            floor_min: 0.5,
            relative: false,
        };
        let (m, _) = estimate_noise(&data, freedom, Distribution::Gaussian).unwrap();
        assert!(m.floor >= 0.5 && m.floor < 0.5001, "{m:?}");
    }

    /// The Student-t log-likelihood at dof 1 is the Cauchy density's, and the Gaussian one the
    /// normal density's (closed forms).
    #[test]
    fn log_likelihoods_match_closed_forms() {
        let (r, s) = (0.7, 1.3);
        let cauchy = -(std::f64::consts::PI * s * (1.0 + (r / s).powi(2))).ln();
        let t1 = log_likelihood(Distribution::StudentT { dof: 1.0 }, &[r], &[s]);
        assert!((t1 - cauchy).abs() < 1e-12, "{t1} {cauchy}");
        let normal = -(s * (2.0 * std::f64::consts::PI).sqrt()).ln() - 0.5 * (r / s).powi(2);
        let g = log_likelihood(Distribution::Gaussian, &[r], &[s]);
        assert!((g - normal).abs() < 1e-12);
    }

    /// The squared deviance residuals differ from -2 log L by a constant: the differences
    /// between two residuals' values agree with the log-likelihood's (scales held).
    #[test]
    fn deviance_residuals_square_to_minus_twice_the_log_likelihood() {
        for dist in [Distribution::Gaussian, Distribution::StudentT { dof: 3.0 }] {
            let ll = |z: f64| log_likelihood(dist, &[z], &[1.0]);
            for z in [-4.0, -0.3, 0.0, 0.2, 2.5, 30.0] {
                let d = deviance_residual(dist, z);
                assert!(
                    (d * d - 2.0 * (ll(0.0) - ll(z))).abs() < 1e-12,
                    "{dist:?} {z}"
                );
                assert_eq!(d.signum(), if z < 0.0 { -1.0 } else { 1.0 }, "{z}");
            }
        }
    }
}
