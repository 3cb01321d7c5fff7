//! Axis ranges: automatic ranges from finite data and validation of user-given ranges.

use crate::error::{GearError, Result};

/// Fraction of the data span added on each side of an automatic range.
const PAD: f64 = 0.05;

/// Smallest and largest finite value, or `None` if there is none.
pub(crate) fn finite_extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// Relative span below which data are drawn as constant: a q_m that varies by rounding only
/// (6e-9 on 1.1) gets the range of a constant, not nine-decimal ticks on its noise.
const CONSTANT_SPAN: f64 = 1e-6;

/// Widens an empty or numerically constant interval around its centre: +-5 % of the value, or
/// +-0.5 around zero.
fn widen_degenerate(lo: f64, hi: f64) -> (f64, f64) {
    let scale = lo.abs().max(hi.abs());
    if hi - lo > CONSTANT_SPAN * scale {
        return (lo, hi);
    }
    let c = 0.5 * (lo + hi);
    let half = if c == 0.0 { 0.5 } else { 0.05 * c.abs() };
    (c - half, c + half)
}

/// Range for an axis: the user's range if given (validated), else the finite data extent with
/// 5 % padding, else (0, 1). `name` names the axis in errors.
pub(crate) fn resolve(
    name: &'static str,
    user: Option<(f64, f64)>,
    data: Option<(f64, f64)>,
) -> Result<(f64, f64)> {
    let (lo, hi) = match (user, data) {
        (Some((lo, hi)), _) => {
            if !lo.is_finite() {
                return Err(GearError::param(name, lo, "range bounds must be finite"));
            }
            if !hi.is_finite() {
                return Err(GearError::param(name, hi, "range bounds must be finite"));
            }
            if lo > hi {
                return Err(GearError::param(
                    name,
                    lo,
                    "range lower bound exceeds upper bound",
                ));
            }
            widen_degenerate(lo, hi)
        }
        (None, Some((lo, hi))) => {
            let (lo, hi) = widen_degenerate(lo, hi);
            let pad = PAD * (hi - lo);
            (lo - pad, hi + pad)
        }
        (None, None) => (0.0, 1.0),
    };
    if !(hi - lo).is_finite() {
        return Err(GearError::param(name, lo, "range too wide to draw"));
    }
    Ok((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_range_pads_and_handles_degenerate_data() {
        let r = resolve("x", None, finite_extent([0.0, f64::NAN, 10.0].into_iter())).unwrap();
        assert!((r.0 + 0.5).abs() < 1e-12 && (r.1 - 10.5).abs() < 1e-12);
        let r = resolve("x", None, Some((2.0, 2.0))).unwrap();
        assert!(r.0 < 2.0 && r.1 > 2.0);
        let r = resolve("x", None, Some((0.0, 0.0))).unwrap();
        assert!(r.0 < 0.0 && r.1 > 0.0);
        assert_eq!(resolve("x", None, None).unwrap(), (0.0, 1.0));
        // A constant with rounding noise: the range of the constant, not of its noise.
        let r = resolve("y", None, Some((1.1, 1.1 + 6e-9))).unwrap();
        assert!(r.0 < 1.05 && r.1 > 1.15 && r.1 - r.0 < 0.13, "{r:?}");
        // Tiny values that do vary (residuals of 1e-18) keep their own range.
        let r = resolve("y", None, Some((-1e-18, 1e-18))).unwrap();
        assert!(r.1 < 1e-17, "{r:?}");
        assert_eq!(finite_extent([f64::NAN, f64::INFINITY].into_iter()), None);
    }

    #[test]
    fn user_range_is_validated() {
        assert_eq!(resolve("x", Some((1.0, 3.0)), None).unwrap(), (1.0, 3.0));
        assert!(resolve("x", Some((3.0, 1.0)), None).is_err());
        assert!(resolve("x", Some((f64::NAN, 1.0)), None).is_err());
        assert!(resolve("x", None, Some((-f64::MAX, f64::MAX))).is_err());
    }
}
