//! Experiment validation (Sec. 7): synthetic stand-ins for the measured curves, the Munro (pp
//! DTE) and Kubo (dynamic factor) pipelines, and the comparison metrics.

mod curve_metrics;
mod kubo;
mod linear;
mod munro;
mod noise;
mod synth;

pub use curve_metrics::{jump_location, min_max, rms};
pub use kubo::{validate_kubo, KuboOptions, KuboValidation, CONTACT_LIMIT as KUBO_CONTACT_LIMIT};
pub use linear::{dte_gain, dte_pp_um, load_factor_max, stays_in_contact};
pub use munro::{validate_munro, LoadResult, ModelPoint, MunroOptions, MunroValidation, SteSource};
pub use noise::Rng;
pub(crate) use synth::flow_with_rtol;
pub use synth::{
    munro_rig, simulate_dte_curve, simulate_up_sweep, synth_kubo, synth_munro, HiddenEffects,
    KuboTruth, MunroTruth,
};
