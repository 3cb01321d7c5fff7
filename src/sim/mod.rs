//! Digital simulation of eq. 3a: exact piecewise solution, adaptive Runge-Kutta with events,
//! steady states, Poincare sections, period and chaos classification, attractors, basins, sweeps.

mod exact;
mod flow;

pub use exact::ExactFlow;
pub use flow::{Observer, PeriodFlow, Piece, State};
