//! Simulated test runs: a speed sweep at one load, the state carried from one speed to the next
//! as on a rig (or each speed started near a sweep already made), giving the full steady state
//! at each speed (pp DTE, period, impacts, D_L).

use super::synth::flow_with_rtol;
use crate::error::Result;
use crate::model::{Dimensional, GearPair};
use crate::progress::Progress;
use crate::sim::{
    from_starts, neighbour_starts, sweep, Branch, FlowFactory, IcGrid, State, SteadyOptions,
    SweepPlan, SweepPoint,
};

/// A simulated test run at one load: the rig's dimensional parameters, the model at that load,
/// its natural frequency, the pinion speeds (rpm) and what each steady state computes.
pub struct TestRun<'a> {
    pub dim: &'a Dimensional,
    pub model: &'a GearPair,
    pub omega_n_hz: f64,
    pub speeds: &'a [f64],
    pub opts: &'a SteadyOptions,
}

impl TestRun<'_> {
    /// Up-sweep (speed increasing, as a test run), started at rest in contact under the mean
    /// load. `rk_rtol` is the DOP853 tolerance used when k(t) varies (the exact solver
    /// otherwise).
    pub fn up_sweep(&self, rk_rtol: f64, progress: &dyn Progress) -> Result<Vec<SweepPoint>> {
        self.sweep(Branch::Up, rk_rtol, progress)
    }

    /// [`TestRun::up_sweep`] on either branch: speed increasing (`Branch::Up`) or decreasing
    /// (`Branch::Down`), started at rest in contact under the mean load at its first speed.
    pub fn sweep(
        &self,
        branch: Branch,
        rk_rtol: f64,
        progress: &dyn Progress,
    ) -> Result<Vec<SweepPoint>> {
        self.sweep_from(branch, rk_rtol, up_sweep_start(self.model), progress)
    }

    /// [`TestRun::sweep`] carried on from state `x0` at its first speed (the section point a
    /// sweep brought from a lower speed, e.g. [`up_sweep_neighbour_starts`] of a period-1 point,
    /// for a part of a sweep refined between two of its speeds).
    pub fn sweep_from(
        &self,
        branch: Branch,
        rk_rtol: f64,
        x0: State,
        progress: &dyn Progress,
    ) -> Result<Vec<SweepPoint>> {
        let flow = |m: &GearPair| flow_with_rtol(m, rk_rtol);
        self.carried(branch, &flow, x0, progress)
    }

    /// [`TestRun::up_sweep`] at parameters near those whose sweep gave `starts`
    /// ([`up_sweep_neighbour_starts`]): each speed from its start, in parallel. Periodic points
    /// give the up-sweep's orbits (to the Newton tolerance) after a few periods instead of a
    /// transient from the speed before.
    pub fn near_up_sweep(&self, rk_rtol: f64, starts: &[State]) -> Result<Vec<SweepPoint>> {
        let models = self
            .speeds
            .iter()
            .map(|&s| self.model.at_omega(self.dim.omega(s, self.omega_n_hz)))
            .collect::<Result<Vec<_>>>()?;
        let flow = |m: &GearPair| flow_with_rtol(m, rk_rtol);
        let states = from_starts(&flow, &models, starts, self.opts)?;
        Ok(models
            .iter()
            .zip(states)
            .map(|(m, steady)| SweepPoint {
                omega: m.omega,
                branch: Branch::Up,
                steady,
                basin_fraction: None,
                kind: None,
                escape_rate: None,
            })
            .collect())
    }

    /// The sweep of `branch` from `x0` with the period map of `factory`, the state carried from
    /// one speed to the next.
    pub(crate) fn carried(
        &self,
        branch: Branch,
        factory: FlowFactory<'_>,
        x0: State,
        progress: &dyn Progress,
    ) -> Result<Vec<SweepPoint>> {
        let plan = SweepPlan {
            omegas: self
                .speeds
                .iter()
                .map(|&s| self.dim.omega(s, self.omega_n_hz))
                .collect(),
            branch,
            x0,
            grid: IcGrid::new(-2.0, 2.0, 1)?,
            opts: self.opts.clone(),
        };
        sweep(factory, self.model, &plan, progress)
    }
}

/// Where a sweep at parameters near those of `pts` (a [`TestRun::up_sweep`] of `model`) starts
/// each speed ([`crate::sim::neighbour_starts`]).
pub fn up_sweep_neighbour_starts(model: &GearPair, pts: &[SweepPoint]) -> Vec<State> {
    neighbour_starts(pts.iter().map(|p| &p.steady), up_sweep_start(model))
}

/// First state of a sweep of `model` (either branch): at rest in contact under the mean load.
pub(crate) fn up_sweep_start(model: &GearPair) -> State {
    [1.0 + model.mean_force, 0.0]
}
