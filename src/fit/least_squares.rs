//! Multi-start least squares with covariance-based 95% intervals.

use crate::error::{GearError, Result};
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra::DMatrix;
use serde::Serialize;

/// A model whose residuals (data minus model, divided by the measurement standard deviation
/// when known) depend on strictly positive parameters.
pub trait Residuals: Sync {
    /// Names of the parameters, for reports.
    fn names(&self) -> Vec<String>;
    /// Residual vector at parameters `p` (all > 0).
    fn residuals(&self, p: &[f64]) -> Result<Vec<f64>>;
}

/// Options of a fit.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// Starting points (each a full parameter vector, all > 0).
    pub starts: Vec<Vec<f64>>,
    /// Standard deviation of the residuals when known (weighted residuals: 1); `None` estimates it
    /// from the residual sum of squares.
    pub sigma: Option<f64>,
    /// Iteration limit per start.
    pub max_iters: u64,
}

/// Result of a least-squares fit.
#[derive(Clone, Debug, Serialize)]
pub struct FitResult {
    /// Parameter names.
    pub names: Vec<String>,
    /// Best-fit parameters.
    pub params: Vec<f64>,
    /// Residual sum of squares at the optimum.
    pub ssr: f64,
    /// Number of residuals.
    pub n: usize,
    /// Residual standard deviation used for the intervals (given, or sqrt(ssr / (n - p))).
    pub sigma: f64,
    /// Standard errors from the covariance sigma^2 (J^T J)^-1 (delta method from log space).
    pub std_errors: Vec<f64>,
    /// 95% intervals from the covariance, computed in log space (so always positive).
    pub ci95_covariance: Vec<(f64, f64)>,
    /// Best residual sum of squares reached from each start (multi-start diagnostics).
    pub start_ssr: Vec<f64>,
}

struct LogProblem<'a, R: Residuals + ?Sized> {
    model: &'a R,
}

impl<R: Residuals + ?Sized> CostFunction for LogProblem<'_, R> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> std::result::Result<f64, argmin::core::Error> {
        let p: Vec<f64> = u.iter().map(|x| x.exp()).collect();
        match self.model.residuals(&p) {
            Ok(r) => {
                let s: f64 = r.iter().map(|x| x * x).sum();
                Ok(if s.is_finite() { s } else { f64::MAX })
            }
            Err(_) => Ok(f64::MAX),
        }
    }
}

/// Minimise the residual sum of squares from every start and keep the best (log-parameters).
pub(crate) fn minimise<R: Residuals + ?Sized>(
    model: &R,
    start: &[f64],
    max_iters: u64,
) -> Result<(Vec<f64>, f64)> {
    if start.iter().any(|&x| !(x.is_finite() && x > 0.0)) {
        return Err(GearError::Numerical(
            "fit start must have finite positive parameters".into(),
        ));
    }
    let u0: Vec<f64> = start.iter().map(|x| x.ln()).collect();
    let mut simplex = vec![u0.clone()];
    for i in 0..u0.len() {
        let mut v = u0.clone();
        v[i] += 0.1;
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-14)
        .map_err(|e| GearError::Numerical(format!("Nelder-Mead setup: {e}")))?;
    let res = Executor::new(LogProblem { model }, solver)
        .configure(|s| s.max_iters(max_iters))
        .run()
        .map_err(|e| GearError::Numerical(format!("Nelder-Mead: {e}")))?;
    let u = res
        .state()
        .best_param
        .clone()
        .ok_or_else(|| GearError::Numerical("Nelder-Mead returned no parameters".into()))?;
    let cost = res.state().best_cost;
    Ok((u.iter().map(|x| x.exp()).collect(), cost))
}

/// Fit from several starts and compute covariance intervals at the best optimum.
pub fn fit<R: Residuals + ?Sized>(model: &R, opts: &FitOptions) -> Result<FitResult> {
    if opts.starts.is_empty() {
        return Err(GearError::Numerical(
            "a fit needs at least one start".into(),
        ));
    }
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut start_ssr = Vec::new();
    for s in &opts.starts {
        let (p, _) = minimise(model, s, opts.max_iters)?;
        // A second pass from the optimum restarts the simplex (Nelder-Mead can stall).
        let (p, c) = minimise(model, &p, opts.max_iters)?;
        start_ssr.push(c);
        if best.as_ref().is_none_or(|(_, b)| c < *b) {
            best = Some((p, c));
        }
    }
    let (params, ssr) = best.ok_or_else(|| GearError::Numerical("no fit converged".into()))?;
    let r0 = model.residuals(&params)?;
    let n = r0.len();
    let k = params.len();
    if n <= k {
        return Err(GearError::Numerical(format!(
            "{n} data points cannot determine {k} parameters"
        )));
    }
    let sigma = opts.sigma.unwrap_or_else(|| (ssr / (n - k) as f64).sqrt());
    // Jacobian with respect to u = ln p by central differences.
    let mut jac = DMatrix::zeros(n, k);
    for j in 0..k {
        let h: f64 = 1e-6;
        let mut up = params.clone();
        let mut dn = params.clone();
        up[j] *= h.exp();
        dn[j] *= (-h).exp();
        let (rp, rm) = (model.residuals(&up)?, model.residuals(&dn)?);
        for i in 0..n {
            jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
        }
    }
    let jtj = jac.transpose() * &jac;
    let cov_u = jtj
        .try_inverse()
        .map(|m| m * (sigma * sigma))
        .ok_or_else(|| {
            GearError::Numerical(
                "singular Jacobian: parameters not identifiable from these data".into(),
            )
        })?;
    let mut std_errors = Vec::with_capacity(k);
    let mut ci = Vec::with_capacity(k);
    for j in 0..k {
        let su = cov_u[(j, j)].max(0.0).sqrt();
        std_errors.push(params[j] * su);
        ci.push((
            params[j] * (-1.96 * su).exp(),
            params[j] * (1.96 * su).exp(),
        ));
    }
    Ok(FitResult {
        names: model.names(),
        params,
        ssr,
        n,
        sigma,
        std_errors,
        ci95_covariance: ci,
        start_ssr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y = a exp(-b x) with known a, b and no noise: the fit recovers them to 1e-6 relative.
    struct Decay {
        x: Vec<f64>,
        y: Vec<f64>,
    }
    impl Residuals for Decay {
        fn names(&self) -> Vec<String> {
            vec!["a".into(), "b".into()]
        }
        fn residuals(&self, p: &[f64]) -> Result<Vec<f64>> {
            Ok(self
                .x
                .iter()
                .zip(&self.y)
                .map(|(x, y)| y - p[0] * (-p[1] * x).exp())
                .collect())
        }
    }

    #[test]
    fn recovers_exact_parameters() {
        let x: Vec<f64> = (0..30).map(|i| i as f64 * 0.1).collect();
        let y = x.iter().map(|x| 2.5 * (-0.7 * x).exp()).collect();
        let m = Decay { x, y };
        let r = fit(
            &m,
            &FitOptions {
                starts: vec![vec![1.0, 1.0], vec![5.0, 0.1]],
                sigma: Some(0.01),
                max_iters: 2000,
            },
        )
        .unwrap();
        assert!(
            (r.params[0] - 2.5).abs() < 1e-6 && (r.params[1] - 0.7).abs() < 1e-6,
            "{:?}",
            r.params
        );
        assert!(r.ci95_covariance[0].0 < 2.5 && r.ci95_covariance[0].1 > 2.5);
    }
}
