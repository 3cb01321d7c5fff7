//! The null distribution of a discovery run's statistics: a parametric bootstrap from the fitted
//! M0 and its fitted error model, correlation along speed and tails included (Efron & Tibshirani
//! 1993, ch. 16). Each replicate is M0's curve plus errors drawn as the fit assumed them; M0 and
//! every candidate are fitted to it by the same engine and error family as the data, linearised
//! at M0 (the candidates by their columns at delta = 0): its likelihood ratios are the data's
//! statistic under the null, whatever the effects' phases and a correlated drift make of the law.

use super::effects::Candidate;
use crate::error::Result;
use crate::fit::{
    estimate, neg_log_likelihood, Axis, Correlation, Distribution, Estimate, EstimateOptions,
    Measurement, Param, Stop, Whitener,
};
use crate::numeric::Rng;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Log-likelihood of a fit at its parameters and noise on the points `axis`, the statistic's:
/// not the restricted one, whose term depends on the mean parameters' Jacobian and units, so
/// that it cannot compare models with other ones (Welham & Thompson 1997).
pub fn log_likelihood(est: &Estimate, axis: &Axis) -> f64 {
    log_likelihood_under(est, axis, est.noise.model.distribution)
}

/// [`log_likelihood`] with the curves' errors under `distribution`; the stated STEs' Gaussian
/// factor adds -z^2 / 2 each, its constant left out: every model of a run weighs the same
/// statements, so the constants cancel in each comparison.
pub fn log_likelihood_under(est: &Estimate, axis: &Axis, distribution: Distribution) -> f64 {
    let correlation = Correlation {
        axis,
        length: est.noise.model.correlation_length,
    };
    -neg_log_likelihood(
        distribution,
        &est.residuals,
        &est.noise.scales,
        Some(correlation),
    ) - 0.5 * est.measurements.iter().map(|m| m.z * m.z).sum::<f64>()
}

/// The discrepancy of M0's held-out check at a fit: -2 log of its points' standardized
/// errors' density under `distribution` (each residual over its fitted scale, the correlation
/// along speed left out), plus the stated STEs' squared z. [`standardized_deviance`] of the
/// fit's residuals.
pub fn held_discrepancy(est: &Estimate, distribution: Distribution) -> f64 {
    standardized_deviance(distribution, &est.residuals, &est.noise.scales)
        + est.measurements.iter().map(|m| m.z * m.z).sum::<f64>()
}

/// -2 log density of the standardized errors r_i / s_i under `distribution`, independent:
/// sum z^2 for Gaussian errors. Pivotal, so that a parametric bootstrap calibrates it (Davison &
/// Hinkley 1997, Sec. 2.6): without the scales' log terms, whose replicates centre on the data
/// fit's scale rather than the truth's (the full deviance is off by twice the points times the
/// scale's relative error), and without the correlation, whose innovations move with the
/// estimated length to first order (with both, the check's p-value lay below 0.05 on 13 of
/// 100 correlated null sets). A smooth misfit, which innovations difference away, counts in
/// full.
pub fn standardized_deviance(distribution: Distribution, residuals: &[f64], scales: &[f64]) -> f64 {
    let z: Vec<f64> = residuals.iter().zip(scales).map(|(r, s)| r / s).collect();
    2.0 * neg_log_likelihood(distribution, &z, &vec![1.0; z.len()], None)
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
    /// The discrepancy of M0's prediction of the held-out loads ([`HeldLinear`]), where there
    /// are any.
    pub held_deviance: Option<f64>,
}

/// M0's prediction of the held-out loads, linearised at its fit: values `f0` at their compared
/// points, derivatives (um per unit) along zeta and omega_n (`globals`) and each load's STE (`ste`,
/// a column per load, zero off its curve), the points' speed axis, and their scales: `stated`
/// per point, else a fit's noise model at `f0`. A replicate draws the held-out errors as the
/// training ones, moves zeta and omega_n as its M0 fit did, fits each STE alone as the data's
/// (a statement with uncertainty `ste_sd`, um, drawn about it and weighed) and takes the
/// discrepancy ([`held_discrepancy`]): the predictive deviance under M0, the training fit's
/// and the noise's uncertainty in it.
pub struct HeldLinear {
    pub f0: Vec<f64>,
    pub globals: DMatrix<f64>,
    pub ste: DMatrix<f64>,
    pub ste_sd: Vec<Option<f64>>,
    pub axis: Axis,
    pub stated: Option<Vec<f64>>,
    /// Scales of the draws: M0's data fit's noise at these points.
    pub draw_scales: Vec<f64>,
}

impl HeldLinear {
    /// The discrepancy at errors `e` after the training loads' M0 fit moved zeta and omega_n by
    /// `moved` and estimated the noise `model`: each load's STE fitted alone (Gaussian weighted
    /// least squares, decorrelated along speed, its statement's standardized error `stated_z[k]`
    /// one more row), then [`standardized_deviance`] under `model`'s distribution plus the
    /// statements' squared z.
    pub fn deviance(
        &self,
        (e, stated_z): (&[f64], &[f64]),
        moved: [f64; 2],
        model: &crate::fit::NoiseModel,
    ) -> f64 {
        let scales = match &self.stated {
            Some(s) => s.clone(),
            None => self.f0.iter().map(|&f| model.scale(f)).collect(),
        };
        let whitener = Whitener::unit(scales.clone(), Some(&self.axis), model.correlation_length);
        let whiten = |v: &[f64]| whitener.innovations(v);
        let mut r: Vec<f64> = e.to_vec();
        for (k, dk) in moved.iter().enumerate() {
            for (ri, jk) in r.iter_mut().zip(self.globals.column(k).iter()) {
                *ri -= jk * dk;
            }
        }
        // The columns lie on separate curves, whose innovations are separate: each load's
        // least-squares step is its own projection.
        let w = whiten(&r);
        let mut stated_deviance = 0.0;
        for k in 0..self.ste.ncols() {
            let col: Vec<f64> = self.ste.column(k).iter().copied().collect();
            let c = whiten(&col);
            // The statement's row: residual z (s - e0 = sd z), derivative 1 / sd per um.
            let (z, inv_sd) = match self.ste_sd.get(k).copied().flatten() {
                Some(sd) => (stated_z.get(k).copied().unwrap_or(0.0), 1.0 / sd),
                None => (0.0, 0.0),
            };
            let cc: f64 = c.iter().map(|x| x * x).sum::<f64>() + inv_sd * inv_sd;
            if cc > 0.0 {
                let step = (c.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() + z * inv_sd) / cc;
                for (ri, ck) in r.iter_mut().zip(&col) {
                    *ri -= ck * step;
                }
                stated_deviance += (z - step * inv_sd).powi(2);
            }
        }
        standardized_deviance(model.distribution, &r, &scales) + stated_deviance
    }
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
        let mut y = null.f0.to_vec();
        let m0 = p.iter().zip(null.p0).map(|(pk, p0k)| pk - p0k);
        let delta = d.map(|d| (&p[null.p0.len()..], d));
        let steps = m0.zip(null.j0.column_iter()).chain(
            delta
                .into_iter()
                .flat_map(|(p, d)| p.iter().copied().zip(d.column_iter())),
        );
        for (dp, column) in steps.filter(|(dp, _)| *dp != 0.0) {
            for (yi, jik) in y.iter_mut().zip(column.iter()) {
                *yi += jik * dp;
            }
        }
        Ok(y)
    }
}

/// The replicates' statistics: `b` replicates from seed `seed`, each fitted by M0 and by M0 plus
/// each candidate's `columns`, each model with its own options (the starts set here), each one
/// done advancing `progress`. A replicate whose M0 fit fails is left out; a candidate fit that
/// fails is None in its replicate.
pub fn replicates(
    null: &NullModel,
    columns: &[Columns],
    errors: &ErrorModel,
    held: Option<&HeldLinear>,
    (b, seed): (usize, u64),
    progress: &dyn crate::progress::Progress,
) -> Vec<Replicate> {
    let axis = errors.axis;
    let stop = Stop::converged(20);
    let replicate = |k: usize| -> Option<Replicate> {
        let mut rng = Rng::new(seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let y: Vec<f64> = null
            .f0
            .iter()
            .zip(errors.draw(&mut rng))
            .map(|(f, e)| f + e)
            .collect();
        // The stated STEs drawn about M0's, as the data's were stated about the true ones;
        // after the curves' errors, so that those are the same with or without statements.
        let stated: Vec<Measurement> = null
            .options
            .measurements
            .iter()
            .map(|m| Measurement {
                value: null.p0[m.param] + m.sd * rng.normal(),
                ..*m
            })
            .collect();
        let fit =
            |d: Option<&DMatrix<f64>>, scale: f64, opts: &EstimateOptions| -> Result<Estimate> {
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
                    measurements: stated.clone(),
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
        // Drawn after the training errors, so that those are the same with or without it.
        let held_deviance = held.map(|h| {
            let e = ErrorModel {
                scales: &h.draw_scales,
                axis: &h.axis,
                ..*errors
            }
            .draw(&mut rng);
            let z: Vec<f64> = h
                .ste_sd
                .iter()
                .map(|sd| sd.map_or(0.0, |_| rng.normal()))
                .collect();
            let moved = [m0.params[0] - null.p0[0], m0.params[1] - null.p0[1]];
            h.deviance((&e, &z), moved, &m0.noise.model)
        });
        Some(Replicate {
            chi_square: m0.chi_square,
            lr,
            held_deviance,
        })
    };
    (0..b)
        .into_par_iter()
        .filter_map(|k| {
            let r = replicate(k);
            progress.advance(1);
            r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::HeldLinear;
    use crate::fit::{Axis, NoiseModel};
    use nalgebra::DMatrix;

    /// Two held-out curves of three points, noise 0.5 um: an error along a curve's STE column
    /// is that STE's fit and leaves no deviance beyond the constant; a move of zeta that the
    /// STEs cannot follow leaves exactly its whitened square.
    #[test]
    fn the_held_out_deviance_fits_each_ste_and_keeps_what_the_globals_moved() {
        let axis = Axis::new(vec![0, 0, 0, 1, 1, 1], vec![1.0, 2.0, 3.0, 1.0, 2.0, 3.0]).unwrap();
        let ste = DMatrix::from_row_slice(
            6,
            2,
            &[1.0, 0.0, 2.0, 0.0, 3.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0],
        );
        // Zeta moves the first point of each curve only (orthogonal to nothing in particular).
        let globals = DMatrix::from_row_slice(
            6,
            2,
            &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        );
        let h = HeldLinear {
            f0: vec![1.0; 6],
            globals,
            ste,
            ste_sd: vec![None, None],
            axis,
            stated: None,
            draw_scales: vec![0.5; 6],
        };
        let noise = NoiseModel::constant(0.5);
        let constant = 6.0 * (2.0 * std::f64::consts::PI).ln();
        let along_ste = [0.3, 0.6, 0.9, -0.2, -0.2, -0.2];
        let d = h.deviance((&along_ste, &[]), [0.0, 0.0], &noise);
        assert!((d - constant).abs() < 1e-9, "{d} vs {constant}");
        // Zeta moved by 0.1: residual -0.1 at each curve's first point. Curve 1's STE column
        // (1, 2, 3) takes its projection -0.1/14 (1, 2, 3): what is left has square
        // 0.01 (1 - 1/14); curve 2's (1, 1, 1) leaves 0.01 (1 - 1/3). Whitened by 0.5^2.
        let d = h.deviance((&[0.0; 6], &[]), [0.1, 0.0], &noise);
        let expected = constant + (0.01 * (1.0 - 1.0 / 14.0) + 0.01 * (1.0 - 1.0 / 3.0)) / 0.25;
        assert!((d - expected).abs() < 1e-9, "{d} vs {expected}");

        // Curve 1's STE stated with sd 0.05 um, its statement 1 sd above the fitted STE, the
        // error 0.1 along its column: one least-squares problem of the whitened column
        // (2, 4, 6) and the statement's row 1 / sd = 20 against (0.2, 0.4, 0.6) and z = 1,
        // whose least sum of squares is y'y - (x'y)^2 / x'x.
        let stated = HeldLinear {
            ste_sd: vec![Some(0.05), None],
            ..h
        };
        let (a, z, inv_sd) = (0.1, 1.0, 20.0);
        let e = [a, 2.0 * a, 3.0 * a, 0.0, 0.0, 0.0];
        let d = stated.deviance((&e, &[z, 0.0]), [0.0, 0.0], &noise);
        let (xy, xx, yy) = (
            56.0 * a + inv_sd * z,
            56.0 + inv_sd * inv_sd,
            56.0 * a * a + z * z,
        );
        let expected = constant + yy - xy * xy / xx;
        assert!((d - expected).abs() < 1e-9, "{d} vs {expected}");
    }

    /// With errors correlated along speed (length 1, neighbours rho = e^-1), a load's STE is
    /// its generalised least-squares step, and the discrepancy the standardized residuals'
    /// plain squares: the error 0.3 at curve 2's last point gives, through the AR(1)
    /// precision's row sums (1, 1 - rho, 1), the step 0.3 / (3 - rho).
    #[test]
    fn with_correlated_errors_the_ste_is_the_gls_step_and_the_discrepancy_plain_squares() {
        let axis = Axis::new(vec![0, 0, 0, 1, 1, 1], vec![1.0, 2.0, 3.0, 1.0, 2.0, 3.0]).unwrap();
        let ste = DMatrix::from_row_slice(
            6,
            2,
            &[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0],
        );
        let h = HeldLinear {
            f0: vec![1.0; 6],
            globals: DMatrix::zeros(6, 2),
            ste,
            ste_sd: vec![None, None],
            axis,
            stated: None,
            draw_scales: vec![0.5; 6],
        };
        let noise = NoiseModel {
            correlation_length: 1.0,
            ..NoiseModel::constant(0.5)
        };
        let rho = (-1.0f64).exp();
        let step = 0.3 / (3.0 - rho);
        let squares = 2.0 * step * step + (0.3 - step).powi(2);
        let constant = 6.0 * (2.0 * std::f64::consts::PI).ln();
        let d = h.deviance((&[0.0, 0.0, 0.0, 0.0, 0.0, 0.3], &[]), [0.0, 0.0], &noise);
        let expected = constant + squares / 0.25;
        assert!((d - expected).abs() < 1e-9, "{d} vs {expected}");
    }
}
