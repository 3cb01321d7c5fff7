//! Digital simulation of eq. 3a: exact piecewise solution, adaptive Runge-Kutta with events,
//! steady states, Poincare sections, period and chaos classification, attractors, basins, sweeps.

mod attractors;
mod escape;
mod exact;
mod exact_bounds;
mod excitation_table;
mod extrema;
mod flow;
mod ic_grid;
mod lyapunov;
mod period;
mod rk;
mod rk_flow;
mod set_follow;
mod shooting;
mod steady;
mod sweep;
mod trajectory;
mod window_spread;

pub use attractors::{
    find_attractors, same_attractor, Attractor, AttractorMap, BasinTime, SetKind,
};
pub use escape::{
    escape_rate, EscapeBudget, EscapeRecord, SurvivalPoint, MAX_EXPOSURE, MAX_HORIZON, MIN_ESCAPES,
};
pub use exact::ExactFlow;
pub(crate) use extrema::golden_max;
pub use extrema::Extremes;
pub use flow::{Observer, PeriodFlow, Piece, State};
pub use ic_grid::{IcGrid, MAX_GRID_N};
pub use lyapunov::largest_lyapunov;
pub use period::{detect_period, eigenvalues2, monodromy, refine_orbit, PeriodicOrbit, MAX_PERIOD};
pub use rk::{
    Crossing, DenseStep, Dop853, Dop853Options, Dop853Stats, EventFunction, FnEvent, LevelCrossing,
    OdeSystem, Outcome,
};
pub use rk_flow::{RkFlow, ATOL_PER_RTOL};
pub use steady::{
    default_transient, steady_state, Motion, SteadyOptions, SteadyState, MAX_KEEP, MAX_TRANSIENT,
    SETTLED_DECAY,
};
pub use sweep::{
    carry, frequency_range, from_starts, neighbour_starts, sweep, Branch, FlowFactory, SweepPlan,
    SweepPoint,
};
pub use trajectory::{sample_trajectory, Sample};
pub use window_spread::dte_pp_over_windows;
