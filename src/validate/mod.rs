//! Experiment validation (Sec. 7): synthetic stand-ins for the measured curves, the Munro (pp
//! DTE) and Kubo (dynamic factor) pipelines, and the comparison metrics.

mod curve_metrics;
mod design_fit;
mod fit_check;
mod geometry_ste;
mod kubo;
mod kubo_midline;
mod kubo_swept;
mod linear;
mod munro;
mod study;
mod synth;
mod test_run;

pub use curve_metrics::{jump_location, rms, transition_location};
pub use design_fit::{
    fit_design_load, CorrelationChoice, DesignLoadFit, DesignModel, ErrorChoice, MunroNoise,
    StatedSte, LOW_SPEED_OMEGA,
};
pub use fit_check::{fit_failure, FITTED_ZETA};
pub use geometry_ste::{
    geometry_model, GearMesh, GeometryExcitation, GeometryFit, GeometryModel,
    GeometryOperatingPoint, GeometryOptions, ReliefRule, StiffnessChoice,
};
pub use kubo::{
    validate_kubo, KuboFitPath, KuboOptions, KuboValidation, CONTACT_LIMIT as KUBO_CONTACT_LIMIT,
};
pub use kubo_midline::{spread_interval, PAIR_SPREAD};
pub use linear::{
    dte_gain, dte_pp_um, dte_pp_um_harmonics, load_factor_max, stays_in_contact,
    stays_in_contact_harmonics,
};
pub(crate) use munro::{check_design_levels, require_ste_uncertainty};
pub use munro::{
    fit_munro_design_load, noise_setting, validate_munro, GeometryValidation, LoadResult,
    ModelPoint, MunroOptions, MunroValidation, SteMode, SteSource, MIN_DESIGN_POINTS,
};
pub use study::{
    run_validate_study, Covered, ParameterCoverage, SpeedGrid, ValidateSeed, ValidateStudyOptions,
    ValidateStudySummary,
};
pub(crate) use synth::flow_with_rtol;
pub use synth::{
    clean_munro_curves, simulate_dte_curve, synth_kubo, synth_munro, write_munro_set, CleanCurves,
    HiddenEffects, KuboTruth, MunroTruth, NoiseFamily, SynthNoise, FAMILY_QUANTUM_UM,
    FAMILY_RELATIVE, FAMILY_T_DOF,
};
pub use test_run::{up_sweep_neighbour_starts, TestRun};
