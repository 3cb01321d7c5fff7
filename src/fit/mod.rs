//! The estimation engine of geardyn, used by `validate munro`, `validate kubo`, `discover` and
//! the studies alike: parameters with transforms ([`Param`]), Levenberg-Marquardt least squares
//! on the `levenberg-marquardt` crate ([`least_squares`]), a noise model that is part of the
//! likelihood ([`NoiseModel`]: floor plus relative part, Gaussian or Student-t), the
//! maximum-likelihood fit of both with Fisher and sandwich covariances ([`estimate`]), and
//! profile-likelihood intervals ([`profile_interval`]).

mod estimate;
mod lm;
mod noise;
mod params;
mod profile;
mod profile_search;

pub use estimate::{
    estimate, estimate_warm, satterthwaite_dof_of, t_quantile_975, Estimate, EstimateOptions,
    NearModel, NoiseFit, NoiseSetting, NoiseSource, Robust, ROBUST_LR_CRITICAL,
};
pub use lm::{
    least_squares, least_squares_warm, rss, secant_jacobian, LmFit, NearResiduals, Stop, UNSEEN,
};
pub use noise::{
    estimate_noise, floor_at_bound, held_variance_components, log_likelihood, robust_weight,
    variance_components, Distribution, NoiseData, NoiseFreedom, NoiseModel, VarianceComponents,
};
pub use params::{Param, Transform};
pub use profile::{profile_interval, profile_interval_or_better, ProfileInterval, Profiled};
pub use profile_search::{search_side, Fitted, InnerFit, SearchOptions, SideEnd};
