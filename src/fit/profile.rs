//! Profile-likelihood 95% intervals (Venzon & Moolgavkar 1988; Bates & Watts 1988, Sec. 6.1):
//! the values of one parameter at which the weighted residual sum of squares, minimised over
//! the others with the fit's final weights held (the working likelihood of the reweighted fit),
//! exceeds its minimum by q^2, q the fit's t quantile, so that the profile and Wald intervals
//! agree where the model is linear in its parameters.

use super::estimate::Estimate;
use super::lm::{least_squares, rss, Stop};
use super::params::restarted;
use crate::error::Result;

/// Doublings of the bracketing step (from one standard error, internal coordinates) before a
/// side is declared unbounded.
const MAX_DOUBLINGS: usize = 12;
/// Bisections of the bracket: 2^-30 of it.
const BISECTIONS: usize = 30;

/// Profile interval of parameter `index` of the fit `est` of `model` to `y`; None on a side
/// where the profile does not rise enough within 2^12 standard errors (the parameter is not
/// identifiable that way).
pub fn profile_interval<M>(
    model: &M,
    y: &[f64],
    est: &Estimate,
    index: usize,
    stop: Stop,
) -> Result<(Option<f64>, Option<f64>)>
where
    M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    let defs = &est.param_defs;
    let w = &est.weights;
    let weighted = |p: &[f64]| -> Result<Vec<f64>> {
        let m = model(p)?;
        Ok(y.iter()
            .zip(&m)
            .zip(w)
            .map(|((y, f), w)| (y - f) * w.sqrt())
            .collect())
    };
    let minimum = rss(&weighted(&est.params)?);
    let target = minimum + est.quantile[index] * est.quantile[index];
    let mut others = restarted(defs, &est.params);
    others.remove(index);
    let t = defs[index].transform;
    let profile = |u: f64| -> Result<f64> {
        let value = t.value(u);
        let full = |p: &[f64]| {
            let mut q = p.to_vec();
            q.insert(index, value);
            q
        };
        if others.is_empty() {
            return Ok(rss(&weighted(&full(&[]))?));
        }
        let f = |p: &[f64]| weighted(&full(p));
        // A profile point that cannot be fitted counts as outside the interval.
        Ok(least_squares(&f, &others, stop).map_or(f64::INFINITY, |fit| fit.rss))
    };
    let centre = t.internal(est.params[index]).unwrap_or(est.params[index]);
    let se_u = est.std_errors[index] / t.derivative(centre).abs().max(1e-300);
    let step = if se_u.is_finite() && se_u > 0.0 {
        se_u
    } else {
        1e-3 * centre.abs().max(1e-3)
    };
    let side = |dir: f64| -> Result<Option<f64>> {
        let (mut lo, mut hi) = (0.0, dir * step);
        for _ in 0..MAX_DOUBLINGS {
            if profile(centre + hi)? > target {
                for _ in 0..BISECTIONS {
                    let mid = 0.5 * (lo + hi);
                    if profile(centre + mid)? > target {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Ok(Some(t.value(centre + 0.5 * (lo + hi))));
            }
            lo = hi;
            hi *= 2.0;
        }
        Ok(None)
    };
    Ok((side(-1.0)?, side(1.0)?))
}
