//! Tests of DOP853 alone, on problems with known solutions.

use super::tableau::{A, BHH, C, D, E5};
use super::*;
use std::f64::consts::PI;

fn oscillator(_t: f64, y: &[f64; 2]) -> [f64; 2] {
    [y[1], -y[0]]
}

fn solver<const N: usize>(rtol: f64, atol: f64) -> Dop853<N> {
    Dop853::new(Dop853Options::new(rtol, atol)).unwrap()
}

/// Row sums of A equal the nodes c, and the weights b = A[12] satisfy the quadrature order
/// conditions sum b_j c_j^k = 1 / (k + 1) up to order 8; both embedded estimates annihilate
/// constants, and D only adds terms that vanish at theta = 0 and 1.
#[test]
fn tableau_is_consistent() {
    for i in 1..16 {
        let s: f64 = A[i][..i].iter().sum();
        assert!((s - C[i]).abs() < 1e-14, "row {i}: {s} vs {}", C[i]);
        assert!(A[i][i..].iter().all(|&a| a == 0.0));
    }
    for k in 0..8 {
        let s: f64 = (0..12).map(|j| A[12][j] * C[j].powi(k)).sum();
        assert!((s - 1.0 / (k as f64 + 1.0)).abs() < 1e-14, "order {k}: {s}");
    }
    assert!(E5.iter().sum::<f64>().abs() < 1e-14);
    assert!((BHH.iter().map(|b| b.1).sum::<f64>() - 1.0).abs() < 1e-14);
    // Each dense row must annihilate constants (sum over stages of D = 0) for consistency.
    for row in &D {
        assert!(
            row.iter().sum::<f64>().abs() < 1e-11,
            "{}",
            row.iter().sum::<f64>()
        );
    }
}

/// y'' = -y from (1, 0): y = cos t, to 1e-10 after about three periods.
#[test]
fn harmonic_oscillator_to_1e_10() {
    let mut s = solver::<2>(1e-12, 1e-14);
    let t_end = 20.0;
    let out = s
        .integrate(&oscillator, 0.0, [1.0, 0.0], t_end, &[], None)
        .unwrap();
    assert_eq!(out.t, t_end);
    assert_eq!(out.event, None);
    assert!((out.y[0] - t_end.cos()).abs() < 1e-10, "{}", out.y[0]);
    assert!((out.y[1] + t_end.sin()).abs() < 1e-10, "{}", out.y[1]);
    let st = s.stats();
    assert!(st.accepted_steps > 10);
    // One call of f at the start, one for the initial step, 12 per accepted and 11 per
    // rejected step, nothing else without events or observer.
    assert_eq!(
        st.rhs_evaluations,
        2 + 12 * st.accepted_steps + 11 * st.rejected_steps
    );
}

/// y' = -y: relative error of e^{-t} over 30 time units at rtol 1e-12 (the global error
/// accumulates the local errors of the ~100 steps).
#[test]
fn exponential_decay() {
    let mut s = solver::<1>(1e-12, 1e-30);
    let out = s
        .integrate(
            &|_t: f64, y: &[f64; 1]| [-y[0]],
            0.0,
            [1.0],
            30.0,
            &[],
            None,
        )
        .unwrap();
    let exact = (-30.0f64).exp();
    assert!(((out.y[0] - exact) / exact).abs() < 1e-10, "{}", out.y[0]);
}

/// The dense output between steps matches the exact solution of the oscillator (and of a
/// forced, time-dependent problem), and so does its derivative.
#[test]
fn dense_output_matches_exact_solution() {
    let mut s = solver::<2>(1e-11, 1e-13);
    let mut worst = (0.0f64, 0.0f64);
    let mut spans = Vec::new();
    let mut obs = |d: &DenseStep<2>| {
        let (a, b) = d.span();
        spans.push((a, b));
        for j in 1..8 {
            let t = a + (b - a) * j as f64 / 8.0;
            let y = d.eval(t);
            let dy = d.eval_derivative(t);
            worst.0 = worst
                .0
                .max((y[0] - t.cos()).abs())
                .max((y[1] + t.sin()).abs());
            worst.1 = worst
                .1
                .max((dy[0] + t.sin()).abs())
                .max((dy[1] + t.cos()).abs());
        }
    };
    s.integrate(&oscillator, 0.0, [1.0, 0.0], 15.0, &[], Some(&mut obs))
        .unwrap();
    assert!(worst.0 < 1e-10, "dense value error {}", worst.0);
    assert!(worst.1 < 1e-8, "dense derivative error {}", worst.1);
    // Steps tile the interval.
    assert_eq!(spans.first().unwrap().0, 0.0);
    assert_eq!(spans.last().unwrap().1, 15.0);
    assert!(spans.windows(2).all(|w| w[0].1 == w[1].0));

    // y' = cos(3 t) y: y = exp(sin(3 t) / 3).
    let mut s = solver::<1>(1e-11, 1e-13);
    let mut worst = 0.0f64;
    let mut obs = |d: &DenseStep<1>| {
        let (a, b) = d.span();
        for j in 1..6 {
            let t = a + (b - a) * j as f64 / 6.0;
            worst = worst.max((d.eval(t)[0] - ((3.0 * t).sin() / 3.0).exp()).abs());
        }
    };
    let f = |t: f64, y: &[f64; 1]| [(3.0 * t).cos() * y[0]];
    s.integrate(&f, 0.0, [1.0], 10.0, &[], Some(&mut obs))
        .unwrap();
    assert!(worst < 1e-10, "{worst}");
}

/// cos t falls through 0 at pi/2 and rises through 0 at 3 pi/2: each direction stops at its
/// own crossing, to the accuracy of the solution (~1e-12 at rtol 1e-12), and a restart continues to the next.
#[test]
fn event_time_of_known_crossing() {
    let falling = LevelCrossing {
        component: 0,
        level: 0.0,
        crossing: Crossing::Falling,
    };
    let rising = LevelCrossing {
        crossing: Crossing::Rising,
        ..falling
    };
    let mut s = solver::<2>(1e-12, 1e-14);
    let out = s
        .integrate(
            &oscillator,
            0.0,
            [1.0, 0.0],
            10.0,
            &[&rising, &falling],
            None,
        )
        .unwrap();
    assert_eq!(out.event, Some(1));
    assert!((out.t - PI / 2.0).abs() < 1e-12, "{}", out.t - PI / 2.0);
    // The located root is on the far side of the level, within rounding of it.
    assert!(out.y[0] < 0.0 && out.y[0].abs() < 1e-15, "{}", out.y[0]);
    // Restart on the level: the falling event must not fire again at once.
    let out = s
        .integrate(&oscillator, out.t, out.y, 10.0, &[&rising, &falling], None)
        .unwrap();
    assert_eq!(out.event, Some(0));
    assert!((out.t - 1.5 * PI).abs() < 1e-12, "{}", out.t - 1.5 * PI);

    // A closure event with the default (finite-difference) rate: y0^2 = 1/4 first at pi/3.
    let ev = FnEvent {
        g: |_t: f64, y: &[f64; 2]| y[0] * y[0] - 0.25,
        crossing: Crossing::Either,
    };
    let out = s
        .integrate(&oscillator, 0.0, [1.0, 0.0], 10.0, &[&ev], None)
        .unwrap();
    assert_eq!(out.event, Some(0));
    assert!((out.t - PI / 3.0).abs() < 1e-12, "{}", out.t - PI / 3.0);
}

/// sin t rises 1e-9 above the level 1 - 1e-9 around pi/2 and falls back within +-5e-5, inside
/// one step (about 0.4 long at rtol 1e-10): both ends of the step lie below the level, so only
/// the extremum test finds the crossing. A level 1e-9 above the maximum must not fire.
#[test]
fn shallow_crossing_inside_one_step_is_found() {
    let f = |t: f64, _y: &[f64; 1]| [t.cos()];
    for (level, expect) in [(1.0 - 1e-9, true), (1.0 + 1e-9, false)] {
        let ev = LevelCrossing {
            component: 0,
            level,
            crossing: Crossing::Rising,
        };
        let mut s = solver::<1>(1e-10, 1e-12);
        let mut spans = Vec::new();
        let mut obs = |d: &DenseStep<1>| spans.push(d.span());
        let out = s
            .integrate(&f, 0.0, [0.0], 3.0, &[&ev], Some(&mut obs))
            .unwrap();
        if expect {
            assert_eq!(out.event, Some(0));
            let exact = level.asin();
            assert!((out.t - exact).abs() < 1e-7, "{} vs {exact}", out.t);
            // The crossing really was invisible at the step ends.
            assert!(spans.iter().all(|&(a, _)| a.sin() < level));
        } else {
            assert_eq!(out.event, None);
            assert_eq!(out.t, 3.0);
        }
    }
}

/// Failures are errors, not panics: too many steps, invalid options, a blow-up.
#[test]
fn failures_are_errors() {
    let mut opts = Dop853Options::new(1e-12, 1e-14);
    opts.max_steps = 5;
    let mut s = Dop853::new(opts).unwrap();
    let r = s.integrate(&oscillator, 0.0, [1.0, 0.0], 100.0, &[], None);
    assert!(matches!(r, Err(GearError::Numerical(_))));

    assert!(Dop853::<2>::new(Dop853Options::new(0.0, 1e-6)).is_err());
    assert!(Dop853::<2>::new(Dop853Options::new(1e-6, -1.0)).is_err());
    assert!(Dop853::<2>::new(Dop853Options::new(1e-6, f64::INFINITY)).is_err());
    let mut s = solver::<2>(1e-6, 1e-8);
    assert!(s
        .integrate(&oscillator, 1.0, [1.0, 0.0], 0.0, &[], None)
        .is_err());
    assert!(s
        .integrate(&oscillator, 0.0, [f64::NAN, 0.0], 1.0, &[], None)
        .is_err());

    // y' = y^2 from 1 blows up at t = 1.
    let mut s = solver::<1>(1e-8, 1e-10);
    let r = s.integrate(
        &|_t: f64, y: &[f64; 1]| [y[0] * y[0]],
        0.0,
        [1.0],
        2.0,
        &[],
        None,
    );
    assert!(matches!(r, Err(GearError::Numerical(_))), "{r:?}");
}

/// A component with infinite atol is integrated but does not steer the steps: adding it leaves
/// the controlled components bitwise unchanged.
#[test]
fn uncontrolled_components_do_not_change_steps() {
    let mut a = solver::<2>(1e-10, 1e-12);
    let ya = a
        .integrate(&oscillator, 0.0, [1.0, 0.0], 7.0, &[], None)
        .unwrap();
    let mut opts = Dop853Options::new(1e-10, 1e-12);
    opts.atol[2] = f64::INFINITY;
    let mut b = Dop853::<3>::new(opts).unwrap();
    let f3 = |_t: f64, y: &[f64; 3]| [y[1], -y[0], 1e3 * y[0].sin()];
    let yb = b
        .integrate(&f3, 0.0, [1.0, 0.0, 0.0], 7.0, &[], None)
        .unwrap();
    assert_eq!(ya.y[0], yb.y[0]);
    assert_eq!(ya.y[1], yb.y[1]);
    assert_eq!(a.stats().accepted_steps, b.stats().accepted_steps);
}

/// An interval of a few ulps (an event just before the end) is closed, not an error, and the
/// observer still receives a piece that reaches t_end.
#[test]
fn negligible_remainder_is_closed() {
    let mut s = solver::<2>(1e-12, 1e-14);
    let t0 = 10.0 - 4.0 * f64::EPSILON * 10.0;
    let mut last = (0.0, 0.0);
    let mut obs = |d: &DenseStep<2>| last = d.span();
    let out = s
        .integrate(
            &oscillator,
            t0,
            [t0.cos(), -t0.sin()],
            10.0,
            &[],
            Some(&mut obs),
        )
        .unwrap();
    assert_eq!(out.t, 10.0);
    assert_eq!(last.1, 10.0);
    assert!((out.y[0] - 10f64.cos()).abs() < 1e-15);
}
