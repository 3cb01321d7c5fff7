//! Transition frequencies between the no-impact regime and tooth separation (eq. 14).
//!
//! Case I (eq. 13) holds while q_aI < q_mI - 1 = F_m. Setting q_aI = F_m gives, with
//! x = Omega^2 and r = F_ah / F_m,
//!
//!   (1 - r^2) x^2 - 2 (1 - 2 zeta^2) x + 1 = 0,
//!
//! whose roots are eq. 14: x = ((1 - 2 zeta^2) -+ sqrt((1 - 2 zeta^2)^2 - (1 - r^2))) / (1 - r^2).

use super::df_solve::validate;
use crate::error::Result;

/// Transition frequencies (Omega_t1, Omega_t2) of eq. 14: where the case I amplitude q_aI of
/// eq. 13a reaches F_m, below (t1) and above (t2) resonance. Case I holds for Omega < Omega_t1
/// and Omega > Omega_t2.
///
/// - r = F_ah / F_m < 1: both when the discriminant is >= 0, else `(None, None)` (no
///   separation at any frequency, e.g. F_ah = 0).
/// - r = 1: the equation is linear, Omega_t1 = 1 / sqrt(2 (1 - 2 zeta^2)) if zeta^2 < 1/2;
///   no Omega_t2.
/// - r > 1: one positive root Omega_t1; no Omega_t2 (case I is not regained, as
///   q_aI -> F_ah > F_m for Omega -> infinity).
///
/// Errors: `InvalidParameter` unless F_m > 0, F_ah >= 0, 0 < zeta < 1, all finite.
pub fn transition_frequencies(fm: f64, fah: f64, zeta: f64) -> Result<(Option<f64>, Option<f64>)> {
    validate(fm, fah, zeta)?;
    let r = fah / fm;
    let a = 1.0 - r * r;
    let b = 1.0 - 2.0 * zeta * zeta;
    let omega = |x: f64| (x.is_finite() && x > 0.0).then(|| x.sqrt());
    if a == 0.0 {
        return Ok((omega(1.0 / (2.0 * b)), None));
    }
    let disc = b * b - a;
    if disc < 0.0 {
        return Ok((None, None));
    }
    // Roots of a x^2 - 2 b x + 1 = 0 without cancellation: x = 1 / (b + s) and (b + s) / a with
    // s = sign(b) sqrt(disc); x_small = 1 / (b + sqrt(disc)) is the "-" root of eq. 14 for b > 0.
    let s = disc.sqrt().copysign(b);
    let q = b + s;
    let (x1, x2) = if q == 0.0 {
        (f64::NAN, f64::NAN)
    } else {
        (1.0 / q, q / a)
    };
    let mut roots: Vec<f64> = [x1, x2].into_iter().filter_map(omega).collect();
    roots.sort_by(f64::total_cmp);
    Ok(match (a > 0.0, roots.as_slice()) {
        (true, [t1, t2]) => (Some(*t1), Some(*t2)),
        (_, [t1, ..]) => (Some(*t1), None),
        _ => (None, None),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hb::cases::case1;

    #[test]
    fn paper_example_transitions() {
        // Hand evaluation of eq. 14 for F_m = 0.1, F_ah = 0.05, zeta = 0.05: 1 - r^2 = 0.75,
        // 1 - 2 zeta^2 = 0.995, sqrt(0.995^2 - 0.75) = 0.4899235, x = 0.6734353 and 1.9798980,
        // Omega = 0.820631 and 1.407088. Asserted to 1e-4 as asked (the values agree to 1e-6).
        let (t1, t2) = transition_frequencies(0.1, 0.05, 0.05).unwrap_or((None, None));
        let (t1, t2) = (t1.unwrap_or(f64::NAN), t2.unwrap_or(f64::NAN));
        assert!((t1 - 0.8206).abs() < 1e-4, "{t1}");
        assert!((t2 - 1.4071).abs() < 1e-4, "{t2}");
        // At both, eq. 13a gives q_aI = F_m exactly (to rounding).
        for t in [t1, t2] {
            assert!((case1(0.1, 0.05, 0.05, t).0 - 0.1).abs() < 1e-12);
        }
    }

    #[test]
    fn degenerate_force_ratios() {
        // r = 1: x = 1 / (2 (1 - 2 zeta^2)).
        let (t1, t2) = transition_frequencies(0.1, 0.1, 0.05).unwrap_or((None, None));
        let want = (1.0 / (2.0 * 0.995f64)).sqrt();
        assert!((t1.unwrap_or(f64::NAN) - want).abs() < 1e-14 && t2.is_none());
        // r > 1 (F_m 0.1, F_ah 0.2): one root, where q_aI = F_m.
        let (t1, t2) = transition_frequencies(0.1, 0.2, 0.05).unwrap_or((None, None));
        let t1 = t1.unwrap_or(f64::NAN);
        assert!(t2.is_none() && (case1(0.1, 0.2, 0.05, t1).0 - 0.1).abs() < 1e-12);
        // Large F_hat: no transition at all; F_ah = 0 likewise.
        assert_eq!(
            transition_frequencies(5.0, 0.05, 0.05).ok(),
            Some((None, None))
        );
        assert_eq!(
            transition_frequencies(0.1, 0.0, 0.05).ok(),
            Some((None, None))
        );
        assert!(transition_frequencies(0.0, 0.1, 0.05).is_err());
        assert!(transition_frequencies(0.1, 0.1, 1.0).is_err());
        assert!(transition_frequencies(f64::NAN, 0.1, 0.1).is_err());
    }
}
