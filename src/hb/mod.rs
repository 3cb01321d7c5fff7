//! Harmonic balance solutions of eq. 3a.
//!
//! Multi-harmonic balance with alternating frequency-time evaluation (AFT) for the full model
//! q'' + 2 zeta q' + k(t) f(q) = F(t) (design.md section 1: several STE harmonics, external
//! torque, time-varying mesh stiffness), with period-1 and subharmonic (period-nu) ansatz,
//! Newton's method with the exact Jacobian, pseudo-arclength continuation in Omega through folds,
//! and Floquet stability of every solution. This goes beyond the paper's single-harmonic
//! describing-function solution of Sec. 4 (eq. 6-19), which it converges to the simulation
//! (Sec. 3, 5) as the number of harmonics grows.

mod aft;
mod aft_floquet;
mod aft_guess;
mod aft_point;
mod aft_series;
mod aft_solve;
mod continuation;

pub use aft::AftOptions;
pub use aft_guess::{guess_from_state, linear_guess};
pub use aft_point::HbPoint;
pub use aft_solve::solve_at;
pub use continuation::{continue_branch, continue_from, ContinuationOptions};
