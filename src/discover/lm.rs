//! Levenberg-Marquardt least squares with a forward-difference Jacobian (Marquardt 1963 with
//! diagonal scaling, Nocedal & Wright 2006 Sec. 10.3). The discovery fits have signed
//! parameters (effects nested at zero) and an expensive residual (a simulated up-sweep per
//! load), so a derivative-based method with few evaluations suits them better than the
//! Nelder-Mead of `crate::fit`, which works on positive parameters in log space.

use crate::error::{GearError, Result};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// When a fit stops.
#[derive(Clone, Copy, Debug)]
pub struct Stop {
    /// Jacobians at most.
    pub max_iter: usize,
    /// Stop once even a full Gauss-Newton step would lower the residual sum of squares by less
    /// than this (sigma^2 units for normalised residuals; 0: only the relative 1e-9 rule).
    pub decrement: f64,
}

impl Stop {
    /// Run until a step gains less than 1e-9 relative or `max_iter` Jacobians are spent: for
    /// fits whose parameters, Jacobian or residual sum of squares are reported or tested.
    pub fn converged(max_iter: usize) -> Stop {
        Stop {
            max_iter,
            decrement: 0.0,
        }
    }

    /// Stop within about 0.01 sigma^2 of the minimum: for fits that only start a later one
    /// (and a basin comparison against a 3.84 sigma^2 threshold, which 0.01 cannot move). On
    /// an eps 0.2 set the design-load stage ran all 12 Jacobians, the last six gaining
    /// 0.013 sigma^2 together.
    pub fn near(max_iter: usize) -> Stop {
        Stop {
            max_iter,
            decrement: 0.01,
        }
    }
}

/// Result of a Levenberg-Marquardt fit.
#[derive(Clone, Debug)]
pub struct LmFit {
    /// Parameters at the optimum.
    pub params: Vec<f64>,
    /// Residual sum of squares there.
    pub rss: f64,
    /// Jacobian of the residuals (n x p) there.
    pub jacobian: DMatrix<f64>,
}

/// Forward-difference Jacobian of `f` at `p` (columns evaluated in parallel); `steps[i]` is the
/// increment of parameter i.
pub fn jacobian<F>(f: &F, p: &[f64], r0: &[f64], steps: &[f64]) -> Result<DMatrix<f64>>
where
    F: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    let cols: Vec<Result<Vec<f64>>> = (0..p.len())
        .into_par_iter()
        .map(|i| {
            let mut q = p.to_vec();
            q[i] += steps[i];
            let r = f(&q)?;
            Ok(r.iter().zip(r0).map(|(a, b)| (a - b) / steps[i]).collect())
        })
        .collect();
    let mut j = DMatrix::zeros(r0.len(), p.len());
    for (i, c) in cols.into_iter().enumerate() {
        let c = c?;
        if c.len() != r0.len() {
            return Err(GearError::Numerical(
                "residual length changed inside a fit".into(),
            ));
        }
        for (k, v) in c.into_iter().enumerate() {
            j[(k, i)] = v;
        }
    }
    Ok(j)
}

/// Residual sum of squares.
pub fn rss(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// Below this, in residual units (sigma), the residuals do not see a parameter: moving it by
/// its own size changes them by less than a thousandth of the noise, the level at which the
/// forward difference of a simulated curve is rounding rather than response.
const UNSEEN: f64 = 1e-3;

/// Hold still the parameters the residuals do not see at `p`: a column of J whose norm times
/// the parameter's size max(|p_i|, scale_i) is below [`UNSEEN`]. Marquardt's damping scales
/// with diag(J'J), so such a column's step is -g_i / a_ii, rounding over rounding squared:
/// the backlash, which the design-load curve does not depend on (the teeth stay in contact),
/// drifted to b = b_stated e^-667 in three steps and overflowed the solver. Its row and column
/// are replaced by the identity's, so its step is exactly zero; the next Jacobian looks again.
fn freeze_unseen(a: &mut DMatrix<f64>, g: &mut DVector<f64>, p: &[f64], scales: &[f64]) {
    for (i, (x, sc)) in p.iter().zip(scales).enumerate() {
        let size = x.abs().max(*sc);
        if a[(i, i)].sqrt() * size < UNSEEN {
            a.row_mut(i).fill(0.0);
            a.column_mut(i).fill(0.0);
            a[(i, i)] = 1.0;
            g[i] = 0.0;
        }
    }
}

/// Minimise |f(p)|^2 from `start`. `scales[i]` is a typical size of parameter i: the difference
/// step is 1e-4 max(|p_i|, scales[i]). A residual evaluation that fails (e.g. a trial step to an
/// invalid damping) counts as an infinitely bad step. Stops after `stop.max_iter` Jacobians,
/// when a step improves the sum of squares by less than 1e-9 relative, or when the
/// Gauss-Newton decrement g' (J'J)^-1 g (the decrease a full Gauss-Newton step would give on
/// the linearised residuals; Nocedal & Wright 2006 Sec. 10.3) falls below `stop.decrement`.
/// The decrement, unlike the last step's gain, does not depend on the damping lambda, so a
/// short, heavily damped step far from the minimum does not end the fit. A parameter the
/// residuals do not see at the current point is held there (see [`freeze_unseen`]).
pub fn levenberg_marquardt<F>(f: &F, start: &[f64], scales: &[f64], stop: Stop) -> Result<LmFit>
where
    F: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    let mut p = start.to_vec();
    let mut r = f(&p)?;
    let mut s = rss(&r);
    if !s.is_finite() {
        return Err(GearError::Numerical(
            "the fit's starting point gives non-finite residuals".into(),
        ));
    }
    let steps = |p: &[f64]| -> Vec<f64> {
        p.iter()
            .zip(scales)
            .map(|(x, sc)| 1e-4 * x.abs().max(*sc))
            .collect()
    };
    let mut j = jacobian(f, &p, &r, &steps(&p))?;
    let mut lambda = 1e-3;
    for _ in 0..stop.max_iter {
        let jt = j.transpose();
        let mut a = &jt * &j;
        let mut g = &jt * DVector::from_column_slice(&r);
        freeze_unseen(&mut a, &mut g, &p, scales);
        if stop.decrement > 0.0 {
            let mut m = a.clone();
            for i in 0..m.nrows() {
                m[(i, i)] += 1e-12 * a[(i, i)].max(1e-300);
            }
            if let Some(d) = m.lu().solve(&g) {
                if g.dot(&d) < stop.decrement {
                    break;
                }
            }
        }
        let mut improved = false;
        for _ in 0..12 {
            let mut m = a.clone();
            for i in 0..m.nrows() {
                m[(i, i)] += lambda * a[(i, i)].max(1e-12);
            }
            let Some(step) = m.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let q: Vec<f64> = p.iter().zip(step.iter()).map(|(x, d)| x + d).collect();
            let trial = f(&q).ok().filter(|t| t.len() == r.len());
            match trial.map(|t| (rss(&t), t)) {
                Some((st, t)) if st.is_finite() && st < s => {
                    let rel = (s - st) / s.max(1e-300);
                    p = q;
                    r = t;
                    s = st;
                    lambda = (lambda / 5.0).max(1e-9);
                    improved = rel > 1e-9;
                    break;
                }
                _ => lambda *= 8.0,
            }
        }
        if !improved {
            break;
        }
        j = jacobian(f, &p, &r, &steps(&p))?;
    }
    Ok(LmFit {
        params: p,
        rss: s,
        jacobian: j,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_an_exponential_decay() {
        let xs: Vec<f64> = (0..30).map(|i| i as f64 * 0.1).collect();
        let f = |p: &[f64]| -> Result<Vec<f64>> {
            Ok(xs
                .iter()
                .map(|x| 2.0 * (-0.7 * x).exp() + 0.3 - (p[0] * (-p[1] * x).exp() + p[2]))
                .collect())
        };
        let fit = levenberg_marquardt(&f, &[1.0, 0.2, 0.0], &[1.0, 1.0, 1.0], Stop::converged(100))
            .unwrap();
        assert!((fit.params[0] - 2.0).abs() < 1e-5, "{:?}", fit.params);
        assert!((fit.params[1] - 0.7).abs() < 1e-5);
        assert!(fit.rss < 1e-12);
    }

    /// A parameter the residuals see only through rounding (here a pseudo-random 1e-13 wobble,
    /// as the backlash at a load whose teeth never separate) stays where it started, while the
    /// one they see is fitted. Marquardt's step for it was -g/a, ~1e13 times its size.
    #[test]
    fn a_parameter_the_residuals_do_not_see_stays_put() {
        let xs: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
        let f = |p: &[f64]| -> Result<Vec<f64>> {
            Ok(xs
                .iter()
                .enumerate()
                .map(|(k, x)| {
                    let wobble = 1e-13 * ((k as f64 + 1.0) * 1e4 * p[1]).sin();
                    1.5 * x - p[0] * x + wobble
                })
                .collect())
        };
        let fit = levenberg_marquardt(&f, &[1.0, 0.3], &[1.0, 0.05], Stop::converged(20)).unwrap();
        assert!((fit.params[0] - 1.5).abs() < 1e-9, "{:?}", fit.params);
        assert_eq!(fit.params[1], 0.3, "{:?}", fit.params);
    }

    /// `Stop::near` ends within 0.01 of the minimum's sum of squares (a residual with a
    /// positive minimum: the decay plus a wiggle no exponential can follow) and spends fewer
    /// residual evaluations than converging fully.
    #[test]
    fn near_stop_ends_within_its_decrement_of_the_minimum() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let xs: Vec<f64> = (0..60).map(|i| i as f64 * 0.05).collect();
        let calls = AtomicUsize::new(0);
        let f = |p: &[f64]| -> Result<Vec<f64>> {
            calls.fetch_add(1, Ordering::Relaxed);
            Ok(xs
                .iter()
                .map(|x| {
                    2.0 * (-0.7 * x).exp() + 0.3 + 0.1 * (17.0 * x).sin()
                        - (p[0] * (-p[1] * x).exp() + p[2])
                })
                .collect())
        };
        let (start, scales) = ([1.0, 0.2, 0.0], [1.0, 1.0, 1.0]);
        let full = levenberg_marquardt(&f, &start, &scales, Stop::converged(100)).unwrap();
        let full_calls = calls.swap(0, Ordering::Relaxed);
        let near = levenberg_marquardt(&f, &start, &scales, Stop::near(100)).unwrap();
        let near_calls = calls.load(Ordering::Relaxed);
        assert!(full.rss > 0.1, "{}", full.rss);
        assert!(near.rss >= full.rss - 1e-12, "{} {}", near.rss, full.rss);
        assert!(near.rss - full.rss < 0.01, "{} {}", near.rss, full.rss);
        assert!(near_calls < full_calls, "{near_calls} vs {full_calls}");
    }
}
