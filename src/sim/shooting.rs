//! Periodic orbits identified from a trajectory that is still approaching them (issue 23): the
//! candidate periods are the lags at which the section points nearly return, each candidate is
//! refined by Newton shooting with the exact monodromy ([`refine_orbit`], which also reduces a
//! period-2p solution that is a period-p orbit twice to the period-p orbit), and a stable orbit
//! is accepted only once the trajectory itself is captured by it.
//!
//! This is what keeps one orbit from being reported as several: near a period-8 orbit with a
//! Floquet multiplier -0.898 the deviation flips sign every 8 periods, so a repetition test with
//! one tolerance passes at lag 16 before lag 8, and a decay too slow for the kept window looks
//! aperiodic, its Lyapunov exponent the orbit's Floquet rate. Shooting from a near return does
//! not wait for the decay, and the capture test proves the orbit is the one being approached.

use super::flow::{PeriodFlow, State};
use super::period::{distance, refine_orbit, scale, PeriodicOrbit, MAX_PERIOD};
use crate::error::Result;

/// Relative distance between section points p periods apart below which p is a candidate period.
pub(crate) const SHOOT_TOL: f64 = 1e-3;
/// Relative distance to a stable orbit's section point below which a trajectory is captured,
/// provided the distance also shrinks over the next p periods. The orbit itself is Newton's, so
/// this only decides when the approach counts as proven: a basin narrower than 1e-5 of the
/// state's scale exists only within about 1e-10 of a fold in the parameter. At 1e-6 a lightly
/// damped orbit (multiplier 0.89 a period) needed 20 more periods per steady state, a fifth of
/// a continuation step. With the looser value no fit or test changed; in the escape study at
/// Fig. 4's point (441 initial conditions, exact solver) one trajectory is counted as captured
/// by the period-2 orbit before period 2,759 instead of entering the chaotic set.
pub(crate) const CAPTURE_TOL: f64 = 1e-5;
/// Most candidate periods shot from one near return (the nearest returns first).
const MAX_CANDIDATES: usize = 4;
/// A trajectory farther than this multiple of its start distance from the orbit is not
/// approaching it (transient growth of a deviation over a few periods stays well below).
const ESCAPE_FACTOR: f64 = 100.0;

/// Distance from `x` to the nearest section point of `orbit`, and that point's index.
pub(crate) fn distance_to_orbit(x: State, orbit: &[State]) -> (f64, usize) {
    orbit
        .iter()
        .enumerate()
        .map(|(i, &p)| (distance(x, p), i))
        .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
}

/// Candidate periods of the newest point of `history`: lags p <= 32 at which it returns within
/// [`SHOOT_TOL`] (relative), shortest first, at most [`MAX_CANDIDATES`].
///
/// Shortest, not nearest, first: Newton on Phi^p costs p periods an iteration, and a
/// trajectory spiralling onto a period-1 orbit (complex multipliers) often returns nearest at a
/// lag of several periods, where Newton converges to the same orbit at several times the cost
/// and [`refine_orbit`] then refines it again at period 1. A lag that is a multiple of the
/// orbit's period also returns within the tolerance (the period-8 orbit's lag 8 before its
/// lag 16), so the least period is still tried before its multiples.
fn candidate_periods(history: &[State]) -> Vec<u32> {
    let Some(&last) = history.last() else {
        return Vec::new();
    };
    let tol = SHOOT_TOL * scale(&[last]);
    let n = history.len();
    (1..=MAX_PERIOD.min(n as u32 - 1))
        .filter(|&p| distance(last, history[n - 1 - p as usize]) <= tol)
        .take(MAX_CANDIDATES)
        .collect()
}

/// A stable periodic orbit near the newest point of `history`, found by Newton shooting from it
/// at the candidate periods; `None` when no candidate converges to a stable orbit within
/// [`SHOOT_TOL`] of the point.
pub(crate) fn shoot<F: PeriodFlow + ?Sized>(
    flow: &F,
    history: &[State],
) -> Result<Option<PeriodicOrbit>> {
    let Some(&last) = history.last() else {
        return Ok(None);
    };
    let near = SHOOT_TOL * scale(&[last]);
    for p in candidate_periods(history) {
        if let Some(o) = refine_orbit(flow, last, p)? {
            if o.spectral_radius() < 1.0 && distance_to_orbit(last, &o.points).0 <= near {
                return Ok(Some(o));
            }
        }
    }
    Ok(None)
}

/// True when `x` is captured by `orbit`: within [`CAPTURE_TOL`] of one of its points and closer
/// to that point p periods later.
pub(crate) fn captured<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    orbit: &[State],
    tol: f64,
) -> Result<bool> {
    let (d, i) = distance_to_orbit(x, orbit);
    if d >= tol {
        return Ok(false);
    }
    let mut y = x;
    for _ in 0..orbit.len() {
        y = flow.step(y, None)?;
    }
    Ok(distance(y, orbit[i]) < d.max(1e-300))
}

/// Integrate from `x` until it is captured by `orbit` (see [`captured`]), for at most the
/// periods the slowest Floquet multiplier needs to shrink the start distance to the capture
/// tolerance (three times that, plus a margin), never more than `max_periods`. Returns the
/// state reached and the periods used, or `None` when the trajectory is not captured (it moves
/// away, or the budget ends first).
pub(crate) fn follow<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    orbit: &PeriodicOrbit,
    max_periods: usize,
) -> Result<Option<(State, usize)>> {
    let tol = CAPTURE_TOL * scale(&orbit.points);
    let (d0, _) = distance_to_orbit(x, &orbit.points);
    let p = orbit.period as usize;
    let rho = orbit.spectral_radius();
    // Periods for rho^(n / p) d0 to reach the capture tolerance.
    let needed = if d0 <= tol {
        0.0
    } else if rho > 0.0 {
        p as f64 * (tol / d0).ln() / rho.ln()
    } else {
        p as f64
    };
    let budget = (3.0 * needed + 8.0 * p as f64 + 64.0).min(max_periods as f64) as usize;
    let mut y = x;
    for n in 0..=budget {
        if captured(flow, y, &orbit.points, tol)? {
            return Ok(Some((y, n)));
        }
        if distance_to_orbit(y, &orbit.points).0 > ESCAPE_FACTOR * d0.max(tol) {
            return Ok(None);
        }
        y = flow.step(y, None)?;
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::GearPair;
    use crate::sim::ExactFlow;

    /// A period-2 pattern whose deviation flips sign every two points: lag 4 returns closer than
    /// lag 2, lag 3 not at all; the lags are tried shortest first.
    #[test]
    fn candidates_are_the_near_return_lags_shortest_first() {
        let a = [1.0, 0.0];
        let b = [2.0, 0.5];
        let h: Vec<State> = (0..12)
            .map(|k| {
                let e = 1e-4 * (-0.9f64).powi(k / 2);
                let base = if k % 2 == 0 { a } else { b };
                [base[0] + e, base[1]]
            })
            .collect();
        let n = h.len();
        assert!(distance(h[n - 1], h[n - 5]) < distance(h[n - 1], h[n - 3]));
        assert_eq!(candidate_periods(&h), vec![2, 4, 6, 8]);
    }

    /// A spiral onto a fixed point turning a fifth of a revolution a period (multipliers
    /// 0.95 e^(+-2 pi i / 5), a light damping) returns nearest at lag 5, yet lag 1 is tried first: Newton on the
    /// one-period map finds the same orbit at a fifth of the cost an iteration.
    #[test]
    fn a_spiral_onto_a_fixed_point_is_shot_at_period_one_first() {
        let theta = std::f64::consts::TAU / 5.0;
        let h: Vec<State> = (0..12)
            .map(|k| {
                let e = 1e-4 * 0.95f64.powi(k);
                let phase = theta * k as f64;
                [1.0 + e * phase.cos(), e * phase.sin()]
            })
            .collect();
        let n = h.len();
        let nearest = (1..n)
            .min_by(|&a, &b| {
                distance(h[n - 1], h[n - 1 - a]).total_cmp(&distance(h[n - 1], h[n - 1 - b]))
            })
            .unwrap();
        assert_eq!(nearest, 5);
        assert_eq!(candidate_periods(&h).first(), Some(&1));
    }

    /// Fig. 8(a)'s point (F_hat 0.5, zeta 0.05, Omega 1.0): the trajectory from (0, 0) is a
    /// slow approach to the period-8 orbit (issue 23 found such ICs reported as period-16 and as
    /// aperiodic). Shooting from a late point returns the least period, 8, whose multiplier is
    /// the slow one, and the trajectory is captured by it.
    #[test]
    fn slow_approach_is_shot_to_its_least_period_and_captured() {
        let m = GearPair::paper(0.1, 0.2, 0.05, 1.0).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let mut x = [0.0, 0.0];
        let mut history = Vec::new();
        let mut found = None;
        for _ in 0..3000 {
            x = f.step(x, None).unwrap();
            history.push(x);
            if history.len() > 96 {
                history.remove(0);
            }
            if let Some(o) = shoot(&f, &history).unwrap() {
                found = Some(o);
                break;
            }
        }
        let o = found.expect("an orbit within 3000 periods");
        assert!(o.period <= 8 && 8 % o.period == 0, "period {}", o.period);
        assert!(o.spectral_radius() < 1.0);
        let (_, n) = follow(&f, x, &o, 20_000).unwrap().expect("captured");
        assert!(n <= 20_000);
    }
}
