//! Cross-check of the two period maps: the exact piecewise solver (k = 1) and DOP853 with region
//! switching must give the same Poincare points, to 1e-9, over 200 forcing periods, in each
//! impact regime of Fig. 9. The cases are stable period-one orbits reached through
//! well-conditioned transients (the norm of the accumulated Jacobian of the period map stays
//! below ~3.2, measured with the exact tangent map), so the comparison measures integration error
//! and not the amplification of rounding by a saddle or by chaos.

use geardyn::model::{GearPair, Impact, Term};
use geardyn::sim::{ExactFlow, PeriodFlow, Piece, RkFlow, State};

/// Tolerance of the Runge-Kutta flow: at 1e-12 the worst Poincare difference over the three
/// cases is ~5e-12 (1e-10 still passes, at ~5e-10), leaving a wide margin below 1e-9.
const RTOL: f64 = 1e-12;
const PERIODS: usize = 200;
const AGREE: f64 = 1e-9;

/// Poincare points after 1..=n periods.
fn poincare(flow: &dyn PeriodFlow, x0: State, n: usize) -> Vec<State> {
    let mut x = x0;
    (0..n)
        .map(|_| {
            x = flow.step(x, None).unwrap();
            x
        })
        .collect()
}

/// Minimum of q over `n` periods from `x`, sampled on the pieces.
fn min_q(flow: &dyn PeriodFlow, x: State, n: usize) -> f64 {
    let mut m = f64::INFINITY;
    let mut x = x;
    for _ in 0..n {
        let mut obs = |p: &dyn Piece| {
            let (a, b) = p.span();
            for j in 0..=16 {
                m = m.min(p.eval(a + (b - a) * j as f64 / 16.0)[0]);
            }
        };
        x = flow.step(x, Some(&mut obs)).unwrap();
    }
    m
}

/// Run both flows from `x0` and check agreement, convergence to a period-one orbit, and the
/// impact regime of that orbit.
fn check(model: &GearPair, x0: State, regime: Impact) {
    let exact = ExactFlow::new(model).unwrap();
    let rk = RkFlow::new(model, RTOL).unwrap();
    let pe = poincare(&exact, x0, PERIODS);
    let pr = poincare(&rk, x0, PERIODS);
    let mut worst = (0.0f64, 0);
    for (k, (a, b)) in pe.iter().zip(&pr).enumerate() {
        let d = (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
        if d > worst.0 {
            worst = (d, k + 1);
        }
    }
    assert!(
        worst.0 <= AGREE,
        "Poincare points differ by {:e} at period {}",
        worst.0,
        worst.1
    );
    let (last, prev) = (pe[PERIODS - 1], pe[PERIODS - 2]);
    assert!(
        (last[0] - prev[0]).abs() + (last[1] - prev[1]).abs() < 1e-10,
        "not a converged period-one orbit"
    );
    for flow in [&exact as &dyn PeriodFlow, &rk] {
        let m = min_q(flow, last, 10);
        assert_eq!(
            Impact::from_range(m),
            regime,
            "{}: min q = {m}",
            flow.method()
        );
    }
}

/// Case I: heavy mean load, the teeth never separate (min q ~ 1.48).
#[test]
fn contact_only_motion() {
    let model = GearPair::paper(0.5, 0.05, 0.05, 0.5).unwrap();
    check(&model, [1.5, 0.0], Impact::None);
}

/// Case II: tooth separation without back collision (min q ~ 0.84, Omega = 0.9).
#[test]
fn single_sided_impact_motion() {
    let model = GearPair::paper(0.1, 0.05, 0.05, 0.9).unwrap();
    check(&model, [0.0, 0.0], Impact::Single);
}

/// Case III: the double-sided attractor of Fig. 2 / Fig. 14 (F_m = 0.1, F_hat = 0.5, zeta = 0.02,
/// Omega = 0.5; min q ~ -1.44), from an initial condition inside its basin.
#[test]
fn double_sided_impact_motion() {
    let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
    check(&model, [-0.8, 0.4], Impact::Double);
}

/// A small mesh-stiffness variation eps: the Runge-Kutta flow runs and its response differs
/// from eps = 0, while the exact solver refuses the model.
#[test]
fn stiffness_variation_needs_the_runge_kutta_flow() {
    let rigid = GearPair::paper(0.1, 0.05, 0.05, 0.9).unwrap();
    let mut varying = rigid.clone();
    varying.stiffness.push(Term::new(1, 0.05));
    assert!(ExactFlow::new(&varying).is_err());

    let a = poincare(&RkFlow::new(&rigid, 1e-10).unwrap(), [0.0, 0.0], 50);
    let b = poincare(&RkFlow::new(&varying, 1e-10).unwrap(), [0.0, 0.0], 50);
    let d = (a[49][0] - b[49][0]).abs().max((a[49][1] - b[49][1]).abs());
    assert!(
        d > 1e-3,
        "stiffness variation changed the state by only {d:e}"
    );
    assert!(b.iter().all(|x| x[0].is_finite() && x[1].is_finite()));
}
