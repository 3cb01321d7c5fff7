//! Profile-likelihood 95% intervals (Venzon & Moolgavkar 1988; Bates & Watts 1988, Sec. 6.1):
//! the values of one parameter at which -2 log L of the fitted noise model, its scales held
//! (the weighted residual sum of squares under Gaussian errors, the sum of squared deviance
//! residuals under Student-t errors), minimised over the others, exceeds its minimum by q^2,
//! q the fit's t quantile, so that the profile and Wald intervals agree where the model is
//! linear in its parameters.
//!
//! The sum of squares of a model whose curve jumps (an up-sweep falling off its resonance
//! branch) has steps where a jump crosses a measured speed, and an inner fit started on the
//! wrong side of one stays there. So each inner fit starts from the fit of the nearest point
//! found inside the interval (the estimate, at first); a point that rises more than twice as
//! far as the quadratic approximation says (or than the threshold) is fitted again from the
//! ridge (the others' regression on the profiled parameter under the fit's information
//! matrix, the linear approximation to the profile trace, Bates & Watts 1988, Sec. 6.1) and
//! from the estimate, the least of the fits kept; and the root search
//! ([`super::profile_search`]) gets a bracket whose outside end was fitted from its inside
//! end, a quarter of a standard error away. Without this, the profile of zeta on two envelopes
//! of tooth pairs that jump at their own speeds (tests/data/independent-kubo) rose by 18 and 45
//! q^2 within a hundredth of a standard error of the estimate and ended there; now it is a
//! parabola to beyond 1.5 standard errors.
//!
//! A side whose root is a step that no start avoids (see [`super::profile_search`]) ends at the
//! Wald end instead, or at the step if that is farther.

use super::estimate::NearModel;
use super::estimate::{pinv_sym, Estimate, Measurement};
use super::lm::{least_squares_warm, rss, NearResiduals, Stop};
use super::noise::{deviance_residual, Distribution};
use super::params::{restarted, Param};
use super::profile_search::{search_side, Fitted, InnerFit, SearchOptions, SideEnd};
use crate::error::Result;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};

/// Width of the bracket handed to the root search, in standard errors: its outside end was
/// fitted from a start at most this far away.
const BRACKET_WIDTH: f64 = 0.25;
/// Accuracy of an interval's end, in standard errors (internal coordinates): far below what
/// any report prints, and reached by Brent's method in a handful of profile fits where 30
/// bisections took thirty.
const END_TOLERANCE: f64 = 1e-6;
/// Inner fits per side at most: a walk out by factors of 1.25 or more from one standard error
/// to 2^11 takes at most 35, a bracket a few halvings, Brent's method a dozen.
const MAX_FITS_PER_SIDE: usize = 80;
/// A profile point whose rise over the minimum is this many times what the quadratic model
/// predicts there (or the threshold, if larger) is fitted again from the other starts.
const SURPRISE: f64 = 2.0;

/// A profile-likelihood 95% interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ProfileInterval {
    /// None where the profile does not rise enough within 2^11 standard errors (the parameter
    /// is not identifiable that way), or, below, before the parameter's
    /// [`Param::profile_floor`].
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    /// For the lower and the upper end: that end is not where the ratio crosses its threshold
    /// (the profile steps there rather than rises, or its inner fits fail beyond it; see the
    /// module's notes), so it is the Wald end, or the step or failure where that is farther.
    pub stepped: [bool; 2],
}

impl ProfileInterval {
    /// The two ends.
    pub fn ends(&self) -> (Option<f64>, Option<f64>) {
        (self.lower, self.upper)
    }

    /// Whether `value` lies inside (an unbounded side holds everything beyond the estimate).
    pub fn covers(&self, value: f64) -> bool {
        self.lower.is_none_or(|a| a <= value) && self.upper.is_none_or(|b| value <= b)
    }
}

/// Profile interval of parameter `index` of the fit `est` of `model` to `y`.
pub fn profile_interval<M>(
    model: &M,
    y: &[f64],
    est: &Estimate,
    index: usize,
    stop: Stop,
) -> Result<ProfileInterval>
where
    M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    match profile_interval_or_better(model, None, y, est, index, stop, None)? {
        Profiled::Interval(interval) => Ok(interval),
        // Without a threshold no point counts as better.
        Profiled::Better(_) => Err(crate::error::GearError::Numerical(
            "a profile without a better-fit threshold reported a better fit".into(),
        )),
    }
}

/// What [`profile_interval_or_better`] found.
#[derive(Clone, Debug, PartialEq)]
pub enum Profiled {
    /// The interval about the estimate.
    Interval(ProfileInterval),
    /// A profile point fitting better than the estimate: its full parameter vector. The
    /// estimate is not the least minimum, so an interval about it means nothing: the caller
    /// fits again from here.
    Better(Vec<f64>),
}

/// [`profile_interval`], except that a point whose -2 log L lies more than `better_by` (sigma^2)
/// below the estimate's ends the search as [`Profiled::Better`] (None: no point does, as in
/// [`profile_interval`]; nor does any of a one-parameter model, whose profile points have no
/// other parameters fitted to hand back). A curve with jumps has minima the fit's starts may
/// miss and its profile walks into (a two-pair whole-curve Kubo fit at zeta 0.032 whose
/// profile fitted 30 sigma^2 better towards the floor): its interval would be about a point
/// that is not the fit, and the search would go on through every step of it (over a minute
/// of sweeps).
///
/// The inner fits take their Jacobian columns from `near` when given (see [`NearModel`]).
pub fn profile_interval_or_better<M>(
    model: &M,
    near: Option<NearModel<'_>>,
    y: &[f64],
    est: &Estimate,
    index: usize,
    stop: Stop,
    better_by: Option<f64>,
) -> Result<Profiled>
where
    M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    let mut profile = Profile::new(model, near, y, est, index, stop)?;
    profile.better_by = better_by;
    let (lo, hi) = rayon::join(|| profile.side(-1.0), || profile.side(1.0));
    let (lo, hi) = match (lo?, hi?) {
        (Ended::Better(p), _) | (_, Ended::Better(p)) => return Ok(Profiled::Better(p)),
        (Ended::End(lo), Ended::End(hi)) => (lo, hi),
    };
    Ok(Profiled::Interval(ProfileInterval {
        lower: lo.map(|e| e.0),
        upper: hi.map(|e| e.0),
        stepped: [lo.is_some_and(|e| e.1), hi.is_some_and(|e| e.1)],
    }))
}

/// How one side of a profile ended: its end (None where the profile stays inside) with
/// whether it stepped there, or a better fit (the full parameter vector).
enum Ended {
    End(Option<(f64, bool)>),
    Better(Vec<f64>),
}

/// The profile of one parameter, in its internal coordinate u measured from the estimate.
struct Profile<'a, M> {
    model: &'a M,
    /// The inner fits' Jacobian columns (see [`NearModel`]).
    near: Option<NearModel<'a>>,
    y: &'a [f64],
    est: &'a Estimate,
    /// The fit's measurements of parameters ([`Measurement`]), one more factor of the
    /// likelihood at every profile point.
    measurements: Vec<Measurement>,
    index: usize,
    stop: Stop,
    /// The other parameters, starting at the estimate.
    others: Vec<Param>,
    /// Their internal coordinates at the estimate and slopes along the ridge.
    ridge: Vec<(f64, f64)>,
    /// The profiled parameter's internal coordinate at the estimate.
    centre: f64,
    /// Its standard error in the internal coordinate (the bracketing's unit), and whether that is
    /// the standard error (not a stand-in for a parameter without one).
    se: f64,
    se_known: bool,
    minimum: f64,
    /// The threshold's height q^2 above the minimum.
    rise: f64,
    /// Accuracy of an end, in internal units.
    tolerance: f64,
    /// A point this far below the minimum (sigma^2) is a better fit (None: none is).
    better_by: Option<f64>,
    /// Set once a side found a better fit: the other side's search is then worthless, and its
    /// inner fits return at once as failed.
    abandoned: AtomicBool,
}

impl<'a, M> Profile<'a, M>
where
    M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    fn new(
        model: &'a M,
        near: Option<NearModel<'a>>,
        y: &'a [f64],
        est: &'a Estimate,
        index: usize,
        stop: Stop,
    ) -> Result<Self> {
        let t = est.param_defs[index].transform;
        let mut others = restarted(&est.param_defs, &est.params);
        others.remove(index);
        let centre = t.internal(est.params[index]).unwrap_or(est.params[index]);
        let se_u = est.std_errors[index] / t.derivative(centre).abs().max(1e-300);
        let se_known = se_u.is_finite() && se_u > 0.0;
        let se = if se_known {
            se_u
        } else {
            1e-3 * centre.abs().max(1e-3)
        };
        let q = est.quantile[index];
        let mut profile = Profile {
            model,
            near,
            y,
            est,
            measurements: est.measurements.iter().map(|m| m.measurement).collect(),
            index,
            stop,
            others,
            ridge: ridge_slopes(est, index),
            centre,
            se,
            se_known,
            minimum: 0.0,
            rise: (q * q).max(f64::MIN_POSITIVE),
            // Inner fits that stop once they stall are accurate to `stop.stall` in the sum of
            // squares, which places an end to stall / (2 q) standard errors (the profile's
            // slope there is 2 q per standard error): a finer search only bisects that error.
            tolerance: END_TOLERANCE.max(stop.stall / (2.0 * q)) * se,
            better_by: None,
            abandoned: AtomicBool::new(false),
        };
        profile.minimum = rss(&profile.likelihood_residuals(&est.params)?);
        Ok(profile)
    }

    /// Residuals at the full parameter vector `p` whose sum of squares is -2 log L of the
    /// fitted noise model up to a constant, its scales held: weighted by the final weights
    /// under Gaussian errors; deviance residuals under Student-t errors, whose final weights
    /// (the reweighting's, about 1 / sigma^2 on average) would profile a likelihood
    /// (dof + 3) / (dof + 1) times as curved as the Fisher information (dof 3: intervals 18%
    /// short; validate-study's Student-t sets covered 84-90%).
    fn likelihood_residuals(&self, p: &[f64]) -> Result<Vec<f64>> {
        self.with_measured(self.likelihood_residuals_of(&(self.model)(p)?), p)
    }

    /// `r` followed by the measurements' standardized residuals at `p` (their factor of the
    /// likelihood, [`super::Measurement`]).
    fn with_measured(&self, r: Result<Vec<f64>>, p: &[f64]) -> Result<Vec<f64>> {
        let mut r = r?;
        r.extend(Measurement::residuals(&self.measurements, p));
        Ok(r)
    }

    /// [`Profile::likelihood_residuals`] of the model's curve `m`: the innovations (the
    /// standardized residuals, decorrelated along speed where the errors are correlated), as
    /// deviance residuals under Student-t errors.
    fn likelihood_residuals_of(&self, m: &[f64]) -> Result<Vec<f64>> {
        let residuals: Vec<f64> = self.y.iter().zip(m).map(|(y, f)| y - f).collect();
        Ok(match self.est.noise.model.distribution {
            Distribution::Gaussian => self.est.whitener.apply(&residuals),
            dist => self
                .est
                .whitener
                .innovations(&residuals)
                .iter()
                .map(|e| deviance_residual(dist, *e))
                .collect(),
        })
    }

    /// The sum of squares at u with the other parameters fitted from `start`, and their fitted
    /// values; a point that cannot be fitted counts as outside (infinite).
    fn fit_from(&self, u: f64, start: &[Param]) -> Result<(f64, Option<Vec<f64>>)> {
        if start.is_empty() {
            return Ok((rss(&self.likelihood_residuals(&self.full(u, &[]))?), None));
        }
        let f = |p: &[f64]| self.likelihood_residuals(&self.full(u, p));
        let near = self.near.map(|near| {
            move |p: &[f64], base: &[f64]| {
                let full = self.full(u, p);
                self.with_measured(
                    self.likelihood_residuals_of(&near(&full, &self.full(u, base))?),
                    &full,
                )
            }
        });
        let near = near.as_ref().map(|n| n as NearResiduals<'_>);
        Ok(least_squares_warm(&f, near, start, self.stop)
            .map_or((f64::INFINITY, None), |fit| (fit.rss, Some(fit.params))))
    }

    /// The full parameter vector of the others' values `others` with the profiled parameter at
    /// internal coordinate u (from the estimate).
    fn full(&self, u: f64, others: &[f64]) -> Vec<f64> {
        let value = self.est.param_defs[self.index]
            .transform
            .value(self.centre + u);
        let mut p = others.to_vec();
        p.insert(self.index, value);
        p
    }

    /// The other parameters' start on the ridge at u.
    fn on_ridge(&self, u: f64) -> Vec<Param> {
        let values: Vec<f64> = self
            .others
            .iter()
            .zip(&self.ridge)
            .map(|(d, (hat, slope))| d.transform.value(hat + slope * u))
            .collect();
        restarted(&self.others, &values)
    }

    /// The profile at u: fitted from `nearest` (the fit of the nearest point inside), and where
    /// that comes out surprisingly high also from the ridge and the estimate, the least kept.
    fn least_at(&self, u: f64, nearest: &[Param]) -> Result<(f64, Option<Vec<f64>>)> {
        let (mut value, mut fitted) = self.fit_from(u, nearest)?;
        // In chi-square units a quadratic sum of squares rises by (u / se)^2.
        let quadratic = (u / self.se).powi(2);
        if value - self.minimum > SURPRISE * quadratic.max(self.rise) {
            // The estimate is not fitted from again where it was the first start (the nearest
            // point inside is the estimate until one is found): the same fit, twice.
            let from_estimate = nearest
                .iter()
                .zip(&self.others)
                .all(|(a, b)| a.start == b.start);
            let ridge = self.on_ridge(u);
            let mut starts = vec![&ridge[..]];
            if !from_estimate {
                starts.push(&self.others);
            }
            for start in starts {
                let (v, f) = self.fit_from(u, start)?;
                if v < value {
                    (value, fitted) = (v, f);
                }
            }
        }
        Ok((value, fitted))
    }

    /// How far below the estimate the parameter's [`Param::profile_floor`] lies, in internal
    /// units (every transform increases, so below is towards -u); None without a floor.
    fn floor_distance(&self) -> Option<f64> {
        let def = &self.est.param_defs[self.index];
        let floor = def.transform.internal(def.profile_floor?)?;
        Some(self.centre - floor)
    }

    /// The end on side `dir` (-1 or 1), with whether the profile stepped there: the root
    /// search's end, or where it stepped the Wald end if that is farther (see the module's
    /// notes); None where the profile stays inside.
    fn side(&self, dir: f64) -> Result<Ended> {
        let limit = if dir < 0.0 {
            self.floor_distance()
        } else {
            None
        };
        if limit.is_some_and(|l| l <= 0.0) {
            return Ok(Ended::End(None));
        }
        let q = self.rise.sqrt();
        let options = SearchOptions {
            first_step: self.se,
            se: self.se,
            q,
            limit,
            max_fits: MAX_FITS_PER_SIDE,
            accept: 0.0,
            bracket_width: Some(BRACKET_WIDTH),
            tolerance: self.tolerance,
            better_by: self.better_by,
        };
        let (distance, stepped) = match search_side(self, self.others.clone(), dir, options)? {
            SideEnd::At { distance, stepped } => (distance, stepped && self.se_known),
            // No ratio end where the fits fail: as at a step, Wald's end if farther.
            SideEnd::Failed { distance } => (distance, self.se_known),
            SideEnd::Limit | SideEnd::Open => return Ok(Ended::End(None)),
            SideEnd::Better { u, fitted } => {
                self.abandoned.store(true, Ordering::Relaxed);
                let others: Vec<f64> = fitted.iter().map(|d| d.start).collect();
                return Ok(Ended::Better(self.full(u, &others)));
            }
        };
        let end = if stepped {
            distance.max(self.est.quantile[self.index] * self.se)
        } else {
            distance
        };
        // A stepped side's Wald end may lie beyond the floor, where the model is not trusted:
        // the side is then as unbounded as one still inside there.
        if limit.is_some_and(|l| end >= l) {
            return Ok(Ended::End(None));
        }
        let t = self.est.param_defs[self.index].transform;
        Ok(Ended::End(Some((
            t.value(self.centre + dir * end),
            stepped,
        ))))
    }
}

impl<M> InnerFit for Profile<'_, M>
where
    M: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
{
    type Start = Vec<Param>;

    fn fit_at(&self, u: f64, start: &Vec<Param>) -> Result<Fitted<Vec<Param>>> {
        if self.abandoned.load(Ordering::Relaxed) {
            return Ok(Fitted {
                rise: f64::INFINITY,
                fitted: None,
            });
        }
        let (value, fitted) = self.least_at(u, start)?;
        Ok(Fitted {
            rise: value - self.minimum,
            fitted: fitted.map(|p| restarted(&self.others, &p)),
        })
    }
}

/// For each parameter but `index`: its internal coordinate at the estimate, and its change per
/// unit change of `index`'s internal coordinate along the ridge of the weighted sum of squares,
/// -F_oo^+ F_oi, F the information G'G in internal coordinates (G the model's Jacobian mapped
/// as the fit's final least-squares residuals are, [`super::Whitener::apply`]). Zero slopes where F_oo cannot be inverted.
fn ridge_slopes(est: &Estimate, index: usize) -> Vec<(f64, f64)> {
    let defs = &est.param_defs;
    let p = est.params.len();
    let internal: Vec<f64> = defs
        .iter()
        .zip(&est.params)
        .map(|(d, v)| d.transform.internal(*v).unwrap_or(*v))
        .collect();
    let mut j = est.model_jacobian.clone();
    for (c, (d, u)) in defs.iter().zip(&internal).enumerate() {
        j.column_mut(c).scale_mut(d.transform.derivative(*u));
    }
    let mut g = j.clone();
    for c in 0..j.ncols() {
        let col: Vec<f64> = j.column(c).iter().copied().collect();
        for (r, v) in est.whitener.apply(&col).into_iter().enumerate() {
            g[(r, c)] = v;
        }
    }
    let f = g.transpose() * &g;
    let others: Vec<usize> = (0..p).filter(|&c| c != index).collect();
    let f_oo = DMatrix::from_fn(others.len(), others.len(), |a, b| f[(others[a], others[b])]);
    let f_oi = DVector::from_fn(others.len(), |a, _| f[(others[a], index)]);
    let slopes = pinv_sym(&f_oo).map_or_else(|| DVector::zeros(others.len()), |inv| -(inv * f_oi));
    others
        .iter()
        .zip(slopes.iter())
        .map(|(&c, s)| (internal[c], if s.is_finite() { *s } else { 0.0 }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{estimate, CorrelationSetting, EstimateOptions, NoiseSetting, Robust};

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

    /// The line a + b x at the points `x`, and its two signed parameters.
    fn line(x: &[f64]) -> (impl Fn(&[f64]) -> Result<Vec<f64>> + Sync + '_, [Param; 2]) {
        let model =
            |p: &[f64]| -> Result<Vec<f64>> { Ok(x.iter().map(|x| p[0] + p[1] * x).collect()) };
        let params = [Param::signed("a", 0.5, 1.0), Param::signed("b", 1.0, 1.0)];
        (model, params)
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
                correlation: CorrelationSetting::Independent,
                robust: Robust::Off,
                stop: Stop::converged(100).central(),
                starts: Vec::new(),
                noise_start: None,
                measurements: Vec::new(),
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
        let (model, params) = line(&x);
        let est = fit(&model, &y, &sd, &params);
        for i in 0..2 {
            let p = profile_interval(&model, &y, &est, i, Stop::converged(100)).unwrap();
            assert_eq!(p.stepped, [false, false], "{i}: a parabola has no step");
            let (lo, hi) = (p.lower.unwrap(), p.upper.unwrap());
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

    /// A step that no start avoids is not a bound: the linear model with one point that jumps
    /// by ten standard deviations (100 in the sum of squares) once the intercept falls 0.3
    /// standard errors below its estimate, as a point does when a jump of the curve crosses
    /// its speed. The lower end must be the Wald end (the step alone would put it at 0.3
    /// standard errors), the upper one unchanged (the Wald end, as the model is linear there).
    #[test]
    fn a_step_no_start_avoids_ends_at_the_wald_end() {
        let (x, y, sd) = data(|x| 1.0 + 2.0 * x);
        let (line, params) = line(&x);
        let est = fit(&line, &y, &sd, &params);
        let (a, se, q) = (est.params[0], est.std_errors[0], est.quantile[0]);
        let a_step = a - 0.3 * se;
        let stepped = |p: &[f64]| -> Result<Vec<f64>> {
            let mut m = line(p)?;
            if p[0] < a_step {
                m[0] += 10.0 * sd[0];
            }
            Ok(m)
        };
        let p = profile_interval(&stepped, &y, &est, 0, Stop::converged(100)).unwrap();
        assert_eq!(p.stepped, [true, false], "the step is below the estimate");
        let (lo, hi) = (p.lower.unwrap(), p.upper.unwrap());
        assert!(
            (lo - (a - q * se)).abs() < 1e-5 * se,
            "{lo} vs {}",
            a - q * se
        );
        assert!(
            (hi - (a + q * se)).abs() < 1e-5 * se,
            "{hi} vs {}",
            a + q * se
        );
    }

    /// A floor on the intercept (a model that refuses to go below it, as a fit through
    /// simulated sweeps refuses zeta below its least damping): one standard error below the
    /// estimate, inside the interval, the lower side is unbounded and the model is never asked
    /// below the floor; three standard errors below, the lower end is the Wald end as without
    /// a floor. The upper end is the Wald end both times.
    #[test]
    fn a_profile_still_inside_at_its_floor_is_unbounded_below() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let (x, y, sd) = data(|x| 1.0 + 2.0 * x);
        let (line, params) = line(&x);
        let est = fit(&line, &y, &sd, &params);
        let (a, se, q) = (est.params[0], est.std_errors[0], est.quantile[0]);
        for (floor_se, lower) in [(1.0, None), (3.0, Some(a - q * se))] {
            let floor = a - floor_se * se;
            let below = AtomicUsize::new(0);
            let refusing = |p: &[f64]| -> Result<Vec<f64>> {
                if p[0] < floor {
                    below.fetch_add(1, Ordering::Relaxed);
                    return Err(crate::error::GearError::Numerical("below the floor".into()));
                }
                line(p)
            };
            let mut floored = est.clone();
            floored.param_defs[0] = floored.param_defs[0].clone().with_profile_floor(floor);
            let p = profile_interval(&refusing, &y, &floored, 0, Stop::converged(100)).unwrap();
            match (p.lower, lower) {
                (None, None) => {}
                (Some(lo), Some(want)) => assert!((lo - want).abs() < 1e-5 * se, "{lo} vs {want}"),
                (got, want) => panic!("floor {floor_se} se: lower {got:?}, expected {want:?}"),
            }
            assert_eq!(below.load(Ordering::Relaxed), 0, "floor {floor_se} se");
            let hi = p.upper.unwrap();
            assert!((hi - (a + q * se)).abs() < 1e-5 * se, "{hi}");
        }
    }

    /// A deeper minimum the fit missed: the model fits the data exactly (at the estimate's
    /// slope) once the intercept lies 1.5 standard errors below the estimate, inside the
    /// interval. With a threshold the profile hands that point back (its intercept beyond the
    /// 1.5 standard errors, the slope refitted about its value); without a better one, it
    /// gives the same interval as [`profile_interval`].
    #[test]
    fn a_profile_that_finds_a_better_fit_hands_it_back() {
        let (x, y, sd) = data(|x| 1.0 + 2.0 * x);
        let (line, params) = line(&x);
        let est = fit(&line, &y, &sd, &params);
        let (a, se) = (est.params[0], est.std_errors[0]);
        assert!(
            est.chi_square > 1.0,
            "the fit leaves residuals: {}",
            est.chi_square
        );
        let b = est.params[1];
        let two_minima = |p: &[f64]| -> Result<Vec<f64>> {
            if p[0] < a - 1.5 * se {
                return Ok(y.iter().zip(&x).map(|(y, x)| y + (p[1] - b) * x).collect());
            }
            line(p)
        };
        let stop = Stop::converged(100);
        match profile_interval_or_better(&two_minima, None, &y, &est, 0, stop, Some(0.1)).unwrap() {
            Profiled::Better(p) => {
                assert!(p[0] < a - 1.5 * se, "{p:?}");
                assert!(
                    (p[1] - est.params[1]).abs() < 5.0 * est.std_errors[1],
                    "{p:?}"
                );
            }
            other => panic!("expected the better fit, got {other:?}"),
        }
        let plain = profile_interval(&line, &y, &est, 0, stop).unwrap();
        let with = profile_interval_or_better(&line, None, &y, &est, 0, stop, Some(0.1)).unwrap();
        assert_eq!(with, Profiled::Interval(plain));
    }

    /// A step inside the floor whose Wald end lies beyond it: the step 0.3 standard errors
    /// below the estimate (as in the test above), the floor 1.5 below, inside the Wald end at
    /// about 2. The lower side is unbounded, not the Wald end below the floor.
    #[test]
    fn a_stepped_end_beyond_the_floor_is_unbounded() {
        let (x, y, sd) = data(|x| 1.0 + 2.0 * x);
        let (line, params) = line(&x);
        let mut est = fit(&line, &y, &sd, &params);
        let (a, se) = (est.params[0], est.std_errors[0]);
        let stepped = |p: &[f64]| -> Result<Vec<f64>> {
            let mut m = line(p)?;
            if p[0] < a - 0.3 * se {
                m[0] += 10.0 * sd[0];
            }
            Ok(m)
        };
        est.param_defs[0] = est.param_defs[0].clone().with_profile_floor(a - 1.5 * se);
        let p = profile_interval(&stepped, &y, &est, 0, Stop::converged(100)).unwrap();
        assert_eq!(p.lower, None, "{p:?}");
        assert!(p.upper.is_some(), "{p:?}");
    }

    /// Under Student-t errors (a line, 400 points, 3 degrees of freedom, the scale stated and
    /// the dof estimated) the profile of the t likelihood matches the Fisher interval, whose
    /// information is (dof + 1) / (dof + 3) of the reweighting's J'WJ: half-widths within 10%
    /// (the observed information of 400 points scatters by about 5% about the expected). With
    /// the final working weights held, as before, the profile's half-widths were about
    /// sqrt(4 / 6) = 0.82 of the Fisher ones, and validate-study's Student-t sets covered
    /// 84-90%.
    #[test]
    fn student_t_profile_matches_the_fisher_interval() {
        let x: Vec<f64> = (0..400).map(|i| 0.01 * f64::from(i)).collect();
        let mut rng = crate::numeric::Rng::new(11);
        let y: Vec<f64> = x
            .iter()
            .map(|x| 1.0 + 2.0 * x + 0.1 * rng.student_t(3.0))
            .collect();
        let (line, params) = line(&x);
        let est = estimate(
            &line,
            &y,
            &params,
            &EstimateOptions {
                noise: NoiseSetting::PerPoint(vec![0.1; x.len()]),
                correlation: CorrelationSetting::Independent,
                robust: Robust::On,
                stop: Stop::converged(100).central(),
                starts: Vec::new(),
                noise_start: None,
                measurements: Vec::new(),
            },
        )
        .unwrap();
        assert!(
            matches!(
                est.noise.model.distribution,
                crate::fit::Distribution::StudentT { .. }
            ),
            "{:?}",
            est.noise.model
        );
        for i in 0..2 {
            let p = profile_interval(&line, &y, &est, i, Stop::converged(100)).unwrap();
            let (lo, hi) = (p.lower.unwrap(), p.upper.unwrap());
            let (flo, fhi) = est.ci95[i];
            let ratio = (hi - lo) / (fhi - flo);
            assert!(
                (0.9..1.1).contains(&ratio),
                "{i}: profile / Fisher width {ratio}"
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
        let (lo, hi) = profile_interval(&model, &y, &est, 0, Stop::converged(100))
            .unwrap()
            .ends();
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

    /// The inner fits of a two-parameter profile take their Jacobian columns from the near
    /// model: one equal to the model is called and gives the same ends.
    #[test]
    fn inner_fits_take_their_jacobians_from_the_near_model() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let (x, y, sd) = data(|x| 1.5 * (-0.8 * x).exp());
        let curve =
            |p: &[f64]| -> Vec<f64> { x.iter().map(|x| p[0] * (-p[1] * x).exp()).collect() };
        let model = |p: &[f64]| -> Result<Vec<f64>> { Ok(curve(p)) };
        let calls = AtomicUsize::new(0);
        let near = |p: &[f64], _base: &[f64]| -> Result<Vec<f64>> {
            calls.fetch_add(1, Ordering::Relaxed);
            Ok(curve(p))
        };
        let params = [Param::positive("a", 1.0), Param::positive("k", 0.5)];
        let est = fit(&model, &y, &sd, &params);
        let stop = Stop::converged(100);
        let ends = |near: Option<NearModel<'_>>| match profile_interval_or_better(
            &model, near, &y, &est, 1, stop, None,
        )
        .unwrap()
        {
            Profiled::Interval(i) => i.ends(),
            Profiled::Better(p) => panic!("better at {p:?}"),
        };
        let (plain, warm) = (ends(None), ends(Some(&near)));
        assert!(calls.load(Ordering::Relaxed) > 0);
        let se = est.std_errors[1];
        for (a, b) in [(plain.0, warm.0), (plain.1, warm.1)] {
            assert!((a.unwrap() - b.unwrap()).abs() < 1e-6 * se, "{a:?} {b:?}");
        }
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
        let (lo, hi) = profile_interval(&model, &y, &est, 0, Stop::converged(100))
            .unwrap()
            .ends();
        assert!(lo.is_some(), "a small k lowers the curve: bounded below");
        assert!(
            hi.is_none(),
            "every k beyond the estimate fits as well: {hi:?}"
        );
    }
}
