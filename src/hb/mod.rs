//! Harmonic balance: the paper's describing-function solution (Sec. 4, eq. 6-19).
//!
//! - [`describing`]: g, h, N_m, N_a of eq. 7-9 (exact and truncated);
//! - [`df_solutions`] / [`df_response`]: every single-harmonic solution of eq. 5 at one frequency
//!   or over a frequency list (eq. 10, with the per-case formulas eq. 12-19 for the truncated
//!   method);
//! - [`transition_frequencies`]: eq. 14.

mod cases;
pub mod describing;
mod df_solve;
mod mean_balance;
mod roots;
mod scan;
mod transitions;

pub use describing::{g_exact, g_truncated, h_exact, h_truncated, mean_force, n_a, n_m, DfMethod};
pub use df_solve::{df_response, df_solutions, DfSolution};
pub use transitions::transition_frequencies;

#[cfg(test)]
mod tests;
