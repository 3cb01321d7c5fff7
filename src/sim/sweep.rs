//! Frequency sweeps (Sec. 5): up or down carrying the last steady state to the next frequency
//! (the procedure behind Fig. 13, which finds one branch only), or every attractor at each
//! frequency from a grid of initial conditions.

use super::attractors::{find_attractors, Attractor, SetKind};
use super::flow::{PeriodFlow, State};
use super::ic_grid::IcGrid;
use super::steady::{steady_state, SteadyOptions, SteadyState};
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::numeric::to_significant;
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// How the initial condition at each frequency is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Branch {
    /// Increasing Omega, each start from the previous steady state.
    Up,
    /// Decreasing Omega, each start from the previous steady state.
    Down,
    /// Every attractor found from the grid of initial conditions.
    All,
}

impl Branch {
    /// Name used in CSV output.
    pub fn name(self) -> &'static str {
        match self {
            Branch::Up => "up",
            Branch::Down => "down",
            Branch::All => "all",
        }
    }
}

/// One steady state of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    /// Excitation frequency.
    pub omega: f64,
    /// How it was found.
    pub branch: Branch,
    /// The steady state.
    pub steady: SteadyState,
    /// Share of the initial-condition grid reaching it (all-attractor sweeps only).
    pub basin_fraction: Option<f64>,
    /// Attractor or transient set (all-attractor sweeps only).
    pub kind: Option<SetKind>,
    /// Escape rate per forcing period of a followed non-periodic set that trajectories left.
    pub escape_rate: Option<f64>,
}

impl SweepPoint {
    /// A point of an all-attractor search at `omega`.
    pub fn from_attractor(omega: f64, a: Attractor) -> Self {
        SweepPoint {
            omega,
            branch: Branch::All,
            escape_rate: a.escape.as_ref().filter(|r| r.escapes > 0).map(|r| r.rate),
            kind: Some(a.kind),
            steady: a.steady,
            basin_fraction: Some(a.basin_fraction),
        }
    }
}

/// Builds the period map for the model at one frequency (exact or Runge-Kutta).
pub type FlowFactory<'a> = &'a (dyn Fn(&GearPair) -> Result<Box<dyn PeriodFlow>> + Sync);

/// Frequencies START, START+STEP, ..., up to STOP (inclusive within rounding).
pub fn frequency_range(start: f64, stop: f64, step: f64) -> Result<Vec<f64>> {
    if !(start.is_finite() && start > 0.0) {
        return Err(GearError::param(
            "omega",
            start,
            "start frequency must be finite and > 0",
        ));
    }
    if !(stop.is_finite() && stop >= start) {
        return Err(GearError::param(
            "omega",
            stop,
            "stop frequency must be finite and >= start",
        ));
    }
    if !(step.is_finite() && step > 0.0) {
        return Err(GearError::param(
            "omega",
            step,
            "frequency step must be finite and > 0",
        ));
    }
    let n = ((stop - start) / step + 1e-9).floor() as usize + 1;
    if n > 100_000 {
        return Err(GearError::param(
            "omega",
            n as f64,
            "at most 100000 frequencies per sweep",
        ));
    }
    Ok((0..n)
        .map(|i| to_significant(start + i as f64 * step, GRID_DIGITS))
        .collect())
}

/// Significant digits of the values of [`frequency_range`]: the grid is made by index (no
/// accumulated steps) and rounded to 12 digits, so that 0.2 + 10 x 0.1 is the 1.2 that the user
/// asked for, not 1.2000000000000002 (the change, below 1e-12 relative, is far below any
/// tolerance of the solvers).
const GRID_DIGITS: usize = 12;

/// What a sweep covers and how each frequency is started.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    /// Frequencies in increasing order.
    pub omegas: Vec<f64>,
    /// Carried up, carried down, or every attractor.
    pub branch: Branch,
    /// Initial state of a carried sweep at its first frequency.
    pub x0: State,
    /// Initial conditions searched at each frequency by an all-attractor sweep.
    pub grid: IcGrid,
    /// Steady-state options.
    pub opts: SteadyOptions,
}

/// Steady states of `models` in order, each integrated from the first section point of the
/// previous one's steady state (the first from `x0`): the procedure behind Fig. 13, which follows
/// one branch and misses the states it does not lead to.
pub fn carry(
    factory: FlowFactory<'_>,
    models: &[GearPair],
    x0: State,
    opts: &SteadyOptions,
    progress: &dyn Progress,
) -> Result<Vec<SteadyState>> {
    progress.start(models.len() as u64, "carried steady states");
    let mut x = x0;
    let mut out = Vec::with_capacity(models.len());
    for m in models {
        let flow = factory(m)?;
        let steady = steady_state(flow.as_ref(), x, opts)?;
        x = carried_past(x, &steady);
        out.push(steady);
        progress.advance(1);
    }
    progress.finish();
    Ok(out)
}

/// Where a sweep at parameters near those of `states` (a carried sweep from `x0`) starts each
/// frequency: a periodic point on its own orbit, which the nearby orbit continues; any other
/// from the state the carried sweep brought to it. [`from_starts`] then reproduces a carried
/// sweep of the nearby parameters on the same branch without its transients.
pub fn neighbour_starts<'a>(
    states: impl IntoIterator<Item = &'a SteadyState>,
    x0: State,
) -> Vec<State> {
    let mut carried = x0;
    states
        .into_iter()
        .map(|s| {
            let start = match (s.period, s.poincare.first()) {
                (Some(_), Some(p)) => *p,
                _ => carried,
            };
            carried = carried_past(carried, s);
            start
        })
        .collect()
}

/// The state a carried sweep takes to the next frequency after `steady`, which it reached
/// from `x`: the first section point of that steady state (`x` when it has none).
fn carried_past(x: State, steady: &SteadyState) -> State {
    steady.poincare.first().copied().unwrap_or(x)
}

/// Steady states of `models`, each from its own start (see [`neighbour_starts`]), in parallel.
pub fn from_starts(
    factory: FlowFactory<'_>,
    models: &[GearPair],
    starts: &[State],
    opts: &SteadyOptions,
) -> Result<Vec<SteadyState>> {
    if models.len() != starts.len() {
        return Err(GearError::Numerical(format!(
            "{} models and {} starts",
            models.len(),
            starts.len()
        )));
    }
    models
        .par_iter()
        .zip(starts)
        .map(|(m, &x)| steady_state(factory(m)?.as_ref(), x, opts))
        .collect()
}

/// Sweep `model` over the plan's frequencies along its branch.
pub fn sweep(
    factory: FlowFactory<'_>,
    model: &GearPair,
    plan: &SweepPlan,
    progress: &dyn Progress,
) -> Result<Vec<SweepPoint>> {
    let mut out = Vec::new();
    match plan.branch {
        Branch::Up | Branch::Down => {
            let mut ordered = plan.omegas.clone();
            if plan.branch == Branch::Down {
                ordered.reverse();
            }
            let models = ordered
                .iter()
                .map(|&om| model.at_omega(om))
                .collect::<Result<Vec<_>>>()?;
            let states = carry(factory, &models, plan.x0, &plan.opts, progress)?;
            out.extend(
                ordered
                    .into_iter()
                    .zip(states)
                    .map(|(om, steady)| SweepPoint {
                        omega: om,
                        branch: plan.branch,
                        steady,
                        basin_fraction: None,
                        kind: None,
                        escape_rate: None,
                    }),
            );
        }
        Branch::All => {
            for &om in &plan.omegas {
                let flow = factory(&model.at_omega(om)?)?;
                let map = find_attractors(flow.as_ref(), &plan.grid, &plan.opts, progress)?;
                out.extend(
                    map.attractors
                        .into_iter()
                        .map(|a| SweepPoint::from_attractor(om, a)),
                );
            }
        }
    }
    out.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep started from a carried sweep's neighbour starts, at a damping 1e-4 away, gives
    /// the carried sweep of that damping at every periodic point to the orbit's Newton
    /// tolerance (the paper's F_m 0.1, F_ah 0.02, zeta 0.05 over Omega 0.5-1.5: in contact,
    /// separation and the jump), with fewer periods integrated.
    #[test]
    fn neighbour_starts_reproduce_a_nearby_carried_sweep() {
        use crate::sim::ExactFlow;
        let factory =
            |m: &GearPair| -> Result<Box<dyn PeriodFlow>> { Ok(Box::new(ExactFlow::new(m)?)) };
        let base = GearPair::paper(0.1, 0.02, 0.05, 0.5).unwrap();
        let mut near = base.clone();
        near.zeta *= 1.0 + 1e-4;
        let omegas = frequency_range(0.5, 1.5, 0.02).unwrap();
        let at = |m: &GearPair| -> Vec<GearPair> {
            omegas.iter().map(|&om| m.at_omega(om).unwrap()).collect()
        };
        let opts = SteadyOptions::default();
        let x0 = [1.1, 0.0];
        let noop = crate::progress::NoProgress;
        let carried = carry(&factory, &at(&base), x0, &opts, &noop).unwrap();
        let fresh = carry(&factory, &at(&near), x0, &opts, &noop).unwrap();
        let starts = neighbour_starts(&carried, x0);
        let warm = from_starts(&factory, &at(&near), &starts, &opts).unwrap();
        let mut compared = 0;
        for (f, w) in fresh.iter().zip(&warm) {
            if f.period.is_some() {
                assert_eq!(f.period, w.period);
                assert!((f.dte_pp - w.dte_pp).abs() <= 1e-9 * f.dte_pp.abs().max(1.0));
                compared += 1;
            }
        }
        assert!(compared > 40, "{compared} periodic points");
        let separated = fresh.iter().filter(|s| s.q_min < 1.0).count();
        assert!(
            separated > 3 && separated < fresh.len() - 3,
            "{separated} separated"
        );
        let periods = |v: &[SteadyState]| v.iter().map(|s| s.transient_periods).sum::<usize>();
        assert!(
            2 * periods(&warm) < periods(&fresh),
            "{} vs {}",
            periods(&warm),
            periods(&fresh)
        );
        assert!(from_starts(&factory, &at(&near), &starts[1..], &opts).is_err());
    }

    #[test]
    fn range_is_inclusive_and_validated() {
        let r = frequency_range(0.3, 1.5, 0.1).unwrap();
        assert_eq!(r.len(), 13);
        assert!((r[12] - 1.5).abs() < 1e-12);
        assert!(frequency_range(0.0, 1.0, 0.1).is_err());
        assert!(frequency_range(1.0, 0.5, 0.1).is_err());
        assert!(frequency_range(0.5, 1.0, 0.0).is_err());
        assert!(frequency_range(0.5, 1.0, f64::NAN).is_err());
    }

    /// The grid values print as typed: 0.1 + 11 x 0.1 evaluates to 1.2000000000000002 in
    /// binary floating point, and 1000 + 80 x 50 rpm stays an integer.
    #[test]
    fn grid_values_are_the_decimal_ones() {
        assert_ne!(0.1 + 11.0 * 0.1, 1.2);
        let r = frequency_range(0.1, 1.6, 0.1).unwrap();
        assert_eq!(r.len(), 16);
        assert_eq!(r[11], 1.2);
        assert_eq!(format!("{}", r[11]), "1.2");
        assert_eq!(format!("{}", r[15]), "1.6");
        let rpm = frequency_range(1000.0, 5000.0, 50.0).unwrap();
        assert_eq!((rpm.len(), rpm[80]), (81, 5000.0));
    }
}
