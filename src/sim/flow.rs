//! The stroboscopic period map that every steady-state tool is written against, so that the exact
//! piecewise solver and the adaptive Runge-Kutta integrator are interchangeable (and cross-checked).

use crate::error::Result;
use crate::model::GearPair;
use nalgebra::Matrix2;

/// A state (q, q') of eq. 3a.
pub type State = [f64; 2];

/// A piece of trajectory inside one forcing period that can be evaluated anywhere on its span.
/// Time `s` is local to the period, 0 <= s <= T, so the forcing phase at `s` is Omega s.
pub trait Piece {
    /// Local start and end time of the piece.
    fn span(&self) -> (f64, f64);
    /// State (q, q') at local time `s` inside the span.
    fn eval(&self, s: f64) -> State;
}

/// Observer of the pieces a period step produces (used to analyse kept periods).
pub type Observer<'a> = &'a mut dyn FnMut(&dyn Piece);

/// One forcing period of eq. 3a as a map of the state at phase 0 (the Poincare map).
pub trait PeriodFlow: Sync {
    /// The model being integrated.
    fn model(&self) -> &GearPair;

    /// Short name of the method, for reports ("exact", "dop853").
    fn method(&self) -> &'static str;

    /// Advance `x` by one forcing period; `observer` receives each piece of the trajectory.
    fn step(&self, x: State, observer: Option<Observer<'_>>) -> Result<State>;

    /// Advance `x` by one period and left-multiply `phi` by the period's state-transition matrix
    /// (the Jacobian of the Poincare map at `x`).
    fn step_tangent(&self, x: State, phi: &mut Matrix2<f64>) -> Result<State>;

    /// Forcing period T = 2 pi / Omega.
    fn period(&self) -> f64 {
        self.model().period()
    }
}
