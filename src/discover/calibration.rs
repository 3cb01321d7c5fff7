//! The null distribution of a discovery run's statistics: a parametric bootstrap from the
//! fitted M0 and its fitted error model, correlation along speed and tails included (Efron &
//! Tibshirani 1993, ch. 16). Each replicate is M0's curve plus errors drawn as the fit assumed
//! them; M0 and every candidate are fitted to it by the same engine and error family as the data
//! were, linearised at M0 (its values plus its Jacobian times the parameters' change, the
//! candidates' columns their derivatives at delta = 0): the replicate's likelihood ratios are
//! then the data's statistic under the null. Nested models' ratios have this law whatever the
//! effects' phases make of their asymptotic one, and the drift of correlated errors is in it.

use super::effects::Candidate;
use crate::error::Result;
use crate::fit::{
    estimate, neg_log_likelihood, Axis, Correlation, Distribution, Estimate, EstimateOptions,
    Param, Stop,
};
use crate::numeric::Rng;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Log-likelihood (not the restricted one) of a fit at its parameters and its noise on the
/// points `axis`: the statistic's likelihood. The restricted likelihood estimates the noise;
/// it cannot compare models with other mean parameters (its term depends on their Jacobian
/// and units), the full likelihood can (Welham & Thompson 1997).
pub fn log_likelihood(est: &Estimate, axis: &Axis) -> f64 {
    let m = &est.noise.model;
    let correlation = Correlation {
        axis,
        length: m.correlation_length,
    };
    -neg_log_likelihood(
        m.distribution,
        &est.residuals,
        &est.noise.scales,
        Some(correlation),
    )
}

/// M0 linearised at its fit: values `f0` at the kept points, parameters `p0` (definitions
/// `params`), model Jacobian `j0` (um per parameter), and the options its replicate fits use.
pub struct NullModel<'a> {
    pub f0: &'a [f64],
    pub p0: &'a [f64],
    pub params: &'a [Param],
    pub j0: &'a DMatrix<f64>,
    pub options: EstimateOptions,
}

/// A candidate's derivative columns at delta = 0 (um per unit of each delta coordinate) at the
/// kept points, and the options its replicate fits use.
pub struct Columns {
    pub candidate: Candidate,
    pub d: DMatrix<f64>,
    pub options: EstimateOptions,
}

/// One replicate's statistics.
#[derive(Clone, Debug)]
pub struct Replicate {
    /// M0's chi-square of innovations.
    pub chi_square: f64,
    /// 2 (log L_c - log L_0) per candidate of the run's columns (None: its fit failed).
    pub lr: Vec<Option<f64>>,
}

/// How a replicate's errors are drawn: M0's fitted scale of each point, distribution and
/// correlation length on `axis`.
pub struct ErrorModel<'a> {
    pub scales: &'a [f64],
    pub distribution: Distribution,
    pub length: f64,
    pub axis: &'a Axis,
}

impl ErrorModel<'_> {
    /// One draw of the errors: standard innovations from the distribution, correlated along
    /// speed, times each point's scale.
    pub fn draw(&self, rng: &mut Rng) -> Vec<f64> {
        let z: Vec<f64> = (0..self.scales.len())
            .map(|_| match self.distribution {
                Distribution::Gaussian => rng.normal(),
                Distribution::StudentT { dof } => rng.student_t(dof),
            })
            .collect();
        let z = if self.length > 0.0 {
            Correlation {
                axis: self.axis,
                length: self.length,
            }
            .correlate(&z)
        } else {
            z
        };
        z.iter().zip(self.scales).map(|(z, s)| z * s).collect()
    }
}

/// The linear model f0 + J (p - p0) over M0's parameters and (past them) the candidate's
/// columns `d`, nested at zero.
fn linear_model<'a>(
    null: &'a NullModel,
    d: Option<&'a DMatrix<f64>>,
) -> impl Fn(&[f64]) -> Result<Vec<f64>> + Sync + 'a {
    move |p: &[f64]| {
        let n0 = null.p0.len();
        let mut y = null.f0.to_vec();
        for (k, (pk, p0k)) in p.iter().zip(null.p0).enumerate() {
            let dp = pk - p0k;
            if dp != 0.0 {
                for (yi, jik) in y.iter_mut().zip(null.j0.column(k).iter()) {
                    *yi += jik * dp;
                }
            }
        }
        if let Some(d) = d {
            for (k, &dk) in p[n0..].iter().enumerate() {
                if dk != 0.0 {
                    for (yi, jik) in y.iter_mut().zip(d.column(k).iter()) {
                        *yi += jik * dk;
                    }
                }
            }
        }
        Ok(y)
    }
}

/// The replicates' statistics: `b` replicates from seed `seed`, each fitted by M0 and by M0
/// plus each candidate's `columns`, each model with its own options (the starts are set here).
/// A replicate whose M0 fit fails is left out (none has on the studies' sets); a candidate fit
/// that fails is None in its replicate.
pub fn replicates(
    null: &NullModel,
    columns: &[Columns],
    errors: &ErrorModel,
    (b, seed): (usize, u64),
) -> Vec<Replicate> {
    let axis = errors.axis;
    let stop = Stop::converged(20);
    (0..b)
        .into_par_iter()
        .filter_map(|k| {
            let mut rng = Rng::new(seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let y: Vec<f64> = null
                .f0
                .iter()
                .zip(errors.draw(&mut rng))
                .map(|(f, e)| f + e)
                .collect();
            let fit = |d: Option<&DMatrix<f64>>,
                       scale: f64,
                       opts: &EstimateOptions|
             -> Result<Estimate> {
                let mut params = null.params.to_vec();
                let mut start = null.p0.to_vec();
                if let Some(d) = d {
                    for k in 0..d.ncols() {
                        params.push(Param::signed(&format!("delta_{k}"), 0.0, scale));
                        start.push(0.0);
                    }
                }
                let opts = EstimateOptions {
                    starts: vec![start],
                    stop,
                    ..opts.clone()
                };
                estimate(&linear_model(null, d), &y, &params, &opts)
            };
            let m0 = fit(None, 1.0, &null.options).ok()?;
            let l0 = log_likelihood(&m0, axis);
            let lr = columns
                .iter()
                .map(|c| {
                    fit(Some(&c.d), c.candidate.scale(), &c.options)
                        .ok()
                        .map(|e| 2.0 * (log_likelihood(&e, axis) - l0))
                })
                .collect();
            Some(Replicate {
                chi_square: m0.chi_square,
                lr,
            })
        })
        .collect()
}
