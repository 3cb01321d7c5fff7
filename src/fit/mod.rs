//! The estimation engine of geardyn, used by `validate munro`, `validate kubo`, `discover` and
//! the studies alike: parameters with transforms ([`Param`]), Levenberg-Marquardt least squares
//! on the `levenberg-marquardt` crate ([`least_squares`]), a noise model that is part of the
//! likelihood ([`NoiseModel`]: floor plus relative part, Gaussian or Student-t), the
//! maximum-likelihood fit of both with Fisher and sandwich covariances ([`estimate`]), errors
//! correlated along speed within a curve ([`Axis`], [`CorrelationSetting`];
//! docs/correlated-errors.md), and profile-likelihood intervals ([`profile_interval`]).

mod correlation;
mod estimate;
mod lm;
mod noise;
mod params;
mod profile;
mod profile_search;
mod whitener;

pub use correlation::{curve_correlations, ljung_box, Axis, Correlation, CurveCorrelation};
pub use estimate::{
    estimate, estimate_warm, satterthwaite_dof_of, t_quantile_975, CorrelationFit,
    CorrelationSetting, CorrelationSource, Estimate, EstimateOptions, Measurement, MeasurementFit,
    NearModel, NoiseFit, NoiseSetting, NoiseSource, Robust, CORRELATION_LR_CRITICAL,
    ROBUST_LR_CRITICAL,
};
pub use lm::{
    least_squares, least_squares_warm, rss, secant_jacobian, LmFit, NearResiduals, Stop, UNSEEN,
};
pub use noise::{
    estimate_length, estimate_noise, estimate_noise_and_length, estimate_noise_near,
    floor_at_bound, held_variance_components, length_interval, log_likelihood, neg_log_likelihood,
    restricted_term, robust_weight, variance_components, Distribution, NoiseData, NoiseFreedom,
    NoiseModel, VarianceComponents,
};
pub use params::{Param, Transform};
pub use profile::{profile_interval, profile_interval_or_better, ProfileInterval, Profiled};
pub use profile_search::{search_side, Fitted, InnerFit, SearchOptions, SideEnd};
pub use whitener::Whitener;
