//! Digital simulation of eq. 3a: exact piecewise solution, adaptive Runge-Kutta with events,
//! steady states, Poincare sections, period and chaos classification, attractors, basins, sweeps.

mod exact;
mod flow;
mod rk;
mod rk_flow;

pub use exact::ExactFlow;
pub use flow::{Observer, PeriodFlow, Piece, State};
pub use rk::{
    Crossing, DenseStep, Dop853, Dop853Options, Dop853Stats, EventFunction, FnEvent, LevelCrossing,
    OdeSystem, Outcome,
};
pub use rk_flow::{RkFlow, ATOL_PER_RTOL};
