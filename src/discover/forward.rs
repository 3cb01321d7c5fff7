//! The forward model of the discovery fits: the pp DTE curve of M0 or M0 + effect at each
//! measured speed of a load, as Munro measured it (speed increasing, state carried), by the
//! exact event-to-event solver (k = 1) or DOP853 (k(t) varying). Jumps and separation come out
//! as in the data, which a harmonic-balance forward model would have to re-create by branch
//! tracking.

use super::effects::Effect;
use crate::data::MunroData;
use crate::error::{GearError, Result};
use crate::model::Dimensional;
use crate::progress::NoProgress;
use crate::validate::simulate_up_sweep;
use rayon::prelude::*;

/// DOP853 tolerance when k(t) varies: pp DTE agrees with rtol 1e-9 to ~1e-5 um on periodic
/// orbits, at about half the cost.
const RK_RTOL: f64 = 1e-7;

/// Smallest damping ratio a discovery fit may use.
pub const MIN_ZETA: f64 = 0.003;

/// One measured curve.
#[derive(Clone, Debug)]
pub struct Curve {
    pub load_n: f64,
    pub speeds_rpm: Vec<f64>,
    pub dte_pp_um: Vec<f64>,
}

/// The measured data and the rig's stated scales (nothing from `[source.truth]`).
#[derive(Clone, Debug)]
pub struct Setup {
    pub dim: Dimensional,
    pub design_load_n: f64,
    /// Curves by descending load.
    pub curves: Vec<Curve>,
}

impl Setup {
    /// From a loaded Munro-style set: at least 8 points per load on increasing speeds.
    pub fn from_munro(data: &MunroData) -> Result<Self> {
        let dim = Dimensional::from_rig(&data.rig.rig)?;
        let mut curves = Vec::new();
        for load in data.loads() {
            let c = data.curve(load);
            if c.len() < 8 {
                return Err(GearError::Data {
                    file: data.dir.join("rig.toml"),
                    line: 0,
                    field: "load_n".into(),
                    message: format!(
                        "discovery needs at least 8 speeds per load; load {load} N has {}",
                        c.len()
                    ),
                });
            }
            curves.push(Curve {
                load_n: load,
                speeds_rpm: c.iter().map(|p| p.speed_rpm).collect(),
                dte_pp_um: c.iter().map(|p| p.dte_pp_um).collect(),
            });
        }
        Ok(Setup {
            dim,
            design_load_n: data.rig.rig.design_load_n,
            curves,
        })
    }
}

/// Model curve at one load.
#[derive(Clone, Debug)]
pub struct CurvePrediction {
    pub dte_pp_um: Vec<f64>,
    /// Period-1 steady state (else chaotic, subharmonic or aperiodic: not comparable point-wise).
    pub period1: Vec<bool>,
    /// The teeth separate somewhere in the period (q_min < 1).
    pub separated: Vec<bool>,
    /// The back flanks touch somewhere in the period (q_min < -1, double-sided impacts).
    pub back_contact: Vec<bool>,
}

/// Parameters shared by all loads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Globals {
    pub zeta: f64,
    pub omega_n_hz: f64,
}

/// Predicted curve of `setup.curves[i]` with STE amplitude `ste_um` (um, first harmonic).
pub fn predict(
    setup: &Setup,
    i: usize,
    g: Globals,
    ste_um: f64,
    effect: &Effect,
) -> Result<CurvePrediction> {
    let c = &setup.curves[i];
    let dim = effect.dimensional(&setup.dim);
    let model = effect.model(
        g.zeta,
        dim.mean_force(c.load_n),
        dim.ste_amplitude(ste_um.abs()),
        c.load_n / setup.design_load_n,
        dim.mean_force(setup.design_load_n),
    )?;
    // Below 0.3% damping the steady state needs tens of thousands of periods and no gear mesh
    // is that lightly damped: a fit that wanders there is stopped (the step is rejected).
    if g.zeta < MIN_ZETA {
        return Err(GearError::param(
            "zeta",
            g.zeta,
            "discovery fits keep zeta >= 0.003",
        ));
    }
    if !(g.omega_n_hz.is_finite() && g.omega_n_hz > 0.0) {
        return Err(GearError::param(
            "omega_n_hz",
            g.omega_n_hz,
            "natural frequency must be positive",
        ));
    }
    let pts = simulate_up_sweep(
        &dim,
        &model,
        g.omega_n_hz,
        &c.speeds_rpm,
        RK_RTOL,
        &NoProgress,
    )?;
    Ok(CurvePrediction {
        dte_pp_um: pts.iter().map(|p| dim.dte_um(p.steady.dte_pp)).collect(),
        period1: pts.iter().map(|p| p.steady.period == Some(1)).collect(),
        separated: pts.iter().map(|p| p.steady.q_min < 1.0).collect(),
        back_contact: pts.iter().map(|p| p.steady.q_min < -1.0).collect(),
    })
}

/// Predictions of several curves in parallel, each with its STE amplitude.
pub fn predict_many(
    setup: &Setup,
    idx: &[usize],
    g: Globals,
    ste_um: &[f64],
    effect: &Effect,
) -> Result<Vec<CurvePrediction>> {
    idx.par_iter()
        .zip(ste_um.par_iter())
        .map(|(&i, &e)| predict(setup, i, g, e, effect))
        .collect()
}
