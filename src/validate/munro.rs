//! `validate munro` (Sec. 7, Figs 19-22): fit zeta and omega_n (and the STE amplitude when not
//! given) to the design-load pp DTE curve, where the teeth stay in contact and eq. 13 is exact,
//! then predict pp DTE at the other loads by simulation with every branch (carried up, carried
//! down, all attractors), and compare with the measurements.
//!
//! Two sources of the STE at the predicted loads ([`SteMode`]): read from each curve (its
//! low-speed part, fitted jointly with the design load; the default), and, with
//! `--ste geometry`, from the gear geometry and a tip relief ([`super::geometry_ste`]), with
//! zeta, omega_n (and the relief depth when asked) fitted to the design-load curve alone. The
//! geometry path is run beside the per-curve one, so that both are reported side by side.

use super::curve_metrics::{jump_location, location_error, location_error_text, rms};
use super::design_fit::{
    curve_in_contact, curve_in_contact_harmonics, fit_design_geometry, fit_design_load,
    CorrelationChoice, DesignLoadFit, DesignModel, ErrorChoice, MunroNoise, StatedSte,
    LOW_SPEED_OMEGA,
};
use super::fit_check::{fit_failed, fit_failure, FITTED_ZETA};
use super::geometry_ste::{
    geometry_model, GearMesh, GeometryExcitation, GeometryFit, GeometryOptions, ReliefRule,
};
use super::kubo_swept::SWEPT_ZETA_FLOOR;
use super::synth::flow_with_rtol;
use crate::data::{locate_rig_key, rig_key_error, MunroData, MunroPoint};
use crate::error::{GearError, Result};
use crate::fit::{Distribution, NoiseModel, Robust};
use crate::model::{Dimensional, GearPair};
use crate::numeric::min_max;
use crate::progress::Progress;
use crate::sim::{
    find_attractors, sweep, Branch, EscapeBudget, IcGrid, SetKind, SteadyOptions, SweepPlan,
};
use rayon::prelude::*;
use serde::Serialize;

/// Settings of the Munro pipeline.
#[derive(Clone, Debug)]
pub struct MunroOptions {
    /// Points of the dense speed grid on which the model curves are drawn.
    pub dense_points: usize,
    /// Speeds (evenly spread) at which every attractor is searched.
    pub attractor_speeds: usize,
    /// Initial conditions per axis of that search.
    pub ic_per_axis: usize,
    /// How long that search follows non-periodic sets to tell a chaotic attractor from a
    /// chaotic transient (`PREDICTION_HORIZON` by default).
    pub escape: EscapeBudget,
    /// Student-t errors for the design-load fit: off, on, or when the residuals say so.
    pub robust: Robust,
    /// The errors' correlation along speed (`--correlation`); None: as rig.toml's `[noise]
    /// correlation_rpm` states it, else [`CorrelationChoice::Auto`].
    pub correlation: Option<CorrelationChoice>,
    /// Where the STE at the predicted loads comes from.
    pub ste: SteMode,
}

/// Where the STE at the predicted loads comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SteMode {
    /// Read from each curve (its low-speed part, fitted jointly with the design load).
    Curve,
    /// As `Curve`, and beside it the geometry path: zeta, omega_n (and the relief when asked)
    /// fitted at the design load alone, every other load predicted with the STE (and k(t) when
    /// asked) of the tooth-contact model.
    Geometry(Box<GeometryOptions>),
}

/// Relative tolerance of DOP853 when the geometry's k(t) varies (the exact solver otherwise).
const RK_RTOL: f64 = 1e-8;

/// Forcing periods up to which the predictions' attractor searches follow non-periodic sets
/// (`geardyn attractors` follows 40,000). A prediction asks what a rig held at one speed shows
/// while it is measured: a chaotic set that keeps all its trajectories for 10,000 mesh periods
/// (a few seconds of a rig's mesh at kHz mesh frequencies) and loses fewer than
/// [`crate::sim::MIN_ESCAPES`] of them is, on that time scale, an attractor (with ~50
/// trajectories the 95% upper bound of its escape rate is then ~1e-5 per period), and the sets
/// that do empty within it (Fig. 4's empties in ~18,000 periods on average) are still told
/// apart. On `data/munro` it finds the same attractors as 40,000 in less than half the time
/// (docs/performance.md), and shows one chaotic set at 945 N, 4333 rpm that still holds 2 of
/// 49 trajectories at 10,000 periods, labelled a transient.
pub const PREDICTION_HORIZON: usize = 10_000;

impl Default for MunroOptions {
    fn default() -> Self {
        MunroOptions {
            dense_points: 121,
            attractor_speeds: 25,
            ic_per_axis: 7,
            escape: EscapeBudget {
                horizon: PREDICTION_HORIZON,
                ..EscapeBudget::default()
            },
            robust: Robust::Auto,
            correlation: None,
            ste: SteMode::Curve,
        }
    }
}

/// Where an STE amplitude came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SteSource {
    /// The `[ste]` table of rig.toml, held as stated.
    RigToml,
    /// The `[ste]` table of rig.toml with its uncertainty `sd_um`: a measurement fitted with
    /// zeta and omega_n at the design load ([`crate::fit::Measurement`]).
    Measured,
    /// Fitted with zeta and omega_n at the design load.
    Fitted,
    /// Fitted to the curve's low-speed part (Omega <= 0.6 in contact), with the model's
    /// quasi-static gain, jointly with the design-load fit and its noise model.
    LowSpeedFit,
    /// Half the pp DTE at the curve's lowest speed (quasi-static DTE equals STE), corrected by
    /// the fitted linear gain there: only when fewer than 3 low-speed points are in contact.
    LowSpeedEnd,
    /// First harmonic of the loaded STE of the gear geometry with its tip relief
    /// (`--ste geometry`).
    Geometry,
}

/// A model curve point: speed, pp DTE in um, impact case (1, 2, 3).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ModelPoint {
    pub speed_rpm: f64,
    pub dte_pp_um: f64,
    pub case: u8,
    /// Period of the steady state in forcing periods (None: chaotic or aperiodic).
    pub period: Option<u32>,
    /// Basin fraction for all-attractor points.
    pub basin_fraction: Option<f64>,
    /// For all-attractor points: an attractor, or a transient set that still held
    /// trajectories of the grid at the search's horizon.
    pub kind: Option<SetKind>,
}

impl ModelPoint {
    /// On an attractor: a point of a carried sweep (no kind), or an all-attractor point whose
    /// set is an attractor rather than a transient set still held at the search's horizon.
    pub fn on_attractor(&self) -> bool {
        matches!(self.kind, None | Some(SetKind::Attractor))
    }
}

/// Prediction and errors at one load.
#[derive(Clone, Debug, Serialize)]
pub struct LoadResult {
    pub load_n: f64,
    pub mean_force: f64,
    pub ste_um: f64,
    /// 95% interval of the STE amplitude (fitted sources only).
    pub ste_ci95_um: Option<(f64, f64)>,
    pub ste_amplitude: f64,
    pub ste_source: SteSource,
    pub force_ratio: f64,
    /// True for the design load (the fitted curve).
    pub fitted: bool,
    pub measured: Vec<(f64, f64)>,
    pub up: Vec<ModelPoint>,
    pub down: Vec<ModelPoint>,
    pub all: Vec<ModelPoint>,
    /// RMS error against the nearer of the up and down branches at each measured speed, um.
    pub rms_um: f64,
    pub rms_up_um: f64,
    pub rms_down_um: f64,
    /// RMS error over the measured speeds where the nearer branch is period-1, um: the
    /// comparison that is stable. A chaotic pp follows the last bits of the arithmetic and a
    /// subharmonic one the branch history, so the points where the model is not period-1 are
    /// counted and described by their ranges instead (None when there are no period-1 points).
    pub rms_period1_um: Option<f64>,
    /// Measured speeds where the nearer branch is not period-1.
    pub not_period1_points: usize,
    /// Measured and model pp ranges (um) over those points.
    pub not_period1_measured_um: Option<(f64, f64)>,
    pub not_period1_model_um: Option<(f64, f64)>,
    pub jump_measured_rpm: Option<f64>,
    pub jump_up_rpm: Option<f64>,
    /// Period (forcing periods) of the motion the model's up-sweep lands on at its first jump;
    /// None where that motion is chaotic or aperiodic, or there is no jump (`jump_up_rpm`).
    pub jump_up_onto_period: Option<u32>,
    pub jump_down_rpm: Option<f64>,
    /// Model up-jump minus measured jump, rpm.
    pub jump_error_rpm: Option<f64>,
    /// How finely the grids place that error, rpm: half the data's speed step at its jump plus
    /// half the model sweep's at its jump (each jump lies somewhere within its step).
    pub jump_error_resolution_rpm: Option<f64>,
    /// Residuals (measured minus best branch) at the measured speeds.
    pub residuals: Vec<(f64, f64)>,
}

/// Everything `validate munro` computed.
#[derive(Clone, Debug, Serialize)]
pub struct MunroValidation {
    /// The design-load fit: parameters zeta, omega_n_hz (and ste_um when rig.toml gives none),
    /// the noise model, Fisher, sandwich and profile intervals.
    pub fit: DesignLoadFit,
    pub zeta: f64,
    pub omega_n_hz: f64,
    pub half_backlash_um: f64,
    pub mesh_stiffness_n_per_um: f64,
    /// Where k_h came from: a snake_case tag (`rig_toml`, `iso6336_estimate`).
    pub stiffness_source: &'static str,
    /// The same in words, with the estimate's numbers.
    pub stiffness_source_text: String,
    /// The fitted linear model keeps the teeth in contact at the design load at every measured speed.
    pub design_load_in_contact: bool,
    pub loads: Vec<LoadResult>,
    /// The geometry path (`--ste geometry`), beside the per-curve one.
    pub geometry: Option<GeometryValidation>,
}

/// The geometry path of `validate munro --ste geometry`: the design-load fit with the STE from
/// the geometry, and every load predicted with the geometry's excitation.
#[derive(Clone, Debug, Serialize)]
pub struct GeometryValidation {
    /// The engine's fit at the design load alone: zeta, omega_n_hz (and tip_relief_um).
    pub fit: DesignLoadFit,
    /// The relief used and how it was chosen; the model's harmonics and stiffness.
    pub relief: GeometryFit,
    pub zeta: f64,
    pub omega_n_hz: f64,
    /// The fitted model keeps the design load's teeth in contact at every measured speed
    /// (triangle-inequality bound over the STE harmonics).
    pub design_load_in_contact: bool,
    /// The geometry's STE and stiffness per load, in the order of `loads`.
    pub excitation: Vec<GeometryExcitation>,
    /// Predictions and errors per load (the design load's is the fitted curve).
    pub loads: Vec<LoadResult>,
}

/// The STE rig.toml states at a load with its uncertainty (a statement without one is
/// refused before any fit, [`require_ste_uncertainty`]).
fn stated_ste(data: &MunroData, load: f64) -> Option<StatedSte> {
    let table = data.rig.ste.as_ref()?;
    Some(StatedSte {
        amplitude_um: table.amplitude_at(load)?,
        sd_um: table.sd_at(load)?,
    })
}

/// The fewest points the design-load curve may have: one more than the parameters fitted to
/// it alone at first (zeta, omega_n, the STE amplitude, the noise floor and relative part).
pub const MIN_DESIGN_POINTS: usize = 6;

/// The least largest pp DTE of a design-load curve, um: below it the values are most likely in
/// mm (a gear pair's pp DTE through its resonance is tenths of a um at the least).
const MIN_DESIGN_PEAK_UM: f64 = 0.01;

/// A design-load curve that can show a resonance: not flat (every value the same, zero
/// included: the noise could not be estimated and zeta ran off to thousands) and not so small
/// that its values must be in another unit.
pub(crate) fn check_design_levels(design: f64, curve: &[&MunroPoint]) -> Result<()> {
    let (lo, hi) = curve.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), p| {
        (a.min(p.dte_pp_um), b.max(p.dte_pp_um))
    });
    let Some(first) = curve.first() else {
        return Ok(());
    };
    let message = if curve.len() > 1 && hi <= lo {
        format!(
            "every point of the design-load curve ({design} N) reads {hi} um: a flat curve shows \
             no resonance to fit"
        )
    } else if hi < MIN_DESIGN_PEAK_UM {
        format!(
            "the design-load curve ({design} N) peaks at {hi} um, below any gear pair's pp DTE: \
             the column must be in um (is it in mm?)"
        )
    } else {
        return Ok(());
    };
    Err(GearError::Data {
        file: first.file.clone(),
        line: 0,
        field: "dte_pp_um".into(),
        message,
    })
}

/// The rig's dimensional scales, the design load (N) and its measured curve, which a fit needs
/// with at least [`MIN_DESIGN_POINTS`] points. rig.toml may not give zeta or omega_n_hz: this
/// pipeline fits them.
fn design_curve(data: &MunroData) -> Result<(Dimensional, f64, Vec<&MunroPoint>)> {
    let rig = &data.rig.rig;
    for (key, given) in [("zeta", rig.zeta), ("omega_n_hz", rig.omega_n_hz)] {
        if let Some(v) = given {
            return Err(rig_key_error(
                &data.dir,
                "rig",
                key,
                format!(
                    "{key} = {v}: validate munro fits zeta and omega_n_hz to the design-load \
                     curve and would ignore this value; remove it from [rig] (sweep, simulate \
                     and the other analysis commands with --rig take it as their default, \
                     validate kubo as a fixed value)"
                ),
            ));
        }
    }
    let dim = rig.dimensional()?;
    let design = rig.design_load_n;
    let curve = data.curve(design);
    check_design_levels(design, &curve)?;
    if curve.len() < MIN_DESIGN_POINTS {
        return Err(rig_key_error(
            &data.dir,
            "rig",
            "design_load_n",
            format!(
                "the fit needs the design-load curve ({design} N) with at least \
                 {MIN_DESIGN_POINTS} points (zeta, omega_n, the STE and the noise's floor and \
                 relative part are fitted to it); found {}{}",
                curve.len(),
                if curve.is_empty() {
                    format!(
                        " (the curves' loads: {} N; are the loads in N?)",
                        crate::data::loads_text(&data.loads())
                    )
                } else {
                    String::new()
                }
            ),
        ));
    }
    Ok((dim, design, curve))
}

/// The fit `fit` of the data set `data`, or the reason it failed (see [`fit_failure`]).
///
/// A fit through simulated up-sweeps ([`DesignModel::Swept`]) cannot take zeta below the least
/// damping it simulates; one that ends there is refused as not determining zeta: where the
/// teeth separate over the resonance, the curve's peak is set by the backlash more than by the
/// damping (F_hat 4.7, zeta 0.0175, relative noise: three of six DOP853-made sets ran to the
/// floor, the others ended at 0.017-0.021 with intervals spanning a factor of ten).
fn usable(data: &MunroData, what: &str, fit: DesignLoadFit) -> Result<DesignLoadFit> {
    let (zeta_range, what) = match fit.design_model {
        DesignModel::Linear => (FITTED_ZETA, what.to_string()),
        DesignModel::Swept => (
            (SWEPT_ZETA_FLOOR, FITTED_ZETA.1),
            format!(
                "{what} through simulated up-sweeps (the teeth separate at the design load, where \
                 eq. 13 does not hold)"
            ),
        ),
    };
    match fit_failure(&fit.estimate, &fit.ci95_profile, zeta_range) {
        Some(reason) => Err(fit_failed(&data.dir, &what, reason)),
        None => Ok(fit),
    }
}

/// The design-load fit of [`fit_munro_design_load`] if it can be used (see [`usable`]), else
/// the reason as [`GearError::FitFailed`].
pub fn usable_design_fit(data: &MunroData, fit: DesignLoadFit) -> Result<DesignLoadFit> {
    usable(data, "design-load fit", fit)
}

/// The STE of a load whose curve has fewer than 3 low-speed points in contact: half the pp DTE
/// at its lowest speed over the linear gain there (quasi-static DTE equals STE). A zero reading
/// there would give a zero STE and an infinite force ratio: it is an error naming the point.
fn ste_from_lowest_speed(first: &MunroPoint, zeta: f64, omega: f64, load_n: f64) -> Result<f64> {
    let ste = first.dte_pp_um / (2.0 * super::linear::dte_gain(zeta, omega));
    if ste.is_finite() && ste > 0.0 {
        return Ok(ste);
    }
    Err(GearError::Data {
        file: first.file.clone(),
        line: first.line,
        field: "dte_pp_um".into(),
        message: format!(
            "the STE at {load_n} N is read from its lowest speed ({} rpm; fewer than 3 points \
             lie below Omega = {LOW_SPEED_OMEGA} in contact), and the pp DTE there is {}: give \
             the STE at this load in rig.toml ([ste] load_n, amplitude_um) or measure the curve \
             at lower speeds",
            first.speed_rpm, first.dte_pp_um
        ),
    })
}

/// The design-load fit of `validate munro` on a loaded set (its curve, the rig's STE when
/// given, the set's noise setting), and the STE the rig states at the design load, if any
/// (with `sd_um`, a measurement the fit weighs). Errors when rig.toml states an STE without
/// its uncertainty ([`require_ste_uncertainty`]) or the design load has fewer than
/// [`MIN_DESIGN_POINTS`] points.
pub fn fit_munro_design_load(
    data: &MunroData,
    errors: (Robust, Option<CorrelationChoice>),
) -> Result<(DesignLoadFit, Option<StatedSte>)> {
    require_ste_uncertainty(data)?;
    let stated = |l: f64| stated_ste(data, l);
    let fit = design_load_fit(data, errors, &stated)?;
    Ok((fit, stated(data.rig.rig.design_load_n)))
}

/// [`fit_munro_design_load`] with the STE each load states given by `stated`.
fn design_load_fit(
    data: &MunroData,
    errors: (Robust, Option<CorrelationChoice>),
    stated: &dyn Fn(f64) -> Option<StatedSte>,
) -> Result<DesignLoadFit> {
    let (dim, design, curve) = design_curve(data)?;
    // The other loads: their low-speed parts join the fit, each stated STE a measurement.
    let others: Vec<(f64, Vec<&MunroPoint>, Option<StatedSte>)> = data
        .loads()
        .into_iter()
        .filter(|l| !crate::data::same_load(*l, design))
        .map(|l| (l, data.curve(l), stated(l)))
        .collect();
    fit_design_load(
        &dim,
        (design, &curve),
        &others,
        stated(design),
        (noise_setting(data)?, error_choice(data, errors)?),
    )
}

/// A design-load fit that failed or could not be used (`cause`) with the STEs stated with their
/// uncertainty weighed in: the fit again with those STEs free, and each stated one against what the curves alone
/// give, by Theil & Goldberger's (1961) compatibility z = (stated - fitted) / sqrt(sd^2 + se^2),
/// located at `[ste] amplitude_um`. Where the free fit fails too, `cause` as it is.
fn measured_ste_failure(
    data: &MunroData,
    errors: (Robust, Option<CorrelationChoice>),
    cause: GearError,
) -> GearError {
    let Ok(fit) = design_load_fit(data, errors, &|_| None).and_then(|f| usable_design_fit(data, f))
    else {
        return cause;
    };
    let design = data.rig.rig.design_load_n;
    let e = &fit.estimate;
    let fitted_at = |load: f64| {
        let k = fit.ste_param(load, design)?;
        Some((e.params[k], e.std_errors[k]))
    };
    let lines: Vec<String> = data
        .loads()
        .into_iter()
        .filter_map(|l| {
            let s = stated_ste(data, l)?;
            let sd = s.sd_um;
            let Some((b, se)) = fitted_at(l) else {
                return Some(format!(
                    "{l} N: stated {} ± {sd} um, not in the fit (no low-speed part in contact)",
                    s.amplitude_um
                ));
            };
            let z = (s.amplitude_um - b) / (sd * sd + se * se).sqrt();
            Some(format!(
                "{l} N: stated {} ± {sd} um, the curves alone {b:.3} ± {se:.3} um (z {z:+.1}{})",
                s.amplitude_um,
                if z.abs() > 1.96 { ", disagree" } else { "" }
            ))
        })
        .collect();
    rig_key_error(
        &data.dir,
        "ste",
        "amplitude_um",
        format!(
            "the design-load fit failed with the stated STEs weighed in ({cause}); against the \
             curves alone: {}. A stated STE that the curves disagree with is a wrong measurement, \
             a wrong uncertainty or another load's",
            lines.join("; ")
        ),
    )
}

/// A set whose rig.toml states STEs states their uncertainty too (`[ste] sd_um`): a stated STE
/// is weighed against the curves as a measurement, and one held exact would bias zeta by its
/// own error (the resonance peak is about STE / (2 zeta)). `validate munro` and `discover`
/// refuse the set otherwise, at `[ste] amplitude_um`.
pub fn require_ste_uncertainty(data: &MunroData) -> Result<()> {
    let Some(t) = data.rig.ste.as_ref() else {
        return Ok(());
    };
    if t.load_n.is_empty() || t.sd_um.is_some() {
        return Ok(());
    }
    Err(rig_key_error(
        &data.dir,
        "ste",
        "amplitude_um",
        format!(
            "the STE is stated at {} N without its uncertainty: add sd_um to [ste] (the standard \
             uncertainty in um, one value for every load or a list with one per load). A stated \
             STE is weighed against the curves as a measurement; held exact it would bias zeta by \
             its own error. To have each STE fitted to its own curve instead, remove [ste]",
            crate::data::loads_text(&t.load_n)
        ),
    ))
}

/// Run the Munro validation on a loaded data set.
pub fn validate_munro(
    data: &MunroData,
    opts: &MunroOptions,
    progress: &dyn Progress,
) -> Result<MunroValidation> {
    let rig = &data.rig.rig;
    let dim = rig.dimensional()?;
    let design = rig.design_load_n;
    let design_curve = data.curve(design);
    let errors = (opts.robust, opts.correlation);
    let (fit, stated) = fit_munro_design_load(data, errors)
        .and_then(|(fit, ste)| Ok((usable_design_fit(data, fit)?, ste)))
        .map_err(|e| {
            if data.rig.ste.is_some() {
                measured_ste_failure(data, errors, e)
            } else {
                e
            }
        })?;
    let (zeta, wn, ste_design) = fit.values();
    let design_source = match stated {
        Some(_) => SteSource::Measured,
        None => SteSource::Fitted,
    };
    let design_ste_ci = Some(fit.estimate.ci95[2]);
    let design_in_contact = curve_in_contact(
        &dim,
        dim.mean_force(design),
        &design_curve,
        (zeta, wn, ste_design),
    );
    let loads = data.loads();
    progress.start(loads.len() as u64, "loads");
    let results: Vec<Result<LoadResult>> = loads
        .par_iter()
        .map(|&load| {
            let curve = data.curve(load);
            let fitted = (load - design).abs() <= 1e-6 * design;
            let ste = if fitted {
                Ok((ste_design, design_ste_ci, design_source))
            } else {
                match (fit.other_ste(load), stated_ste(data, load)) {
                    (Some((e, ci)), Some(_)) => Ok((e, Some(ci), SteSource::Measured)),
                    (Some((e, ci)), None) => Ok((e, Some(ci), SteSource::LowSpeedFit)),
                    // No low-speed part in contact to weigh it against: as stated.
                    (None, Some(s)) => Ok((s.amplitude_um, None, SteSource::RigToml)),
                    (None, None) => {
                        let p0 = curve[0];
                        ste_from_lowest_speed(p0, zeta, dim.omega(p0.speed_rpm, wn), load)
                            .map(|e| (e, None, SteSource::LowSpeedEnd))
                    }
                }
            };
            let r = ste.and_then(|(ste, ci, source)| {
                let exc = LoadExcitation {
                    model: GearPair::paper(
                        dim.mean_force(load),
                        dim.ste_amplitude(ste),
                        zeta,
                        1.0,
                    )?,
                    omega_n_hz: wn,
                    ste_um: ste,
                    ste_ci95_um: ci,
                    ste_source: source,
                };
                predict_load(&dim, load, &exc, fitted, &curve, opts)
            });
            progress.advance(1);
            r
        })
        .collect();
    progress.finish();
    let loads = check_predictions(data, results.into_iter().collect::<Result<Vec<_>>>()?)?;
    let geometry = match &opts.ste {
        SteMode::Curve => None,
        SteMode::Geometry(g) => Some(validate_geometry(data, g, opts, progress)?),
    };
    Ok(MunroValidation {
        zeta,
        omega_n_hz: wn,
        half_backlash_um: dim.half_backlash_m * 1e6,
        mesh_stiffness_n_per_um: dim.mesh_stiffness_n_per_m * 1e-6,
        stiffness_source: dim.stiffness_source.tag(),
        stiffness_source_text: dim.stiffness_source.describe(),
        design_load_in_contact: design_in_contact,
        loads,
        geometry,
        fit,
    })
}

/// The geometry path: relief by `g.relief`, zeta and omega_n (and the depth) fitted to the
/// design-load curve alone with the geometry's STE there, then every load predicted with the
/// geometry's STE harmonics and, with [`StiffnessChoice::Geometry`], its k_h(F) and k(t)
/// (see [`super::geometry_ste`] for the conventions).
fn validate_geometry(
    data: &MunroData,
    g: &GeometryOptions,
    opts: &MunroOptions,
    progress: &dyn Progress,
) -> Result<GeometryValidation> {
    let rig = &data.rig.rig;
    let (dim, design, curve) = design_curve(data)?;
    let mesh = GearMesh::new(rig, g).map_err(|e| locate_rig_key(&data.dir.join("rig.toml"), e))?;
    let (start_um, fit_depth) = match g.relief {
        ReliefRule::DesignRule => (mesh.design_rule_um(design)?, false),
        ReliefRule::Given { amount_um } => (amount_um, false),
        ReliefRule::Fit => (mesh.design_rule_um(design)?, true),
    };
    let harmonics = g.ste_harmonics;
    let ste_at = |a: f64| -> Result<Vec<(u32, f64, f64)>> {
        Ok(mesh.excitation(design, a)?.ste_terms_um(harmonics))
    };
    let fit = fit_design_geometry(
        &dim,
        (dim.mean_force(design), &curve),
        &ste_at,
        (start_um, fit_depth),
        (
            noise_setting(data)?,
            error_choice(data, (opts.robust, opts.correlation))?,
        ),
    )?;
    let what = match g.relief {
        ReliefRule::Fit => "design-load fit with the geometry's STE",
        _ => {
            "design-load fit with the geometry's STE (its relief not fitted: --relief fit fits \
              the relief depth too, if the curve's STE differs from the geometry's)"
        }
    };
    let fit = usable(data, what, fit)?;
    let p = &fit.estimate.params;
    let (zeta, wn) = (p[0], p[1]);
    let relief_um = if fit_depth { p[2] } else { start_um };
    let loads = data.loads();
    let excitation = loads
        .iter()
        .map(|&l| mesh.excitation(l, relief_um))
        .collect::<Result<Vec<_>>>()?;
    let k_design = mesh
        .excitation(design, relief_um)?
        .mesh_stiffness_mean_n_per_um;
    let design_exc = &excitation[loads
        .iter()
        .position(|l| crate::data::same_load(*l, design))
        .unwrap_or(0)];
    let design_load_in_contact = curve_in_contact_harmonics(
        &dim,
        dim.mean_force(design),
        &curve,
        (zeta, wn),
        &design_exc.ste_terms_um(harmonics),
    );
    progress.start(loads.len() as u64, "loads (geometry)");
    let results: Vec<Result<LoadResult>> = loads
        .par_iter()
        .zip(&excitation)
        .map(|(&load, exc)| {
            let fitted = crate::data::same_load(load, design);
            let r = geometry_excitation(&dim, exc, g, zeta, wn, k_design)
                .and_then(|e| predict_load(&dim, load, &e, fitted, &data.curve(load), opts));
            progress.advance(1);
            r
        })
        .collect();
    progress.finish();
    let mirror_relief_um = if fit_depth {
        mesh.mirror_relief_um(design, relief_um)?
    } else {
        None
    };
    Ok(GeometryValidation {
        relief: GeometryFit {
            relief_rule: g.relief,
            relief_um,
            relief_um_ci95: fit_depth.then(|| fit.estimate.ci95[2]),
            mirror_relief_um,
            relief_length_mm: mesh.relief_length_mm(),
            relief_shape: g.relief_shape,
            ste_harmonics: harmonics,
            stiffness: g.stiffness,
        },
        zeta,
        omega_n_hz: wn,
        design_load_in_contact,
        excitation,
        loads: check_predictions(data, results.into_iter().collect::<Result<Vec<_>>>()?)?,
        fit,
    })
}

/// Every load's force ratio and RMS error must be finite; a prediction that is not is a failed
/// fit, reported with the load.
fn check_predictions(data: &MunroData, loads: Vec<LoadResult>) -> Result<Vec<LoadResult>> {
    for l in &loads {
        if !(l.force_ratio.is_finite() && l.rms_um.is_finite()) {
            return Err(fit_failed(
                &data.dir,
                &format!("prediction at {} N", l.load_n),
                format!(
                    "force ratio F_hat = {} and RMS error {} um are not both finite (STE {} um)",
                    l.force_ratio, l.rms_um, l.ste_um
                ),
            ));
        }
    }
    Ok(loads)
}

/// The model of one predicted load from the geometry ([`geometry_model`]), with its STE
/// reported as the first harmonic e_1.
fn geometry_excitation(
    dim: &Dimensional,
    exc: &GeometryExcitation,
    g: &GeometryOptions,
    zeta: f64,
    wn: f64,
    k_design_n_per_um: f64,
) -> Result<LoadExcitation> {
    let m = geometry_model(
        dim,
        exc,
        g.ste_harmonics,
        g.stiffness,
        zeta,
        wn,
        k_design_n_per_um,
    )?;
    Ok(LoadExcitation {
        model: m.model,
        omega_n_hz: m.omega_n_hz,
        ste_um: exc.ste_first_harmonic_um,
        ste_ci95_um: None,
        ste_source: SteSource::Geometry,
    })
}

/// The model of one predicted load (at Omega = 1; the sweeps set Omega), its natural frequency,
/// and the STE amplitude reported with it.
struct LoadExcitation {
    model: GearPair,
    omega_n_hz: f64,
    ste_um: f64,
    ste_ci95_um: Option<(f64, f64)>,
    ste_source: SteSource,
}

/// The noise setting of the design-load fit: per point when every point states its standard
/// deviation (`dte_pp_sd_um`); the model of rig.toml's `[noise]` when it states a floor (with
/// its relative part, 0 when not given); else estimated jointly with the fit, the floor never
/// below a stated reading uncertainty.
pub fn noise_setting(data: &MunroData) -> Result<MunroNoise> {
    if !data.points.is_empty() && data.points.iter().all(|p| p.sd_um.is_some()) {
        return Ok(MunroNoise::PerPoint);
    }
    let stated = data.rig.noise.as_ref();
    match stated.and_then(|n| n.floor_um) {
        Some(floor) if floor > 0.0 => Ok(MunroNoise::Stated(NoiseModel {
            floor,
            relative: stated.and_then(|n| n.relative).unwrap_or(0.0),
            distribution: Distribution::Gaussian,
            correlation_length: stated.and_then(|n| n.correlation_rpm).unwrap_or(0.0),
        })),
        Some(_) | None if stated.is_some_and(|n| n.relative.is_some() || n.floor_um.is_some()) => {
            Err(rig_key_error(
                &data.dir,
                "noise",
                "floor_um",
                "a stated noise needs a positive floor_um (the relative part alone gives a zero scale at zero level); give floor_um, or leave [noise] to reading_um and let the fit estimate the noise",
            ))
        }
        _ => Ok(MunroNoise::Estimate {
            floor_min: stated.and_then(|n| n.reading_um).unwrap_or(0.0),
        }),
    }
}

/// How the design-load fit treats its errors: the tails as `robust` says; the correlation along
/// speed as `correlation` says (the command line), else as rig.toml's `[noise] correlation_rpm`
/// states it, else estimated when the data say so. A length stated in both places is refused:
/// one statement of the noise.
pub fn error_choice(
    data: &MunroData,
    (robust, correlation): (Robust, Option<CorrelationChoice>),
) -> Result<ErrorChoice> {
    let stated = data.rig.noise.as_ref().and_then(|n| n.correlation_rpm);
    let correlation = match (correlation, stated) {
        (Some(_), Some(_)) => {
            return Err(rig_key_error(
                &data.dir,
                "noise",
                "correlation_rpm",
                "the correlation length is stated here and by --correlation on the command line: state it once (remove the key, or the option)",
            ))
        }
        (Some(c), None) => c,
        (None, Some(l)) => CorrelationChoice::Stated(l),
        (None, None) => CorrelationChoice::Auto,
    };
    Ok(ErrorChoice {
        robust,
        correlation,
    })
}

fn predict_load(
    dim: &Dimensional,
    load: f64,
    exc: &LoadExcitation,
    fitted: bool,
    curve: &[&MunroPoint],
    opts: &MunroOptions,
) -> Result<LoadResult> {
    let model = &exc.model;
    let (fm, wn) = (model.mean_force, exc.omega_n_hz);
    let fah = model.ste.first().map_or(0.0, |t| t.amplitude);
    let (ste_um, ste_ci95_um, ste_source) = (exc.ste_um, exc.ste_ci95_um, exc.ste_source);
    let measured: Vec<(f64, f64)> = curve.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect();
    let (lo, hi) = (measured[0].0, measured[measured.len() - 1].0);
    let speeds = prediction_speeds(&measured, opts.dense_points.max(2));
    let omegas: Vec<f64> = speeds.iter().map(|&s| dim.omega(s, wn)).collect();
    let opts_ss = SteadyOptions {
        escape: opts.escape,
        ..SteadyOptions::default()
    };
    let steady = Sweep {
        dim,
        model,
        omega_n_hz: wn,
        opts: &opts_ss,
    };
    let up = steady.carried(&omegas, Branch::Up)?;
    let down = steady.carried(&omegas, Branch::Down)?;
    let k = opts.attractor_speeds.max(2);
    let attractor_speeds: Vec<f64> = (0..k)
        .map(|i| lo + (hi - lo) * i as f64 / (k - 1) as f64)
        .collect();
    let all = steady.attractors(&attractor_speeds, opts.ic_per_axis.max(1))?;
    let cmp = Comparison::of(&measured, &up, &down);
    let curve_of = |b: &[ModelPoint]| {
        b.iter()
            .map(|p| (p.speed_rpm, p.dte_pp_um))
            .collect::<Vec<_>>()
    };
    let jump_measured = jump_location(&measured, 6.0);
    let up_curve = curve_of(&up);
    let jump_up = jump_location(&up_curve, 6.0);
    let (jump_error_rpm, jump_error_resolution_rpm) =
        location_error((&measured, jump_measured), (&up_curve, jump_up));
    let jump_down = jump_location(&curve_of(&down), 6.0);
    let jump_up_onto_period = jump_up
        .and_then(|j| up.iter().find(|p| p.speed_rpm > j))
        .and_then(|p| p.period);
    Ok(LoadResult {
        load_n: load,
        mean_force: fm,
        ste_um,
        ste_ci95_um,
        ste_amplitude: fah,
        ste_source,
        force_ratio: fm / fah,
        fitted,
        rms_um: rms(&cmp.best),
        rms_up_um: rms(&cmp.up),
        rms_down_um: rms(&cmp.down),
        rms_period1_um: (!cmp.period1.is_empty()).then(|| rms(&cmp.period1)),
        not_period1_points: cmp.not_period1.len(),
        not_period1_measured_um: min_max(cmp.not_period1.iter().map(|p| p.0)),
        not_period1_model_um: min_max(cmp.not_period1.iter().map(|p| p.1)),
        jump_error_rpm,
        jump_error_resolution_rpm,
        jump_measured_rpm: jump_measured,
        jump_up_rpm: jump_up,
        jump_up_onto_period,
        jump_down_rpm: jump_down,
        residuals: cmp.residuals,
        measured,
        up,
        down,
        all,
    })
}

/// The speeds of a predicted curve: `n` evenly spaced over the measured range, and every
/// measured speed (so that each measured point has a prediction at its own speed).
fn prediction_speeds(measured: &[(f64, f64)], n: usize) -> Vec<f64> {
    let (lo, hi) = (measured[0].0, measured[measured.len() - 1].0);
    let mut speeds: Vec<f64> = (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect();
    speeds.extend(measured.iter().map(|m| m.0));
    speeds.sort_by(f64::total_cmp);
    speeds.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    speeds
}

/// The steady states of one load's model, in the rig's units.
struct Sweep<'a> {
    dim: &'a Dimensional,
    model: &'a GearPair,
    omega_n_hz: f64,
    opts: &'a SteadyOptions,
}

impl LoadResult {
    /// The jump error as "8 ± 42" followed by `unit` (in rpm, with the grids' resolution) and
    /// the motion the model jumps onto where it is not period-1, or why there is none.
    pub fn jump_error_text(&self, unit: &str) -> String {
        match (self.jump_measured_rpm, self.jump_error_rpm) {
            (None, _) => "- (no jump in the data)".to_string(),
            (Some(_), None) => "- (no jump in the model's speed-up sweep)".to_string(),
            (Some(_), Some(e)) => {
                let onto = match self.jump_up_onto_period {
                    Some(1) => String::new(),
                    Some(n) => format!(", the model's jump onto period-{n} motion"),
                    None => ", the model's jump into chaotic or aperiodic motion".to_string(),
                };
                format!(
                    "{}{onto}",
                    location_error_text(e, self.jump_error_resolution_rpm, unit)
                )
            }
        }
    }
}

/// pp DTE (um) at each of `speeds` (rpm) on the up-sweep of `model` (omega_n `omega_n_hz`),
/// each speed started from the last one's state, as a run-up measures it: separation and
/// jumps included.
pub(super) fn up_sweep_pp_um(
    dim: &Dimensional,
    model: &GearPair,
    omega_n_hz: f64,
    speeds: &[f64],
) -> Result<Vec<f64>> {
    let opts = SteadyOptions::default();
    let steady = Sweep {
        dim,
        model,
        omega_n_hz,
        opts: &opts,
    };
    let omegas: Vec<f64> = speeds.iter().map(|&s| dim.omega(s, omega_n_hz)).collect();
    Ok(steady
        .carried(&omegas, Branch::Up)?
        .iter()
        .map(|p| p.dte_pp_um)
        .collect())
}

impl Sweep<'_> {
    /// The sweep up or down `omegas`, each speed started from the last one's state.
    fn carried(&self, omegas: &[f64], branch: Branch) -> Result<Vec<ModelPoint>> {
        let factory = |m: &GearPair| flow_with_rtol(m, RK_RTOL);
        let plan = SweepPlan {
            omegas: omegas.to_vec(),
            branch,
            x0: [1.0 + self.model.mean_force, 0.0],
            grid: IcGrid::new(-2.0, 2.0, 1)?,
            opts: self.opts.clone(),
        };
        Ok(
            sweep(&factory, self.model, &plan, &crate::progress::NoProgress)?
                .iter()
                .map(|p| ModelPoint {
                    speed_rpm: self.dim.speed_rpm(p.omega, self.omega_n_hz),
                    dte_pp_um: self.dim.dte_um(p.steady.dte_pp),
                    case: p.steady.impact.case(),
                    period: p.steady.period,
                    basin_fraction: None,
                    kind: None,
                })
                .collect(),
        )
    }

    /// Every attractor an `ic_per_axis` squared grid of initial conditions finds at each of
    /// `speeds` (rpm), with its basin fraction.
    fn attractors(&self, speeds: &[f64], ic_per_axis: usize) -> Result<Vec<ModelPoint>> {
        let grid = IcGrid::new(-2.0, 2.0, ic_per_axis)?;
        let mut all = Vec::new();
        for &s in speeds {
            let om = self.dim.omega(s, self.omega_n_hz);
            let flow = flow_with_rtol(&self.model.at_omega(om)?, RK_RTOL)?;
            let map = find_attractors(
                flow.as_ref(),
                &grid,
                self.opts,
                &crate::progress::NoProgress,
            )?;
            // A transient set that every trajectory of the grid left within the horizon is not
            // something the rig would show while held at this speed.
            all.extend(
                map.attractors
                    .iter()
                    .filter(|a| a.basin_count > 0)
                    .map(|a| ModelPoint {
                        speed_rpm: s,
                        dte_pp_um: self.dim.dte_um(a.steady.dte_pp),
                        case: a.steady.impact.case(),
                        period: a.steady.period,
                        basin_fraction: Some(a.basin_fraction),
                        kind: Some(a.kind),
                    }),
            );
        }
        Ok(all)
    }
}

/// The measured curve against the up and down sweeps, point by point (um): each residual
/// about either sweep, about the nearer one (`best`), and `best` split by whether the nearer
/// sweep is period-1 there (the others as (measured, predicted)).
struct Comparison {
    up: Vec<f64>,
    down: Vec<f64>,
    best: Vec<f64>,
    period1: Vec<f64>,
    not_period1: Vec<(f64, f64)>,
    residuals: Vec<(f64, f64)>,
}

impl Comparison {
    fn of(measured: &[(f64, f64)], up: &[ModelPoint], down: &[ModelPoint]) -> Comparison {
        let at = |branch: &[ModelPoint], s: f64| {
            branch
                .iter()
                .find(|p| (p.speed_rpm - s).abs() <= 1e-6 * s.abs().max(1.0))
                .map_or((f64::NAN, false), |p| (p.dte_pp_um, p.period == Some(1)))
        };
        let mut c = Comparison {
            up: Vec::new(),
            down: Vec::new(),
            best: Vec::new(),
            period1: Vec::new(),
            not_period1: Vec::new(),
            residuals: Vec::new(),
        };
        for &(s, y) in measured {
            let ((fu, pu), (fd, pd)) = (at(up, s), at(down, s));
            let (u, d) = (y - fu, y - fd);
            let (best, f, p1) = if u.abs() <= d.abs() {
                (u, fu, pu)
            } else {
                (d, fd, pd)
            };
            c.up.push(u);
            c.down.push(d);
            c.best.push(best);
            if p1 {
                c.period1.push(best);
            } else {
                c.not_period1.push((y, f));
            }
            c.residuals.push((s, best));
        }
        c
    }
}
