//! Tests of the describing-function solution against closed forms and the paper's examples.

use super::*;
use crate::model::Impact;

fn solve(fm: f64, fah: f64, zeta: f64, w: f64, m: DfMethod) -> Vec<DfSolution> {
    df_solutions(fm, fah, zeta, w, m).unwrap_or_default()
}

fn cases(s: &[DfSolution]) -> Vec<u8> {
    s.iter().map(|x| x.case.case()).collect()
}

const METHODS: [DfMethod; 2] = [DfMethod::Exact, DfMethod::Truncated];

#[test]
fn heavily_loaded_pair_is_linear_eq13() {
    // F_hat = 100: q_aI <= F_ah / (2 zeta) = 0.5 < F_m, so only case I exists and eq. 13 is exact.
    // Brent refines to a few ulp, so 1e-12 relative on q_a leaves a wide margin; q_m = F_m + 1
    // comes from the mean balance solved to rounding (1e-14).
    let (fm, fah, zeta) = (5.0, 0.05, 0.05);
    for k in 1..=60 {
        let w = 0.05 * k as f64;
        let want = fah * w * w / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
        let phase = -(2.0 * zeta * w).atan2(1.0 - w * w);
        for m in METHODS {
            let s = solve(fm, fah, zeta, w, m);
            assert_eq!(s.len(), 1, "{m:?} omega {w}");
            assert_eq!(s[0].case, Impact::None);
            assert!(
                (s[0].qa / want - 1.0).abs() < 1e-12,
                "{m:?} {w}: {} vs {want}",
                s[0].qa
            );
            assert!((s[0].qm - (fm + 1.0)).abs() < 1e-14);
            assert!((s[0].phase - phase).abs() < 1e-10);
            assert_eq!(s[0].stable, Some(true));
        }
    }
}

#[test]
fn paper_example_f_hat_2_is_dual_valued_near_resonance() {
    // F_m 0.1, F_ah 0.05, zeta 0.05 (Fig. 11, 15b). Measured with the exact DF (bisection on
    // Omega): the jump-down fold of the case II branch is at Omega = 0.68014, case I ends at
    // Omega_t1 = 0.82063 (eq. 14), and the lightly separated continuation of case I folds with the
    // unstable branch at 0.82607. Edges are asserted to 1e-3 by probing 5e-4 either side.
    let (fm, fah, zeta) = (0.1, 0.05, 0.05);
    let e = DfMethod::Exact;
    assert_eq!(cases(&solve(fm, fah, zeta, 0.6, e)), vec![1]);
    assert_eq!(cases(&solve(fm, fah, zeta, 0.9, e)), vec![2]);
    assert_eq!(cases(&solve(fm, fah, zeta, 1.5, e)), vec![1]);
    for w in [0.70, 0.75, 0.80] {
        let s = solve(fm, fah, zeta, w, e);
        assert_eq!(cases(&s), vec![1, 2, 2], "omega {w}");
        let stable: Vec<_> = s.iter().map(|x| x.stable).collect();
        assert_eq!(stable, vec![Some(true), Some(false), Some(true)]);
    }
    assert_eq!(solve(fm, fah, zeta, 0.68014 - 5e-4, e).len(), 1);
    assert_eq!(solve(fm, fah, zeta, 0.68014 + 5e-4, e).len(), 3);
    assert!(cases(&solve(fm, fah, zeta, 0.82063 - 5e-4, e)).contains(&1));
    assert_eq!(
        cases(&solve(fm, fah, zeta, 0.82063 + 5e-4, e)),
        vec![2, 2, 2]
    );
    assert_eq!(solve(fm, fah, zeta, 0.82607 - 5e-4, e).len(), 3);
    assert_eq!(solve(fm, fah, zeta, 0.82607 + 5e-4, e).len(), 1);
    // Truncated: same structure, folds at 0.68012 and 0.82185 (the truncated h has a kink at
    // |gamma| = 1, so the separated continuation of case I folds sooner).
    let t = DfMethod::Truncated;
    assert_eq!(cases(&solve(fm, fah, zeta, 0.75, t)), vec![1, 2, 2]);
    assert_eq!(solve(fm, fah, zeta, 0.68012 - 5e-4, t).len(), 1);
    assert_eq!(solve(fm, fah, zeta, 0.68012 + 5e-4, t).len(), 3);
    assert_eq!(solve(fm, fah, zeta, 0.82185 - 5e-4, t).len(), 3);
    assert_eq!(solve(fm, fah, zeta, 0.82185 + 5e-4, t).len(), 1);
}

#[test]
fn paper_example_f_hat_half_has_no_case_iii_at_zeta_005() {
    // F_m 0.1, F_ah 0.2, zeta 0.05 (Fig. 12, 15d). The paper reports case I + III for
    // 0.4 < Omega < 0.6, all three cases for 0.6-0.625, only case II above. Eq. 10a with
    // 0 <= N_a <= 1 bounds q_a <= F_ah Omega / (2 zeta) = 2 Omega for Omega <= 1, and case III
    // needs q_a > 1 + |q_m| > 1, so no case III can exist below Omega = 0.5 with either method;
    // the scan finds none anywhere on [0.2, 1.6].
    let (fm, fah, zeta) = (0.1, 0.2, 0.05);
    let om: Vec<f64> = (0..=1400).map(|k| 0.2 + 0.001 * k as f64).collect();
    for m in METHODS {
        let all = df_response(fm, fah, zeta, &om, m).unwrap_or_default();
        assert!(all.len() > om.len());
        assert!(all.iter().all(|s| s.case != Impact::Double), "{m:?}");
    }
    // Measured structure (exact DF): case I alone below 0.44320; from there a stable case II
    // branch with q_min = q_m - q_a of -0.28 .. 0.05 (single-sided, not double-sided) and an
    // unstable one coexist with case I up to Omega_t1 = 0.57807 (eq. 14 with F_ah/F_m = 2), three
    // case II solutions up to the fold at 0.60478, then case II alone. Truncated: 0.43989,
    // 0.57807, 0.60164. Probed 5e-4 either side of each edge.
    for (m, lo, hi) in [
        (DfMethod::Exact, 0.44320, 0.60478),
        (DfMethod::Truncated, 0.43989, 0.60164),
    ] {
        assert_eq!(cases(&solve(fm, fah, zeta, lo - 5e-4, m)), vec![1]);
        assert_eq!(cases(&solve(fm, fah, zeta, lo + 5e-4, m)), vec![1, 2, 2]);
        assert_eq!(
            cases(&solve(fm, fah, zeta, 0.57807 - 5e-4, m)),
            vec![1, 2, 2]
        );
        assert_eq!(
            cases(&solve(fm, fah, zeta, 0.57807 + 5e-4, m)),
            vec![2, 2, 2]
        );
        assert_eq!(cases(&solve(fm, fah, zeta, hi - 5e-4, m)), vec![2, 2, 2]);
        assert_eq!(cases(&solve(fm, fah, zeta, hi + 5e-4, m)), vec![2]);
    }
    let upper = solve(fm, fah, zeta, 0.5, DfMethod::Exact);
    assert!(upper.iter().all(|s| s.qm - s.qa > -1.0));
}

#[test]
fn case_iii_appears_at_lower_damping() {
    // Same loads at zeta = 0.02 (Sec. 3, Fig. 2b: three period-one attractors at Omega = 0.5, no
    // impact, single- and double-sided). The exact DF gives five solutions, stable ones in
    // cases I, II and III. (Case III disappears above zeta = 0.0324 exact, 0.0330 truncated.)
    for m in METHODS {
        let s = solve(0.1, 0.2, 0.02, 0.5, m);
        assert_eq!(cases(&s), vec![1, 2, 2, 3, 3], "{m:?}");
        let stable: Vec<u8> = s
            .iter()
            .filter(|x| x.stable == Some(true))
            .map(|x| x.case.case())
            .collect();
        assert_eq!(stable, vec![1, 2, 3]);
    }
    let none = |zeta| {
        let om: Vec<f64> = (0..=600).map(|k| 0.3 + 0.001 * k as f64).collect();
        df_response(0.1, 0.2, zeta, &om, DfMethod::Exact)
            .unwrap_or_default()
            .iter()
            .all(|s| s.case != Impact::Double)
    };
    assert!(!none(0.031) && none(0.034));
}

#[test]
fn response_equals_pointwise_solutions_and_keeps_order() {
    // df_response shares one q_a table over all frequencies; df_solutions builds its own.
    // Both refine with Brent to a few ulp, so 1e-10 covers the different starting brackets.
    let om: Vec<f64> = (0..121).map(|k| 1.4 - 0.01 * k as f64).collect();
    for m in METHODS {
        let all = df_response(0.1, 0.05, 0.05, &om, m).unwrap_or_default();
        let mut i = 0;
        for &w in &om {
            let s = solve(0.1, 0.05, 0.05, w, m);
            assert!(!s.is_empty());
            for x in s {
                let y = all[i];
                assert_eq!((y.omega, y.case, y.stable), (w, x.case, x.stable));
                assert!((y.qa - x.qa).abs() < 1e-10 && (y.qm - x.qm).abs() < 1e-10);
                i += 1;
            }
        }
        assert_eq!(i, all.len());
        assert!(all
            .windows(2)
            .all(|p| p[0].omega != p[1].omega || p[0].qa <= p[1].qa));
    }
}

#[test]
fn solutions_satisfy_eq10_and_the_slope_criterion_alternates() {
    // Residuals of eq. 10a, 10b and the phase of eq. 10c at each root, exact DF: 1e-12 on O(1)
    // quantities refined to a few ulp. Sorted by q_a, stable and unstable roots alternate and
    // the outermost are stable (R < 0 below the lower bound, > 0 above the upper one).
    let (fm, fah, zeta) = (0.1, 0.2, 0.02);
    for k in 0..=120 {
        let w = 0.3 + 0.01 * k as f64;
        let s = solve(fm, fah, zeta, w, DfMethod::Exact);
        assert_eq!(s.len() % 2, 1, "omega {w}");
        for (i, x) in s.iter().enumerate() {
            assert_eq!(x.stable, Some(i % 2 == 0));
            let na = n_a(x.qm, x.qa, DfMethod::Exact);
            let den = ((na - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
            assert!((x.qa * den - fah * w * w).abs() < 1e-12);
            assert!((mean_force(x.qm, x.qa, DfMethod::Exact) - fm).abs() < 1e-12);
            assert!((x.phase + (2.0 * zeta * w).atan2(na - w * w)).abs() < 1e-12);
        }
    }
}

#[test]
fn zero_excitation_and_invalid_inputs() {
    for m in METHODS {
        let s = solve(0.3, 0.0, 0.05, 0.9, m);
        assert_eq!(s.len(), 1);
        assert_eq!((s[0].qa, s[0].qm, s[0].case), (0.0, 1.3, Impact::None));
        for (fm, fah, zeta, w) in [
            (0.0, 0.1, 0.05, 1.0),
            (-1.0, 0.1, 0.05, 1.0),
            (0.1, -0.1, 0.05, 1.0),
            (0.1, 0.1, 0.0, 1.0),
            (0.1, 0.1, 1.0, 1.0),
            (0.1, 0.1, 0.05, 0.0),
            (0.1, 0.1, 0.05, f64::NAN),
            (f64::INFINITY, 0.1, 0.05, 1.0),
            (0.1, f64::NAN, 0.05, 1.0),
        ] {
            assert!(matches!(
                df_solutions(fm, fah, zeta, w, m),
                Err(crate::GearError::InvalidParameter { .. })
            ));
            assert!(df_response(fm, fah, zeta, &[0.5, w], m).is_err());
        }
        assert!(df_response(0.1, 0.1, 0.05, &[], m).is_ok_and(|v| v.is_empty()));
        // Extreme but valid inputs give an answer or a typed error, never a panic.
        let _ = df_solutions(0.1, 0.1, 1e-300, 1.0, m);
        let _ = df_solutions(0.1, 1e-310, 0.05, 1e-3, m);
        let _ = df_solutions(0.1, 0.1, 0.05, 1e200, m);
    }
}
