//! The mean (zeroth-harmonic) balance of eq. 10b with the exact describing function:
//! mean_f(q_m, q_a) = F_m, solved for q_m at given q_a.
//!
//! d mean_f / d q_m is the fraction of the period spent in contact (>= 0), so mean_f is
//! non-decreasing in q_m, and strictly increasing wherever mean_f > 0 (the orbit reaches contact).
//! Since F_m > 0 the root is unique. As q - 1 <= f(q) <= q + 1, mean_f lies within 1 of q_m, so
//! the root lies in [F_m - 1, F_m + 1], which brackets it for a safeguarded Newton iteration.

use super::describing::{mean_force, mean_force_slope_exact, DfMethod};

/// Unique q_m with mean_f(q_m, q_a) = F_m for the exact describing function (F_m > 0, q_a >= 0).
/// `hint` is a starting guess (e.g. from a neighbouring q_a); the bracket guarantees convergence.
pub(crate) fn exact_qm(fm: f64, qa: f64, hint: Option<f64>) -> f64 {
    let (mut lo, mut hi) = (fm - 1.0, fm + 1.0);
    let mut x = match hint {
        Some(h) if h > lo && h < hi => h,
        _ => fm + 1.0 - f64::EPSILON,
    };
    for _ in 0..200 {
        let r = mean_force(x, qa, DfMethod::Exact) - fm;
        if r == 0.0 {
            return x;
        }
        if r < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let slope = mean_force_slope_exact(x, qa);
        let newton = x - r / slope;
        let next = if slope > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - x).abs();
        x = next;
        if step <= 2.0 * f64::EPSILON * (1.0 + x.abs())
            || hi - lo <= 4.0 * f64::EPSILON * (1.0 + x.abs())
        {
            return x;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_balance_is_solved_to_rounding() {
        // Residuals are checked at 1e-14: the mean force is O(1) and is computed with a few
        // rounding errors; Newton stops at a step of a few ulp.
        for &fm in &[0.01, 0.1, 1.0, 5.0] {
            for &qa in &[0.0, 1e-6, 0.05, 0.5, 1.0, 1.3, 4.0, 50.0] {
                for hint in [None, Some(0.0), Some(fm + 0.9)] {
                    let qm = exact_qm(fm, qa, hint);
                    let r = mean_force(qm, qa, DfMethod::Exact) - fm;
                    assert!(r.abs() < 1e-14, "fm={fm} qa={qa}: residual {r}");
                }
            }
        }
        // Case I: q_m = F_m + 1 (eq. 13b) whenever q_a < F_m.
        assert!((exact_qm(0.1, 0.05, None) - 1.1).abs() < 1e-15);
    }
}
