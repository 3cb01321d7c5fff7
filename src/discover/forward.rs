//! The forward model of the discovery fits: the pp DTE curve of M0 or M0 + effect at each
//! measured speed of a load, as Munro measured it (speed increasing, state carried), by the exact
//! event-to-event solver (k = 1) or DOP853 (k(t) varying): jumps and separation come out as in
//! the data, which a harmonic-balance model would have to re-create by branch tracking.

use super::effects::Effect;
use super::memo::PredictionMemo;
use crate::data::MunroData;
use crate::error::{GearError, Result};
use crate::model::{Dimensional, GearPair};
use crate::numeric::min_max;
use crate::progress::NoProgress;
use crate::sim::{dte_pp_over_windows, Branch, State, SteadyOptions};
use crate::validate::{
    check_design_levels, flow_with_rtol, noise_setting, require_ste_uncertainty,
    up_sweep_neighbour_starts, MunroNoise, TestRun,
};
use rayon::prelude::*;

/// DOP853 tolerance when k(t) varies: pp DTE agrees with rtol 1e-9 to ~1e-5 um on periodic
/// orbits, at about half the cost.
const RK_RTOL: f64 = 1e-7;

/// Observation windows over which [`aperiodic_pp_range`] samples the pp of a non-periodic steady
/// state, of which a measured chaotic pp is one draw: the largest of n exceeds a fresh window's
/// with probability n / (n + 1); 32 cost about what a Lyapunov exponent does (2000 periods).
const SPREAD_WINDOWS: usize = 32;

/// Smallest damping ratio a discovery fit may use.
pub const MIN_ZETA: f64 = 0.003;

/// A fit's damping at every curve it fits, after a damping law, is at least [`MIN_ZETA`]
/// ([`above_floor`]; a law can take one load far below the others), else the step is rejected.
/// A held-out load's prediction is bound alike: a law that takes it below does not predict it.
pub fn fitted_damping_admissible(
    setup: &Setup,
    idx: &[usize],
    g: Globals,
    effect: &Effect,
) -> Result<()> {
    for &i in idx {
        above_floor(effect.zeta_at(g.zeta, setup.curves[i].load_n / setup.design_load_n))?;
    }
    Ok(())
}

/// Below 0.3% damping the steady state needs tens of thousands of periods and no gear mesh
/// is that lightly damped: a fit that wanders there is stopped (the step is rejected).
fn above_floor(zeta: f64) -> Result<()> {
    if zeta.is_nan() || zeta < MIN_ZETA {
        return Err(GearError::param(
            "zeta",
            zeta,
            "discovery fits keep zeta >= 0.003 (at every fitted load, after a damping law)",
        ));
    }
    Ok(())
}

/// One measured curve.
#[derive(Clone, Debug)]
pub struct Curve {
    pub load_n: f64,
    pub speeds_rpm: Vec<f64>,
    pub dte_pp_um: Vec<f64>,
    /// Stated standard deviation of each point (um), when the set has a `dte_pp_sd_um` column.
    pub sd_um: Option<Vec<f64>>,
    /// The load's STE amplitude and its standard uncertainty (um), where rig.toml `[ste]`
    /// states both: every fit weighs it as a measurement of that load's STE.
    pub stated_ste: Option<(f64, f64)>,
}

/// The measured data and the rig's stated scales (nothing from `[source.truth]`), with the
/// curves predicted from them so far.
#[derive(Clone, Debug)]
pub struct Setup {
    pub dim: Dimensional,
    pub design_load_n: f64,
    /// Curves by descending load.
    pub curves: Vec<Curve>,
    /// What the set states of its noise (the rule `validate munro` uses).
    pub noise: MunroNoise,
    /// [`predict`]'s curves by their inputs (a clone starts empty).
    predictions: PredictionMemo,
}

impl Setup {
    /// A set of `curves` (by descending load) on a rig with scales `dim`.
    pub fn new(
        dim: Dimensional,
        design_load_n: f64,
        curves: Vec<Curve>,
        noise: MunroNoise,
    ) -> Self {
        Setup {
            dim,
            design_load_n,
            curves,
            noise,
            predictions: PredictionMemo::new(),
        }
    }

    /// From a loaded Munro-style set: at least 8 points per load on increasing speeds, the
    /// design-load curve neither flat nor in another unit (as `validate munro` requires).
    pub fn from_munro(data: &MunroData) -> Result<Self> {
        let dim = data.rig.rig.dimensional()?;
        let design = data.rig.rig.design_load_n;
        check_design_levels(design, &data.curve(design))?;
        require_ste_uncertainty(data)?;
        let mut curves = Vec::new();
        for load in data.loads() {
            let c = data.curve(load);
            if c.len() < 8 {
                let (file, line) = c
                    .first()
                    .map_or((data.dir.join("rig.toml"), 0), |p| (p.file.clone(), p.line));
                return Err(GearError::Data {
                    file,
                    line,
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
                sd_um: c.iter().map(|p| p.sd_um).collect(),
                stated_ste: data
                    .rig
                    .ste
                    .as_ref()
                    .and_then(|t| Some((t.amplitude_at(load)?, t.sd_at(load)?))),
            });
        }
        Ok(Setup::new(dim, design, curves, noise_setting(data)?))
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
    /// Phase-0 section state from which [`aperiodic_pp_range`] samples observation windows at
    /// the points that are not period-1 ([`window_starts`]).
    pub aperiodic_start: Vec<Option<State>>,
    /// Where a prediction at nearby parameters starts each speed ([`simulate`]).
    pub neighbour_starts: Vec<State>,
    /// The model the curve was simulated with, for [`jumps_between`] (`None`: unknown).
    pub sweep_model: Option<SweepModel>,
}

/// The model of a predicted curve: its dimensional scales, its equation of motion and its
/// natural frequency, which set the speed-to-Omega map.
#[derive(Clone, Debug)]
pub struct SweepModel {
    dim: Dimensional,
    model: GearPair,
    omega_n_hz: f64,
}

/// Parameters shared by all loads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Globals {
    pub zeta: f64,
    pub omega_n_hz: f64,
}

/// The dimensional scales and the model of `setup.curves[i]` with STE amplitude `ste_um` (um,
/// first harmonic), M0 or M0 + `effect`, at Omega = 1 (the sweep sets Omega).
fn curve_model(
    setup: &Setup,
    i: usize,
    g: Globals,
    ste_um: f64,
    effect: &Effect,
) -> Result<(Dimensional, GearPair)> {
    let c = &setup.curves[i];
    let dim = effect.dimensional(&setup.dim)?;
    let model = effect.model(
        g.zeta,
        dim.mean_force(c.load_n),
        dim.ste_amplitude(ste_um.abs()),
        c.load_n / setup.design_load_n,
        dim.mean_force(setup.design_load_n),
    )?;
    above_floor(g.zeta)?;
    if !(g.omega_n_hz.is_finite() && g.omega_n_hz > 0.0) {
        return Err(GearError::param(
            "omega_n_hz",
            g.omega_n_hz,
            "natural frequency must be positive",
        ));
    }
    Ok((dim, model))
}

/// What a prediction's steady states compute: no Lyapunov exponent of non-periodic motion (2000
/// periods a point, a large share of a run), which a prediction never reads; a non-periodic
/// point's range over windows is simulated on its own ([`aperiodic_pp_range`]).
fn fit_steady_options() -> SteadyOptions {
    SteadyOptions {
        classify_aperiodic: false,
        ..SteadyOptions::default()
    }
}

/// Predicted curve of `setup.curves[i]` with STE amplitude `ste_um` (um, first harmonic); a
/// curve predicted before at the same inputs comes from the set's memo.
pub fn predict(
    setup: &Setup,
    i: usize,
    g: Globals,
    ste_um: f64,
    effect: &Effect,
) -> Result<CurvePrediction> {
    setup.predictions.get_or_predict(
        &setup.curves[i],
        setup.design_load_n,
        g,
        ste_um,
        effect,
        || simulate(setup, i, g, ste_um, effect, None),
    )
}

/// [`predict`] simulated, not from the memo. With `base` (a [`predict`] of the same curve a
/// finite-difference step away), each speed starts from its [`CurvePrediction::neighbour_starts`],
/// continuing base's branch, and periodic orbits skip their transients (a Jacobian's columns, four
/// times cheaper): equal to [`predict`] at period-1 points to the orbit's Newton tolerance,
/// unless the step moves a jump across a speed (such points are masked).
pub fn simulate(
    setup: &Setup,
    i: usize,
    g: Globals,
    ste_um: f64,
    effect: &Effect,
    base: Option<&CurvePrediction>,
) -> Result<CurvePrediction> {
    let (dim, model) = curve_model(setup, i, g, ste_um, effect)?;
    let run = TestRun {
        dim: &dim,
        model: &model,
        omega_n_hz: g.omega_n_hz,
        speeds: &setup.curves[i].speeds_rpm,
        opts: &fit_steady_options(),
    };
    let (pts, neighbour_starts) = match base {
        None => {
            let pts = run.up_sweep(RK_RTOL, &NoProgress)?;
            let starts = up_sweep_neighbour_starts(&model, &pts);
            (pts, starts)
        }
        Some(b) => (
            run.near_up_sweep(RK_RTOL, &b.neighbour_starts)?,
            b.neighbour_starts.clone(),
        ),
    };
    Ok(CurvePrediction {
        dte_pp_um: pts.iter().map(|p| dim.dte_um(p.steady.dte_pp)).collect(),
        period1: pts.iter().map(|p| p.steady.period == Some(1)).collect(),
        separated: pts.iter().map(|p| p.steady.q_min < 1.0).collect(),
        back_contact: pts.iter().map(|p| p.steady.q_min < -1.0).collect(),
        aperiodic_start: window_starts(&pts),
        neighbour_starts,
        sweep_model: Some(SweepModel {
            dim,
            model,
            omega_n_hz: g.omega_n_hz,
        }),
    })
}

/// Speeds an interval is cut into at each level of [`jumps_between`].
const REFINE_STEPS: usize = 8;

/// Narrowest interval [`jumps_between`] refines, relative to its speed: 0.1%, about the
/// standard error of omega_n in these fits, so that a step still left there cannot be told
/// from a discontinuity by any fit on the data.
const FINEST_REFINEMENT: f64 = 1e-3;

/// Bound on [`jumps_between`]'s levels (8^4 pieces of an interval: below
/// [`FINEST_REFINEMENT`] for any interval under 400% of its speed).
const MAX_REFINE_LEVELS: usize = 4;

/// Whether `pred`'s up-sweep jumps by more than `step_um` between its speeds `j - 1` and `j`
/// (`speeds`, the curve's) rather than rising steeply along one branch: the interval is cut into
/// [`REFINE_STEPS`] speeds swept on from speed `j - 1`'s orbit, the piece with the largest step
/// cut again, down to [`FINEST_REFINEMENT`]. A step that stays above `step_um` is a jump (a
/// branch ending at a fold); one that shrinks below it is a continuous stretch (a coarse grid's
/// resonance peak where the teeth separate for a moment, which determines zeta). Counted as a
/// jump, so that no point is kept by mistake: an end point, a piece not period-1, the refined
/// sweep reaching speed `j` on another branch, a prediction without its model.
pub fn jumps_between(
    pred: &CurvePrediction,
    speeds: &[f64],
    j: usize,
    step_um: f64,
) -> Result<bool> {
    let Some(sweep) = &pred.sweep_model else {
        return Ok(true);
    };
    if j == 0 || j >= speeds.len() || !(pred.period1[j - 1] && pred.period1[j]) {
        return Ok(true);
    }
    let (mut s_lo, mut x_lo, mut y_lo) = (
        speeds[j - 1],
        pred.neighbour_starts[j - 1],
        pred.dte_pp_um[j - 1],
    );
    let (mut s_hi, mut y_hi) = (speeds[j], pred.dte_pp_um[j]);
    for _ in 0..MAX_REFINE_LEVELS {
        let width = (s_hi - s_lo) / REFINE_STEPS as f64;
        let sub: Vec<f64> = (1..=REFINE_STEPS)
            .map(|k| s_lo + width * k as f64)
            .collect();
        let pts = TestRun {
            dim: &sweep.dim,
            model: &sweep.model,
            omega_n_hz: sweep.omega_n_hz,
            speeds: &sub,
            opts: &fit_steady_options(),
        }
        .sweep_from(Branch::Up, RK_RTOL, x_lo, &NoProgress)?;
        if pts.iter().any(|p| p.steady.period != Some(1)) {
            return Ok(true);
        }
        let ys: Vec<f64> = pts
            .iter()
            .map(|p| sweep.dim.dte_um(p.steady.dte_pp))
            .collect();
        if (ys[REFINE_STEPS - 1] - y_hi).abs() > step_um {
            return Ok(true);
        }
        let (k, step) = (0..REFINE_STEPS)
            .map(|k| (k, (ys[k] - if k == 0 { y_lo } else { ys[k - 1] }).abs()))
            .fold((0, 0.0), |best, c| if c.1 > best.1 { c } else { best });
        if step <= step_um {
            return Ok(false);
        }
        if width <= FINEST_REFINEMENT * s_hi {
            return Ok(true);
        }
        if k > 0 {
            s_lo = sub[k - 1];
            y_lo = ys[k - 1];
            x_lo = pts[k - 1].steady.poincare.first().copied().unwrap_or(x_lo);
        }
        (s_hi, y_hi) = (sub[k], ys[k]);
    }
    Ok(true)
}

/// Where the observation windows of each sweep point start: with no period up to 32, the
/// analysed window's start; at a subharmonic point, where the speed before ended its analysis,
/// as a rig's run-up goes on (`sim::sweep::carry` starts from that speed's first section point):
/// a measurement can catch a chaotic transient there, beyond every window of the orbit. None at
/// period-1 points and at a sweep's first point.
fn window_starts(pts: &[crate::sim::SweepPoint]) -> Vec<Option<State>> {
    pts.iter()
        .enumerate()
        .map(|(k, p)| match p.steady.period {
            Some(1) => None,
            None => p.steady.poincare.first().copied(),
            Some(_) => k.checked_sub(1).map(|j| pts[j].steady.end),
        })
        .collect()
}

/// Smallest and largest pp DTE (um) over [`SPREAD_WINDOWS`] observation windows of the analysed
/// length from its window start ([`window_starts`]) at each point of `pred` (`setup.curves[i]`'s
/// prediction at these parameters) that is not period-1; `None` where every window repeats.
pub fn aperiodic_pp_range(
    setup: &Setup,
    i: usize,
    g: Globals,
    ste_um: f64,
    effect: &Effect,
    pred: &CurvePrediction,
) -> Result<Vec<Option<(f64, f64)>>> {
    let (dim, model) = curve_model(setup, i, g, ste_um, effect)?;
    let keep = SteadyOptions::default().keep;
    setup.curves[i]
        .speeds_rpm
        .par_iter()
        .zip(&pred.aperiodic_start)
        .map(|(&rpm, start)| {
            let Some(x) = start else { return Ok(None) };
            let flow = flow_with_rtol(&model.at_omega(dim.omega(rpm, g.omega_n_hz))?, RK_RTOL)?;
            let pp = dte_pp_over_windows(flow.as_ref(), *x, keep, SPREAD_WINDOWS)?;
            Ok(min_max(pp.into_iter().map(|v| dim.dte_um(v))))
        })
        .collect()
}
