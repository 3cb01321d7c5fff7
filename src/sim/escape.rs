//! Escape from a non-periodic set (transient chaos, issue 23): the observation budget, the
//! survival curve of the trajectories followed on the set, and the escape rate with its exact
//! 95% interval.
//!
//! Trajectories on a chaotic saddle leave it independently at a constant rate kappa per forcing
//! period, so the survival after the start of the observation is exp(-kappa n) (Lai & Tel,
//! Transient Chaos, 2011, ch. 1-2). With d escapes seen in an exposure of E trajectory-periods
//! (the periods every followed trajectory spent on the set, censored at the horizon), the
//! maximum-likelihood rate is d / E and the exact (Garwood) 95% interval is
//! [chi2_{0.025}(2d) / 2E, chi2_{0.975}(2d + 2) / 2E].

use crate::error::{GearError, Result};
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// How long non-periodic sets are followed after the steady-state analysis to tell a chaotic
/// attractor from a chaotic transient. Each set is followed until its rate is measured
/// (`target_escapes` escapes), its exposure reaches `max_exposure`, no trajectory is left on it,
/// or the horizon is reached: the time is bounded by `max_exposure` per set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EscapeBudget {
    /// Largest age, in forcing periods from the initial condition, to which a non-periodic set is
    /// followed; 0 does not follow (the steady-state analysis alone decides).
    pub horizon: usize,
    /// Escapes after which a set's rate is taken as measured (100 give about +-20% at 95%).
    pub target_escapes: usize,
    /// Trajectory-periods after which a set is no longer followed; with no escape seen the upper
    /// end of the rate's 95% interval is then 3.69 / max_exposure.
    pub max_exposure: f64,
    /// Forcing periods between two checkpoints of the survival curve.
    pub block: usize,
}

/// Largest accepted horizon (forcing periods).
pub const MAX_HORIZON: usize = 1_000_000;
/// Largest accepted exposure per set (trajectory-periods): about a minute of CPU.
pub const MAX_EXPOSURE: f64 = 5e7;

impl Default for EscapeBudget {
    /// 40,000 periods (issue 23's long run) and at most 4e6 trajectory-periods per set (a few
    /// seconds of CPU; a set without escape then has a rate below 9.2e-7 per period).
    fn default() -> Self {
        EscapeBudget {
            horizon: 40_000,
            target_escapes: 100,
            max_exposure: 4e6,
            block: 500,
        }
    }
}

impl EscapeBudget {
    /// No following: non-periodic sets are reported as the steady-state analysis found them.
    pub fn none() -> Self {
        EscapeBudget {
            horizon: 0,
            ..EscapeBudget::default()
        }
    }

    /// Check the budget against [`MAX_HORIZON`] and [`MAX_EXPOSURE`].
    pub fn validate(&self) -> Result<()> {
        if self.horizon > MAX_HORIZON {
            return Err(GearError::param(
                "horizon",
                self.horizon as f64,
                "at most 1000000 periods",
            ));
        }
        if !(self.max_exposure > 0.0 && self.max_exposure <= MAX_EXPOSURE) {
            return Err(GearError::param(
                "max_exposure",
                self.max_exposure,
                "the exposure must be in (0, 5e7] trajectory-periods",
            ));
        }
        if self.block == 0 || self.target_escapes == 0 {
            return Err(GearError::param(
                "block",
                self.block as f64,
                "the checkpoint interval and the target escapes must be at least 1",
            ));
        }
        Ok(())
    }
}

/// Escapes from a set below which it counts as an attractor: one or two late departures can be
/// trajectories that had not yet reached a coexisting chaotic attractor when observed.
pub const MIN_ESCAPES: usize = 3;

/// One point of a survival curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SurvivalPoint {
    /// Age, forcing periods from the initial condition.
    pub periods: usize,
    /// Trajectories still on the set at that age.
    pub alive: usize,
}

/// What following a non-periodic set found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EscapeRecord {
    /// Trajectories on the set when the observation started.
    pub entered: usize,
    /// Age (forcing periods from the initial conditions) at which the observation started.
    pub start_periods: usize,
    /// Age at which the observation of the set ended.
    pub end_periods: usize,
    /// Survival curve: trajectories still on the set at each checkpoint.
    pub survival: Vec<SurvivalPoint>,
    /// Trajectories that left the set (captured by a periodic orbit).
    pub escapes: usize,
    /// Trajectory-periods spent on the set during the observation.
    pub exposure: f64,
    /// Escape rate per forcing period, escapes / exposure.
    pub rate: f64,
    /// Exact 95% interval of the rate (see the module notes).
    pub rate_ci95: (f64, f64),
    /// Where the escaping trajectories went: (index of the attractor, count).
    pub destinations: Vec<(usize, usize)>,
}

impl EscapeRecord {
    /// Mean lifetime on the set, 1 / rate, in forcing periods (`None` without escapes).
    pub fn mean_lifetime(&self) -> Option<f64> {
        (self.escapes > 0).then(|| 1.0 / self.rate)
    }

    /// True when the set loses trajectories: at least [`MIN_ESCAPES`] escapes.
    pub fn is_transient(&self) -> bool {
        self.escapes >= MIN_ESCAPES
    }
}

/// Rate d / E and its exact 95% interval (Garwood) for `escapes` events in `exposure`
/// trajectory-periods. With no exposure the rate is 0 and the interval [0, infinity).
pub fn escape_rate(escapes: usize, exposure: f64) -> (f64, (f64, f64)) {
    if exposure <= 0.0 {
        return (0.0, (0.0, f64::INFINITY));
    }
    let d = escapes as f64;
    let quantile = |dof: f64, p: f64| {
        ChiSquared::new(dof)
            .map(|c| c.inverse_cdf(p))
            .unwrap_or(f64::NAN)
    };
    let lo = if escapes == 0 {
        0.0
    } else {
        quantile(2.0 * d, 0.025) / (2.0 * exposure)
    };
    let hi = quantile(2.0 * d + 2.0, 0.975) / (2.0 * exposure);
    (d / exposure, (lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::Rng;

    /// Garwood's interval for 10 Poisson events is [4.795, 18.39] (tables, e.g. Ulm 1990); for
    /// none the upper end is chi2_{0.975}(2) / 2 = -ln(0.025) = 3.689 events.
    #[test]
    fn interval_matches_the_tables() {
        let (r, (lo, hi)) = escape_rate(10, 1000.0);
        assert!((r - 0.01).abs() < 1e-15);
        assert!((lo * 1000.0 - 4.795).abs() < 1e-3, "{lo}");
        assert!((hi * 1000.0 - 18.39).abs() < 1e-2, "{hi}");
        let (_, (lo, hi)) = escape_rate(0, 100.0);
        assert_eq!(lo, 0.0);
        assert!((hi * 100.0 - (-(0.025f64).ln())).abs() < 1e-9, "{hi}");
    }

    /// Seeded exponential lifetimes censored at a horizon, as the saddle's trajectories are: the
    /// interval covers the true rate in about 95% of 400 replicates (binomial sd 1.1%, so the
    /// 91% floor is 3.6 sd below), and the estimate is unbiased to 2%.
    #[test]
    fn interval_covers_the_true_rate_of_censored_exponential_lifetimes() {
        let kappa = 5.5e-5;
        let horizon = 20_000.0;
        let mut rng = Rng::new(23);
        let (mut covered, mut sum) = (0, 0.0);
        let reps = 400;
        for _ in 0..reps {
            let (mut d, mut e) = (0, 0.0);
            for _ in 0..300 {
                let t = -rng.uniform().ln() / kappa;
                if t < horizon {
                    d += 1;
                    e += t;
                } else {
                    e += horizon;
                }
            }
            let (r, (lo, hi)) = escape_rate(d, e);
            sum += r;
            if lo <= kappa && kappa <= hi {
                covered += 1;
            }
        }
        let coverage = covered as f64 / reps as f64;
        assert!((0.91..=0.99).contains(&coverage), "coverage {coverage}");
        assert!((sum / reps as f64 / kappa - 1.0).abs() < 0.02);
    }

    #[test]
    fn budget_limits_are_checked() {
        assert!(EscapeBudget::default().validate().is_ok());
        let long = EscapeBudget {
            horizon: MAX_HORIZON + 1,
            ..EscapeBudget::default()
        };
        assert!(long.validate().is_err());
        let huge = EscapeBudget {
            max_exposure: 1e9,
            ..EscapeBudget::default()
        };
        assert!(huge.validate().is_err());
    }
}
