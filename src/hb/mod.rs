//! Harmonic balance solutions of eq. 3a.
//!
//! - The paper's describing-function solution (Sec. 4, eq. 6-19): [`describing`] (g, h, N_m, N_a
//!   of eq. 7-9, exact and truncated), [`df_solutions`] / [`df_response`] (every single-harmonic
//!   solution of eq. 5 at one frequency or over a list, eq. 10 with the per-case formulas eq.
//!   12-19 for the truncated method) and [`transition_frequencies`] (eq. 14).
//! - Multi-harmonic balance with alternating frequency-time evaluation (AFT) for the full model
//!   q'' + 2 zeta q' + k(t) f(q) = F(t) (several STE harmonics, external torque, time-varying mesh
//!   stiffness), period-1 and subharmonic ansatz, Newton with the exact Jacobian,
//!   pseudo-arclength continuation through folds, and Floquet stability of every point.

mod aft;
mod aft_floquet;
mod aft_guess;
mod aft_point;
mod aft_series;
mod aft_solve;
mod cases;
mod continuation;
pub mod describing;
mod df_solve;
mod mean_balance;
mod resample;
mod response_ranges;
mod scan;
mod subharmonic;
mod transitions;

pub use aft::{AftOptions, MAX_HARMONICS};
pub use aft_guess::{guess_from_state, linear_guess};
pub use aft_point::HbPoint;
pub use aft_solve::solve_at;
pub use continuation::{continue_branch, continue_from, ContinuationOptions};
pub use describing::{g_exact, g_truncated, h_exact, h_truncated, mean_force, n_a, n_m, DfMethod};
pub use df_solve::{df_response, df_response_forced, df_solutions, DfForcing, DfSolution};
pub use resample::{branch_at, branch_from_start, branches_covering};
pub use response_ranges::{response_ranges, ResponseRanges};
pub use subharmonic::{subharmonic_branch, SeededBranch};
pub use transitions::{
    forced_transition_frequencies, linear_peak, transition_frequencies, LinearPeak,
};

#[cfg(test)]
mod tests;
