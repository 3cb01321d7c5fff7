//! Profile-likelihood 95% intervals (Venzon & Moolgavkar 1988; Bates & Watts 1988, Sec. 6.1):
//! the values of one parameter at which the weighted residual sum of squares, minimised over
//! the others with the fit's final weights held (the working likelihood of the reweighted fit),
//! exceeds its minimum by q^2, q the fit's t quantile, so that the profile and Wald intervals
//! agree where the model is linear in its parameters.

use super::estimate::Estimate;
use super::lm::{least_squares, rss, Stop};
use super::params::{restarted, Param};
use crate::error::Result;
use crate::hb::brent;

/// Doublings of the bracketing step (from one standard error, internal coordinates) before a
/// side is declared unbounded.
const MAX_DOUBLINGS: usize = 12;
/// Accuracy of an interval's end, in standard errors (internal coordinates): far below what
/// any report prints, and reached by Brent's method in a handful of profile fits where 30
/// bisections took thirty.
const END_TOLERANCE: f64 = 1e-6;
/// The profile's excess over its target is capped at this many times the target's distance
/// from the minimum before the root search (a profile point that cannot be fitted is
/// infinite; the cap keeps Brent's interpolation finite and makes it bisect there).
const EXCESS_CAP: f64 = 1e3;

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
    // The profile at u, its other parameters fitted from `start`; the fitted values are
    // returned to start the next point of the same side (a few Jacobians where the estimate
    // as start took several times more). A point that cannot be fitted counts as outside.
    let profile = |u: f64, start: &[Param]| -> Result<(f64, Option<Vec<f64>>)> {
        let value = t.value(u);
        let full = |p: &[f64]| {
            let mut q = p.to_vec();
            q.insert(index, value);
            q
        };
        if start.is_empty() {
            return Ok((rss(&weighted(&full(&[]))?), None));
        }
        let f = |p: &[f64]| weighted(&full(p));
        Ok(least_squares(&f, start, stop)
            .map_or((f64::INFINITY, None), |fit| (fit.rss, Some(fit.params))))
    };
    let centre = t.internal(est.params[index]).unwrap_or(est.params[index]);
    let se_u = est.std_errors[index] / t.derivative(centre).abs().max(1e-300);
    let step = if se_u.is_finite() && se_u > 0.0 {
        se_u
    } else {
        1e-3 * centre.abs().max(1e-3)
    };
    let rise = (target - minimum).max(f64::MIN_POSITIVE);
    // Inner fits that stop once they stall are accurate to `stop.stall` in the sum of
    // squares, which places an end to stall / (2 q) standard errors (the profile's slope
    // there is 2 q per standard error): a finer search only bisects that error.
    let tolerance = END_TOLERANCE.max(stop.stall / (2.0 * est.quantile[index]));
    let side = |dir: f64| -> Result<Option<f64>> {
        let mut start = others.clone();
        let mut excess = |u: f64| -> Result<f64> {
            let (value, fitted) = profile(centre + u, &start)?;
            if let Some(p) = fitted {
                start = restarted(&others, &p);
            }
            Ok((value - target).min(EXCESS_CAP * rise))
        };
        let (mut lo, mut hi) = (0.0, dir * step);
        let mut f_lo = minimum - target;
        for _ in 0..MAX_DOUBLINGS {
            let f_hi = excess(hi)?;
            if f_hi > 0.0 {
                // An error inside Brent's search counts as outside, as above; it is kept and
                // returned after the search.
                let mut failed = None;
                let root = brent(
                    |u| {
                        excess(u).unwrap_or_else(|e| {
                            failed.get_or_insert(e);
                            EXCESS_CAP * rise
                        })
                    },
                    lo,
                    hi,
                    f_lo,
                    f_hi,
                    tolerance * step,
                );
                return match failed {
                    Some(e) => Err(e),
                    None => Ok(Some(t.value(centre + root))),
                };
            }
            (lo, f_lo) = (hi, f_hi);
            hi *= 2.0;
        }
        Ok(None)
    };
    let (lo, hi) = rayon::join(|| side(-1.0), || side(1.0));
    Ok((lo?, hi?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{estimate, EstimateOptions, NoiseSetting, Robust};

    /// Points and per-point standard deviations of the tests: no noise is drawn, the data
    /// are a fixed wiggle about the curve, so that the fit has residuals.
    fn data(curve: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = (0..25).map(|i| 0.1 * f64::from(i)).collect();
        let y = x
            .iter()
            .enumerate()
            .map(|(i, &x)| curve(x) + 0.05 * (1.7 * i as f64).sin())
            .collect();
        let sd = x.iter().map(|x| 0.04 + 0.02 * x).collect();
        (x, y, sd)
    }

    fn fit<M>(model: &M, y: &[f64], sd: &[f64], params: &[Param]) -> Estimate
    where
        M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
    {
        estimate(
            model,
            y,
            params,
            &EstimateOptions {
                noise: NoiseSetting::PerPoint(sd.to_vec()),
                robust: Robust::Off,
                stop: Stop::converged(100).central(),
                starts: Vec::new(),
            },
        )
        .unwrap()
    }

    /// A model linear in signed parameters with a stated noise: the profile interval is the
    /// Wald interval exactly (the weighted sum of squares is quadratic), so the root search
    /// must land on estimate +- 1.96 SE to its tolerance, here 1e-5 SE (the inner fits
    /// converge to 1e-9 in the sum of squares).
    #[test]
    fn profile_of_a_linear_model_is_the_wald_interval() {
        let (x, y, sd) = data(|x| 1.0 + 2.0 * x);
        let model =
            |p: &[f64]| -> Result<Vec<f64>> { Ok(x.iter().map(|x| p[0] + p[1] * x).collect()) };
        let params = [Param::signed("a", 0.5, 1.0), Param::signed("b", 1.0, 1.0)];
        let est = fit(&model, &y, &sd, &params);
        for i in 0..2 {
            let (lo, hi) = profile_interval(&model, &y, &est, i, Stop::converged(100)).unwrap();
            let (lo, hi) = (lo.unwrap(), hi.unwrap());
            let se = est.std_errors[i];
            let q = est.quantile[i];
            assert!(
                (q - 1.959_964).abs() < 1e-5,
                "stated noise: normal quantile"
            );
            assert!(
                (lo - (est.params[i] - q * se)).abs() < 1e-5 * se,
                "{i}: {lo}"
            );
            assert!(
                (hi - (est.params[i] + q * se)).abs() < 1e-5 * se,
                "{i}: {hi}"
            );
        }
    }

    /// A one-parameter nonlinear model y = exp(-k x) with k positive (log coordinate): the
    /// ends are where the weighted sum of squares rises by 1.96^2, found here independently by
    /// bisecting a direct scan of it; the interval is asymmetric, so a Wald answer fails.
    #[test]
    fn profile_of_a_nonlinear_model_crosses_the_deviance_threshold() {
        let (x, y, sd) = data(|x| (-0.8 * x).exp());
        let model =
            |p: &[f64]| -> Result<Vec<f64>> { Ok(x.iter().map(|x| (-p[0] * x).exp()).collect()) };
        let est = fit(&model, &y, &sd, &[Param::positive("k", 0.5)]);
        let (lo, hi) = profile_interval(&model, &y, &est, 0, Stop::converged(100)).unwrap();
        let s = |k: f64| -> f64 {
            let m = model(&[k]).unwrap();
            y.iter()
                .zip(&m)
                .zip(&sd)
                .map(|((y, m), s)| ((y - m) / s).powi(2))
                .sum()
        };
        let target = s(est.params[0]) + est.quantile[0].powi(2);
        let root = |mut inside: f64, mut outside: f64| {
            for _ in 0..200 {
                let mid = 0.5 * (inside + outside);
                if s(mid) > target {
                    outside = mid;
                } else {
                    inside = mid;
                }
            }
            inside
        };
        let k = est.params[0];
        let se = est.std_errors[0];
        let (lo_ref, hi_ref) = (root(k, 0.0), root(k, 10.0 * k));
        assert!((lo.unwrap() - lo_ref).abs() < 1e-5 * se, "{lo:?} {lo_ref}");
        assert!((hi.unwrap() - hi_ref).abs() < 1e-5 * se, "{hi:?} {hi_ref}");
        // Not the Wald interval: the check above could not pass by accident.
        assert!(((hi_ref - k) - (k - lo_ref)).abs() > 1e-3 * se);
    }

    /// A parameter the data do not determine on one side has no end there: the level
    /// 1 - exp(-k) saturates, and with the data at 0.98 and a noise of 0.5 every larger k fits
    /// within 1.96^2 of the best (the whole rise to 1 is worth 25 (0.02 / 0.5)^2 = 0.04).
    #[test]
    fn an_undetermined_side_has_no_end() {
        let (x, y, sd) = data(|_| 0.98);
        let sd = vec![0.5; sd.len()];
        let model =
            |p: &[f64]| -> Result<Vec<f64>> { Ok(x.iter().map(|_| 1.0 - (-p[0]).exp()).collect()) };
        let est = fit(&model, &y, &sd, &[Param::positive("k", 3.0)]);
        let (lo, hi) = profile_interval(&model, &y, &est, 0, Stop::converged(100)).unwrap();
        assert!(lo.is_some(), "a small k lowers the curve: bounded below");
        assert!(
            hi.is_none(),
            "every k beyond the estimate fits as well: {hi:?}"
        );
    }
}
