//! Profile-likelihood 95% intervals: the values of one parameter at which the residual sum of
//! squares, minimised over the others, exceeds its minimum by chi^2_1(0.95) sigma^2 = 3.84 sigma^2.

use super::least_squares::{minimise, FitResult, Residuals};
use crate::error::Result;

/// chi-square quantile with one degree of freedom at 95%.
const CHI2_1_95: f64 = 3.841_458_820_694_124;

struct Fixed<'a, R: Residuals + ?Sized> {
    model: &'a R,
    index: usize,
    value: f64,
}

impl<R: Residuals + ?Sized> Residuals for Fixed<'_, R> {
    fn names(&self) -> Vec<String> {
        let mut n = self.model.names();
        n.remove(self.index);
        n
    }
    fn residuals(&self, p: &[f64]) -> Result<Vec<f64>> {
        let mut full = p.to_vec();
        full.insert(self.index, self.value);
        self.model.residuals(&full)
    }
}

/// Profile interval of parameter `index` around the fit `best`; None on a side where the profile
/// does not rise enough within a factor of 10 (the parameter is not identifiable that way).
pub fn profile_interval<R: Residuals + ?Sized>(
    model: &R,
    best: &FitResult,
    index: usize,
) -> Result<(Option<f64>, Option<f64>)> {
    let target = best.ssr + CHI2_1_95 * best.sigma * best.sigma;
    let others: Vec<f64> = best
        .params
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != index)
        .map(|(_, v)| *v)
        .collect();
    let profile = |v: f64| -> Result<f64> {
        if others.is_empty() {
            let mut p = best.params.clone();
            p[index] = v;
            return Ok(model.residuals(&p)?.iter().map(|x| x * x).sum());
        }
        let fixed = Fixed {
            model,
            index,
            value: v,
        };
        Ok(minimise(&fixed, &others, 1000)?.1)
    };
    let centre = best.params[index];
    let step = best.std_errors[index].max(1e-6 * centre) / centre;
    let side = |dir: f64| -> Result<Option<f64>> {
        // Bracket in log space by doubling, then bisect.
        let mut lo = 0.0f64;
        let mut hi = dir * step;
        for _ in 0..40 {
            if profile(centre * hi.exp())? > target {
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if profile(centre * mid.exp())? > target {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Ok(Some(centre * (0.5 * (lo + hi)).exp()));
            }
            lo = hi;
            hi *= 2.0;
            if hi.abs() > 10f64.ln() {
                return Ok(None);
            }
        }
        Ok(None)
    };
    Ok((side(-1.0)?, side(1.0)?))
}
