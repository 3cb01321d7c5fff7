//! Nonlinear least squares for the validation pipelines: multi-start Nelder-Mead (argmin) on the
//! sum of squared residuals in log-parameter space, covariance from the Jacobian at the optimum,
//! and profile-likelihood intervals.

mod least_squares;
mod profile;

pub use least_squares::{fit, FitOptions, FitResult, Residuals};
pub use profile::profile_interval;
