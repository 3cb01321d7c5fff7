//! Whether a fit of `validate` can be used: a fit that ran zeta to a bound, left an interval
//! infinite or unbounded, or ended on a non-finite residual is a failed fit, reported with its
//! reason instead of being carried into predictions and reports.

use crate::error::GearError;
use crate::fit::{Estimate, ProfileInterval, Transform};
use crate::numeric::to_significant;
use std::path::Path;

/// Damping ratios a fit may end at: the range the simulation accepts (below 1e-3 the transient
/// outlasts the budget; at 0.9 the mesh is nearly critically damped). A fitted zeta outside ran
/// to a bound of what the curve can determine (a flat curve drives it to 0 or past 1).
pub const FITTED_ZETA: (f64, f64) = (1e-3, 0.9);

/// A value for a message: 4 significant digits, in exponent form outside [1e-4, 1e6) (a fit that
/// ran off printed zeta as a 77-digit integer).
fn brief(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e6).contains(&a) {
        format!("{v:.3e}")
    } else {
        format!("{}", to_significant(v, 4))
    }
}

/// The reason `est` (with the profile intervals `profile` of its first parameters) cannot be
/// used, if any. Parameter 0 is zeta, which must end inside `zeta_range` ([`FITTED_ZETA`], or
/// a narrower range where the fit's model cannot go as far).
pub fn fit_failure(
    est: &Estimate,
    profile: &[ProfileInterval],
    zeta_range: (f64, f64),
) -> Option<String> {
    if !(est.chi_square.is_finite() && est.log_likelihood.is_finite()) {
        return Some(format!(
            "the residual sum is not finite (chi-square {})",
            est.chi_square
        ));
    }
    for (i, name) in est.names.iter().enumerate() {
        let v = est.params[i];
        let signed = est
            .param_defs
            .get(i)
            .is_some_and(|d| d.transform == Transform::Signed);
        if !(v.is_finite() && (signed || v > 0.0)) {
            let what = if signed { "finite" } else { "positive finite" };
            return Some(format!("{name} = {v} is not a {what} number"));
        }
        let (lo, hi) = est.ci95[i];
        if !(lo.is_finite() && hi.is_finite()) {
            return Some(format!(
                "the 95% interval of {name} = {} is [{}, {}]: the curve does not determine it",
                brief(v),
                brief(lo),
                brief(hi)
            ));
        }
    }
    if let Some(c) = est.noise.correlation.as_ref() {
        if let Some(reason) = c.unbounded_length() {
            return Some(reason);
        }
    }
    let zeta = est.params.first().copied().unwrap_or(f64::NAN);
    if !(zeta_range.0..=zeta_range.1).contains(&zeta) {
        return Some(format!(
            "zeta = {} ran to a bound (plausible fits end in [{}, {}]): the curve shows no \
             resonance that determines the damping",
            brief(zeta),
            brief(zeta_range.0),
            brief(zeta_range.1)
        ));
    }
    for (i, p) in profile.iter().enumerate() {
        let side = match p.ends() {
            (None, _) => "below",
            (_, None) => "above",
            _ => continue,
        };
        return Some(format!(
            "the profile-likelihood 95% interval of {} is unbounded {side}: the curve does not \
             determine it",
            est.names.get(i).map_or("a parameter", |s| s.as_str())
        ));
    }
    None
}

/// The error of a failed fit to the data set in `dir`.
pub fn fit_failed(dir: &Path, what: &str, reason: String) -> GearError {
    GearError::FitFailed {
        data: dir.to_path_buf(),
        reason: format!("{what}: {reason}"),
    }
}

#[cfg(test)]
mod tests {
    use super::brief;

    /// A runaway value prints in exponent form, a plausible one as it is.
    #[test]
    fn messages_print_runaway_values_briefly() {
        assert_eq!(brief(1.064e76), "1.064e76");
        assert_eq!(brief(0.0175), "0.0175");
        assert_eq!(brief(1600.04), "1600");
        assert_eq!(brief(2.5e-7), "2.500e-7");
        assert_eq!(brief(0.0), "0");
        assert_eq!(brief(f64::INFINITY), "inf");
    }
}
