//! The paper's per-case solution with the truncated describing functions (Sec. 4).
//!
//! Each impact regime has its own closed-form describing functions, obtained from eq. 8 with the
//! truncated g, h of eq. 9 where |gamma| <= 1 and the exact |gamma|, sign(gamma) where
//! |gamma| > 1:
//!
//! - case I (eq. 12-13): N_m q_m = q_m - 1, N_a = 1, a linear system;
//! - case II (eq. 16-17): gamma+ > 1, |gamma-| < 1;
//! - case III (eq. 19): |gamma+-| < 1.
//!
//! A candidate solution of a case's equations is kept only if it satisfies that case's condition
//! (eq. 11, 15, 18), as the paper prescribes. Within its region each case's formulas equal the
//! piecewise truncated describing functions of [`super::describing`] (tested below), so the union
//! of the accepted solutions is the set of solutions of eq. 10 with those functions.

use super::describing::{G2, H3};
use std::f64::consts::PI;

/// Case I closed form, eq. 13a, b: (q_aI, q_mI) = (F_ah Omega^2 / sqrt((1 - Omega^2)^2 +
/// (2 zeta Omega)^2), F_m + 1).
pub(crate) fn case1(fm: f64, fah: f64, zeta: f64, omega: f64) -> (f64, f64) {
    let w2 = omega * omega;
    (fah * w2 / (1.0 - w2).hypot(2.0 * zeta * omega), fm + 1.0)
}

/// Case I condition: q(t) > 1 throughout, q_m - q_a > 1 (eq. 11; its literal form
/// |q_m +- q_a| > 1 would also admit q_a > q_m + 1, which is not case I).
pub(crate) fn case1_valid(qm: f64, qa: f64) -> bool {
    qm - qa > 1.0
}

/// Case II mean balance with eq. 17a: N_m q_m = F_m reads, with u = q_m - 1,
/// (pi - 2)/(2 pi q_a) u^2 + u / 2 + q_a / pi - F_m = 0. The left side increases with u on the case
/// II range |u| < q_a, so the larger root is the only admissible one. `None` if no real root.
pub(crate) fn case2_qm(fm: f64, qa: f64) -> Option<f64> {
    let a = G2 / (PI * qa);
    let b = 0.5;
    let c = qa / PI - fm;
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    // Larger root (-b + sqrt(disc)) / 2a, written without cancellation.
    Some(1.0 - 2.0 * c / (b + disc.sqrt()))
}

/// Case II N_a, eq. 17b: 1/2 - (2 (1 - q_m) / (pi q_a)) [1 - ((4 - pi)/4) gamma-^2].
pub(crate) fn case2_na(qm: f64, qa: f64) -> f64 {
    let gm = (1.0 - qm) / qa;
    0.5 - 2.0 * (1.0 - qm) / (PI * qa) * (1.0 - H3 * gm * gm)
}

/// Case II condition, eq. 15: q_m + q_a > 1 and |q_m - q_a| < 1.
pub(crate) fn case2_valid(qm: f64, qa: f64) -> bool {
    qm + qa > 1.0 && (qm - qa).abs() < 1.0
}

/// Case III mean balance with eq. 19a: q_m = F_m / N_m, N_m = 1 - 2 (pi - 2) / (pi q_a).
/// `None` when N_m <= 0 (q_a <= 0.727, where case III cannot hold anyway since it needs q_a > 1).
pub(crate) fn case3_qm(fm: f64, qa: f64) -> Option<f64> {
    let nm = 1.0 - 2.0 * (PI - 2.0) / (PI * qa);
    (nm > 0.0).then(|| fm / nm)
}

/// Case III N_a, eq. 19b: 1 - (4/pi)[1/q_a - ((4 - pi)/4)(1 + 3 q_m^2)/q_a^3].
pub(crate) fn case3_na(qm: f64, qa: f64) -> f64 {
    1.0 - 4.0 / PI * (1.0 / qa - H3 * (1.0 + 3.0 * qm * qm) / (qa * qa * qa))
}

/// Case III condition, eq. 18: q_a > |1 - q_m| and q_a > |1 + q_m|.
pub(crate) fn case3_valid(qm: f64, qa: f64) -> bool {
    qa > (1.0 - qm).abs() && qa > (1.0 + qm).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hb::describing::{mean_force, n_a, DfMethod};

    #[test]
    fn per_case_formulas_equal_piecewise_truncated_functions_in_their_regions() {
        // Same algebra evaluated two ways; 1e-13 covers the rounding of O(1..10) quantities.
        let t = DfMethod::Truncated;
        for &fm in &[0.05, 0.1, 0.5] {
            for k in 1..400 {
                let qa = 0.01 * k as f64;
                if let Some(qm) = case2_qm(fm, qa) {
                    if case2_valid(qm, qa) {
                        assert!((mean_force(qm, qa, t) - fm).abs() < 1e-13);
                        assert!((n_a(qm, qa, t) - case2_na(qm, qa)).abs() < 1e-13);
                    }
                }
                if let Some(qm) = case3_qm(fm, qa) {
                    if case3_valid(qm, qa) {
                        assert!((mean_force(qm, qa, t) - fm).abs() < 1e-13);
                        assert!((n_a(qm, qa, t) - case3_na(qm, qa)).abs() < 1e-13);
                    }
                }
            }
        }
        // Case I: mean q_m - 1 = F_m and N_a = 1 (eq. 12).
        let (qa, qm) = case1(0.1, 0.05, 0.05, 0.5);
        assert!(case1_valid(qm, qa));
        assert!((mean_force(qm, qa, t) - 0.1).abs() < 1e-15);
        assert_eq!(n_a(qm, qa, t), 1.0);
    }

    #[test]
    fn classification_follows_fig9() {
        assert!(case1_valid(1.5, 0.3) && !case2_valid(1.5, 0.3) && !case3_valid(1.5, 0.3));
        assert!(!case1_valid(1.0, 0.5) && case2_valid(1.0, 0.5) && !case3_valid(1.0, 0.5));
        assert!(!case1_valid(0.2, 1.5) && !case2_valid(0.2, 1.5) && case3_valid(0.2, 1.5));
        // All in the gap (|q| < 1 throughout): none of the cases (mean f = 0 != F_m).
        assert!(!case1_valid(0.0, 0.5) && !case2_valid(0.0, 0.5) && !case3_valid(0.0, 0.5));
    }
}
