//! Transition frequencies between the no-impact regime and tooth separation (eq. 14).
//!
//! Case I (eq. 13) holds while q_aI < q_mI - 1 = F_m. Setting q_aI = F_m gives, with
//! x = Omega^2 and r = F_ah / F_m,
//!
//!   (1 - r^2) x^2 - 2 (1 - 2 zeta^2) x + 1 = 0,
//!
//! whose roots are eq. 14: x = ((1 - 2 zeta^2) -+ sqrt((1 - 2 zeta^2)^2 - (1 - r^2))) / (1 - r^2).

use super::df_solve::{validate, DfForcing};
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

/// The largest linear (case I) amplitude over frequency, and where it is reached, for the STE
/// excitation of eq. 5 (force F_ah Omega^2, eq. 13a) and for an external torque of the same
/// amplitude (eq. 4, force F_ah): both peaks are F_ah / (2 zeta sqrt(1 - zeta^2)), at
/// Omega^2 = 1 / (1 - 2 zeta^2) and Omega^2 = 1 - 2 zeta^2 (the maxima of Omega^2 / |D| and
/// 1 / |D|, |D|^2 = (1 - Omega^2)^2 + (2 zeta Omega)^2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearPeak {
    /// Peak amplitude q_a.
    pub qa: f64,
    /// Frequency of the peak under the STE excitation (eq. 5).
    pub omega_ste: f64,
    /// Frequency of the peak under the torque excitation (eq. 4).
    pub omega_torque: f64,
}

/// [`LinearPeak`] of a forcing amplitude `fah` at damping `zeta` (0 < zeta < 1/sqrt(2), where
/// the resonance has a peak).
///
/// Errors: `InvalidParameter` unless F_ah >= 0 and 0 < zeta < 1/sqrt(2), finite.
pub fn linear_peak(fah: f64, zeta: f64) -> Result<LinearPeak> {
    validate(1.0, fah, zeta)?;
    let b = 1.0 - 2.0 * zeta * zeta;
    if b <= 0.0 {
        return Err(crate::error::GearError::param(
            "zeta",
            zeta,
            "the linear response has a resonance peak only for zeta < 1/sqrt(2)",
        ));
    }
    Ok(LinearPeak {
        qa: fah / (2.0 * zeta * (1.0 - zeta * zeta).sqrt()),
        omega_ste: (1.0 / b).sqrt(),
        omega_torque: b.sqrt(),
    })
}

/// Transition frequencies of eq. 14 for any [`DfForcing`]: where the case I amplitude
/// F / |D| (F = F_ah Omega^2 + F_aT, |D|^2 = (1 - Omega^2)^2 + (2 zeta Omega)^2) reaches F_m.
/// With x = Omega^2 this is
///
///   (F_ah^2 - F_m^2) x^2 + 2 (F_ah F_aT + F_m^2 (1 - 2 zeta^2)) x + F_aT^2 - F_m^2 = 0,
///
/// eq. 14 for the STE alone and eq. 14 with x replaced by 1 / x for the torque of eq. 4 alone.
/// Returns the positive roots as frequencies, increasing; case I holds where F / |D| < F_m.
///
/// Errors: `InvalidParameter` unless F_m > 0, F_ah >= 0, F_aT >= 0, 0 < zeta < 1, all finite.
pub fn forced_transition_frequencies(fm: f64, f: DfForcing, zeta: f64) -> Result<Vec<f64>> {
    validate(fm, f.ste, zeta)?;
    validate(fm, f.torque, zeta)?;
    let m2 = fm * fm;
    let a = f.ste * f.ste - m2;
    let b = 2.0 * (f.ste * f.torque + m2 * (1.0 - 2.0 * zeta * zeta));
    let c = f.torque * f.torque - m2;
    let mut xs = Vec::new();
    if a == 0.0 {
        if b != 0.0 {
            xs.push(-c / b);
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            // Without cancellation: q = -(b + sign(b) sqrt(disc)) / 2, roots q / a and c / q.
            let q = -0.5 * (b + disc.sqrt().copysign(b));
            xs.push(q / a);
            if q != 0.0 {
                xs.push(c / q);
            }
        }
    }
    let mut out: Vec<f64> = xs
        .into_iter()
        .filter(|x| x.is_finite() && *x > 0.0)
        .map(f64::sqrt)
        .collect();
    out.sort_by(f64::total_cmp);
    out.dedup();
    Ok(out)
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

    /// The peak of eq. 13a found by a fine scan equals the closed form (F_hat 10, zeta 0.05:
    /// 0.01 / (0.1 sqrt(0.9975)) = 0.1001252, issue 23's grazing depth 1.25e-4 over F_m); at
    /// the torque transitions the eq. 4 amplitude F_T / |D| equals F_m.
    #[test]
    fn linear_peak_and_torque_transitions() {
        let p = linear_peak(0.01, 0.05).unwrap();
        assert!((p.qa - 0.100_125_2).abs() < 1e-7, "{}", p.qa);
        let scan = (0..=200_000)
            .map(|i| 0.9 + 2e-6 * i as f64)
            .map(|w| (case1(0.1, 0.01, 0.05, w).0, w))
            .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
        assert!((scan.0 - p.qa).abs() < 1e-10 && (scan.1 - p.omega_ste).abs() < 1e-5);
        let torque_qa = |w: f64| 0.01 / ((1.0 - w * w).powi(2) + (0.1 * w).powi(2)).sqrt();
        assert!((torque_qa(p.omega_torque) - p.qa).abs() < 1e-12);
        let t = forced_transition_frequencies(0.1, DfForcing::torque(0.01), 0.05).unwrap();
        let (t1, t2) = (t[0], t[1]);
        assert!(t1 < p.omega_torque && p.omega_torque < t2);
        for t in [t1, t2] {
            assert!((torque_qa(t) - 0.1).abs() < 1e-9, "{t}");
        }
        // The eq. 4 roots are the reciprocals of eq. 14's.
        let (s1, s2) = transition_frequencies(0.1, 0.01, 0.05).unwrap();
        assert!((t1 * s2.unwrap() - 1.0).abs() < 1e-9 && (t2 * s1.unwrap() - 1.0).abs() < 1e-9);
        // F_T > F_m: case I only above the one root.
        let t = forced_transition_frequencies(0.1, DfForcing::torque(0.2), 0.05).unwrap();
        assert_eq!(t.len(), 1);
        assert!((torque_qa(t[0]) * 20.0 - 0.1).abs() < 1e-9);
        // The STE alone gives eq. 14's roots; STE and torque together the roots of F / |D| = F_m.
        let s = forced_transition_frequencies(0.1, DfForcing::ste(0.05), 0.05).unwrap();
        let (e1, e2) = transition_frequencies(0.1, 0.05, 0.05).unwrap();
        assert!((s[0] - e1.unwrap()).abs() < 1e-12 && (s[1] - e2.unwrap()).abs() < 1e-12);
        let both = DfForcing {
            ste: 0.03,
            torque: 0.02,
        };
        for w in forced_transition_frequencies(0.1, both, 0.05).unwrap() {
            let d = ((1.0 - w * w).powi(2) + (0.1 * w).powi(2)).sqrt();
            assert!((both.force(w) / d - 0.1).abs() < 1e-9, "{w}");
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
