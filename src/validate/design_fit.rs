//! The fits of `validate munro`, on the estimation engine of [`crate::fit`]: zeta, omega_n (and
//! the STE amplitude when rig.toml gives none) at the design load, where the teeth stay in
//! contact and eq. 13 is exact, with the noise model estimated jointly; and the STE amplitude
//! of another load from the low-speed part of its curve, with the model's own quasi-static
//! amplification and the design load's noise model.

use super::kubo_swept::{SWEPT_ZETA_FLOOR, SWEPT_ZETA_MIN};
use super::linear::{dte_pp_um, dte_pp_um_harmonics, stays_in_contact, stays_in_contact_harmonics};
use super::munro::up_sweep_pp_um;
use crate::data::MunroPoint;
use crate::error::{GearError, Result};
use crate::fit::{
    estimate, profile_interval, Axis, CorrelationSetting, Estimate, EstimateOptions, Measurement,
    NoiseFreedom, NoiseModel, NoiseSetting, Param, ProfileInterval, Robust, Stop,
};
use crate::model::{Dimensional, GearPair};
use serde::Serialize;

/// Jacobians at most in each weighted fit (eq. 13 is smooth: 10-20 suffice).
const FIT_JACOBIANS: usize = 100;
/// Jacobians at most in a fit through simulated up-sweeps, and the gains below which it and
/// its profiles' inner fits stop (sigma^2 over three Jacobians: as `validate kubo`'s
/// whole-curve fit, [`super::kubo_swept`]).
const SWEPT_JACOBIANS: usize = 60;
const SWEPT_FIT_STALL: f64 = 1e-4;
const SWEPT_PROFILE_STALL: f64 = 1e-2;

/// How the design-load curve is modelled in the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignModel {
    /// The linear model's closed form (eq. 13), exact while the teeth stay in contact.
    Linear,
    /// The exact solver's up-sweep at the measured speeds, each speed started from the last
    /// one's state: separation, impacts and jumps included. Taken when eq. 13's fit separates
    /// the teeth at some measured speed, where the closed form is wrong: on a rig whose design
    /// load separates over the resonance (F_hat 4.7, zeta 0.03, 2500 Hz), eq. 13 fitted zeta
    /// 0.0746 [0.0579, 0.0962].
    Swept,
}

/// A load's STE as rig.toml `[ste]` states it: the amplitude (um) and its standard
/// uncertainty (`sd_um`), a measurement the fit weighs against the curves ([`Measurement`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StatedSte {
    pub amplitude_um: f64,
    pub sd_um: f64,
}

/// The design-load fit with its profile-likelihood intervals.
#[derive(Clone, Debug, Serialize)]
pub struct DesignLoadFit {
    /// Parameters: zeta, omega_n_hz, ste_um (design load, unless given), then one STE
    /// amplitude per other load in `other_loads`.
    pub estimate: Estimate,
    /// Profile-likelihood 95% intervals of zeta, omega_n_hz and the design-load STE (None: not
    /// bounded on that side).
    pub ci95_profile: Vec<ProfileInterval>,
    /// Loads whose low-speed part joined the fit, and the points each gave.
    pub other_loads: Vec<(f64, usize)>,
    /// Points of the design-load curve (the first rows of the fit).
    pub design_points: usize,
    /// How the design-load curve was modelled.
    pub design_model: DesignModel,
}

impl DesignLoadFit {
    /// zeta, omega_n (Hz) and the design-load STE amplitude (um).
    pub fn values(&self) -> (f64, f64, f64) {
        let p = &self.estimate.params;
        (p[0], p[1], p[2])
    }

    /// The STE amplitude fitted to the low-speed part of `load_n`, with its 95% interval.
    pub fn other_ste(&self, load_n: f64) -> Option<(f64, (f64, f64))> {
        let k = self.other_ste_param(load_n)?;
        Some((self.estimate.params[k], self.estimate.ci95[k]))
    }

    /// The index of the STE parameter of `load_n` (design load `design_load_n`): the design
    /// load's `ste_um` where it is fitted, else that of the load's low-speed part, if it joined.
    pub fn ste_param(&self, load_n: f64, design_load_n: f64) -> Option<usize> {
        if crate::data::same_load(load_n, design_load_n) {
            self.estimate.names.iter().position(|n| n == "ste_um")
        } else {
            self.other_ste_param(load_n)
        }
    }

    /// The load whose STE parameter `k` is ([`DesignLoadFit::ste_param`]'s inverse).
    pub fn ste_load(&self, k: usize, design_load_n: f64) -> Option<f64> {
        if self.estimate.names.get(k).is_some_and(|n| n == "ste_um") {
            return Some(design_load_n);
        }
        let first = self.estimate.params.len() - self.other_loads.len();
        self.other_loads.get(k.checked_sub(first)?).map(|(l, _)| *l)
    }

    /// The index of the STE parameter of a load whose low-speed part joined the fit.
    fn other_ste_param(&self, load_n: f64) -> Option<usize> {
        let first = self.estimate.params.len() - self.other_loads.len();
        self.other_loads
            .iter()
            .position(|(l, _)| crate::data::same_load(*l, load_n))
            .map(|k| first + k)
    }
}

/// What the set says of its noise (see `validate::munro`'s choice of it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MunroNoise {
    /// Estimated jointly with the fit, the floor at least `floor_min` (a reading uncertainty).
    Estimate { floor_min: f64 },
    /// Stated in rig.toml.
    Stated(NoiseModel),
    /// Stated per point (`dte_pp_sd_um`; every point has one).
    PerPoint,
}

/// How a fit treats the errors' correlation along speed within a curve
/// (docs/correlated-errors.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CorrelationChoice {
    /// Estimated, and kept when the data reject independent errors (the default).
    Auto,
    /// Independent errors (`--correlation off`).
    Off,
    /// Always estimated (`--correlation on`).
    On,
    /// Stated (rig.toml `[noise] correlation_rpm`), rpm; 0 is independent errors.
    Stated(f64),
}

impl CorrelationChoice {
    /// The engine's setting on the fit's points `axis`.
    pub fn setting(self, axis: Axis) -> CorrelationSetting {
        match self {
            CorrelationChoice::Auto => CorrelationSetting::Auto(axis),
            CorrelationChoice::Off => CorrelationSetting::Stated(axis, 0.0),
            CorrelationChoice::On => CorrelationSetting::Estimated(axis),
            CorrelationChoice::Stated(l) => CorrelationSetting::Stated(axis, l),
        }
    }
}

/// How a fit treats its errors: their tails and their correlation along speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorChoice {
    pub robust: Robust,
    pub correlation: CorrelationChoice,
}

/// pp DTE of eq. 13 at each point for (zeta, omega_n, STE).
fn linear_curve(dim: &Dimensional, points: &[&MunroPoint], zeta: f64, wn: f64, e: f64) -> Vec<f64> {
    points
        .iter()
        .map(|pt| dte_pp_um(e, zeta, dim.omega(pt.speed_rpm, wn)))
        .collect()
}

/// Omega up to which a curve's points count as its low-speed part: well below the resonance
/// (|H_x| < 1.6 for any damping), where the pp DTE is the STE times the quasi-static gain.
pub const LOW_SPEED_OMEGA: f64 = 0.6;

/// The low-speed part of a curve at (zeta, omega_n): points with Omega <= [`LOW_SPEED_OMEGA`]
/// where the linear model with the STE read off its first point keeps the teeth in contact (an
/// STE that separates the teeth makes the curve nonlinear there). Empty with fewer than 3.
fn low_speed_part<'a>(
    dim: &Dimensional,
    points: &[&'a MunroPoint],
    load_n: f64,
    zeta: f64,
    wn: f64,
) -> Vec<&'a MunroPoint> {
    let fm = dim.mean_force(load_n);
    let Some(first) = points.first() else {
        return Vec::new();
    };
    let e0 = (first.dte_pp_um / 2.0).max(1e-3);
    let part: Vec<&MunroPoint> = points
        .iter()
        .copied()
        .filter(|p| {
            let om = dim.omega(p.speed_rpm, wn);
            om <= LOW_SPEED_OMEGA && stays_in_contact(fm, dim.ste_amplitude(e0), zeta, om)
        })
        .collect();
    if part.len() < 3 {
        Vec::new()
    } else {
        part
    }
}

/// `zeta` as a fit through simulated sweeps takes it: its profile goes no lower than where
/// [`swept_curve`] is trusted ([`SWEPT_ZETA_FLOOR`]), so that an interval reaching the floor
/// is unbounded below and the fit refused ([`super::fit_check::fit_failure`]), as a fit ending
/// there is.
fn swept_zeta(zeta: &Param) -> Param {
    zeta.clone().with_profile_floor(SWEPT_ZETA_FLOOR)
}

/// pp DTE of the exact solver's up-sweep at each point for (zeta, omega_n) and the STE
/// harmonics `ste` (order, amplitude um, phase rad) at mean force `fm`
/// ([`DesignModel::Swept`]; one term (1, e, 0) is the paper's model). A damping below
/// [`SWEPT_ZETA_MIN`] is refused: its transients would make each sweep take minutes.
fn swept_curve(
    dim: &Dimensional,
    points: &[&MunroPoint],
    fm: f64,
    (zeta, wn): (f64, f64),
    ste: &[(u32, f64, f64)],
) -> Result<Vec<f64>> {
    if zeta.is_nan() || zeta < SWEPT_ZETA_MIN {
        return Err(GearError::Numerical(format!(
            "zeta = {zeta} is below the least damping a fit through simulated sweeps takes ({SWEPT_ZETA_MIN})"
        )));
    }
    let model = GearPair {
        zeta,
        mean_force: fm,
        omega: 1.0,
        ste: dim.ste_terms(ste),
        torque: Vec::new(),
        stiffness: Vec::new(),
    }
    .validated()?;
    let speeds: Vec<f64> = points.iter().map(|p| p.speed_rpm).collect();
    up_sweep_pp_um(dim, &model, wn, &speeds)
}

/// Whether eq. 13 keeps the teeth in contact at every point of a curve at mean force `fm`
/// (dimensionless) for (zeta, omega_n, STE um).
pub(super) fn curve_in_contact(
    dim: &Dimensional,
    fm: f64,
    points: &[&MunroPoint],
    (zeta, wn, ste_um): (f64, f64, f64),
) -> bool {
    points.iter().all(|pt| {
        stays_in_contact(
            fm,
            dim.ste_amplitude(ste_um),
            zeta,
            dim.omega(pt.speed_rpm, wn),
        )
    })
}

/// [`curve_in_contact`] for an STE of several harmonics (order, e_j um, phase rad), by the
/// triangle-inequality bound of [`stays_in_contact_harmonics`].
pub(super) fn curve_in_contact_harmonics(
    dim: &Dimensional,
    fm: f64,
    points: &[&MunroPoint],
    (zeta, wn): (f64, f64),
    ste_um: &[(u32, f64, f64)],
) -> bool {
    let bound: Vec<(u32, f64)> = dim
        .ste_terms(ste_um)
        .iter()
        .map(|t| (t.order, t.amplitude))
        .collect();
    points
        .iter()
        .all(|pt| stays_in_contact_harmonics(fm, &bound, zeta, dim.omega(pt.speed_rpm, wn)))
}

/// The curves of a fit: the design load's, and the low-speed parts of the others.
struct Curves<'a> {
    dim: &'a Dimensional,
    /// Mean force at the design load (dimensionless), for [`DesignModel::Swept`].
    design_fm: f64,
    design: &'a [&'a MunroPoint],
    design_model: DesignModel,
    others: Vec<Vec<&'a MunroPoint>>,
}

impl Curves<'_> {
    fn model(&self, p: &[f64]) -> Result<Vec<f64>> {
        let (zeta, wn) = (p[0], p[1]);
        let ste = p[2];
        let mut v = match self.design_model {
            DesignModel::Linear => linear_curve(self.dim, self.design, zeta, wn, ste),
            DesignModel::Swept => swept_curve(
                self.dim,
                self.design,
                self.design_fm,
                (zeta, wn),
                &[(1, ste, 0.0)],
            )?,
        };
        for (k, pts) in self.others.iter().enumerate() {
            v.extend(linear_curve(self.dim, pts, zeta, wn, p[3 + k]));
        }
        Ok(v)
    }

    /// Whether the fit `p` keeps the design load's teeth in contact at every measured speed
    /// under eq. 13.
    fn design_in_contact(&self, p: &[f64]) -> bool {
        curve_in_contact(self.dim, self.design_fm, self.design, (p[0], p[1], p[2]))
    }

    fn points(&self) -> impl Iterator<Item = &&MunroPoint> {
        self.design.iter().chain(self.others.iter().flatten())
    }

    /// The engine's noise setting for these points.
    fn noise(&self, noise: MunroNoise) -> NoiseSetting {
        match noise {
            MunroNoise::Estimate { floor_min } => NoiseSetting::Estimate(NoiseFreedom {
                floor_min,
                relative: true,
            }),
            MunroNoise::Stated(m) => NoiseSetting::Stated(m),
            MunroNoise::PerPoint => {
                NoiseSetting::PerPoint(self.points().map(|p| p.sd_um.unwrap_or(1.0)).collect())
            }
        }
    }

    fn data(&self) -> Vec<f64> {
        self.design
            .iter()
            .chain(self.others.iter().flatten())
            .map(|p| p.dte_pp_um)
            .collect()
    }

    /// The points' curves (the design load 0, the others 1, 2, ...) and speeds.
    fn axis(&self) -> Result<Axis> {
        let curves = std::iter::once(self.design).chain(self.others.iter().map(|c| c.as_slice()));
        let (curve, speed) = curves
            .enumerate()
            .flat_map(|(k, c)| c.iter().map(move |p| (k, p.speed_rpm)))
            .unzip();
        Axis::new(curve, speed)
    }

    /// The engine's settings for these points.
    fn options(
        &self,
        (noise, errors): (MunroNoise, ErrorChoice),
        stop: Stop,
        (starts, measurements): (Vec<Vec<f64>>, Vec<Measurement>),
    ) -> Result<EstimateOptions> {
        Ok(EstimateOptions {
            noise: self.noise(noise),
            correlation: errors.correlation.setting(self.axis()?),
            robust: errors.robust,
            stop,
            starts,
            noise_start: None,
            measurements,
        })
    }
}

/// Fit zeta, omega_n and the STE amplitude to the design-load curve
/// `design`, where the teeth stay in contact and eq. 13 is exact. The low-speed parts of the
/// curves at `others` (load, points, the STE rig.toml states there with its uncertainty, if
/// any: a measurement of that load's amplitude, as `stated_ste` is of the design load's) join the fit with an STE amplitude each: the same
/// instrument measured them, and their levels (several um, where the design load's curve is
/// near its floor everywhere but at a resonance of a handful of points) are what determines the
/// relative part of the noise. Their selection (Omega <= [`LOW_SPEED_OMEGA`], in contact)
/// uses a first fit of the design load alone. Starts: resonance at the measured peak and 10%
/// either side, damping light to heavy; STE from each curve's low-speed end.
///
/// Where that fit separates the design load's teeth at some measured speed, eq. 13 does not
/// hold there, and the fit is made again with the design-load curve from simulated up-sweeps
/// ([`DesignModel::Swept`]), started from it.
pub fn fit_design_load(
    dim: &Dimensional,
    (design_load_n, design): (f64, &[&MunroPoint]),
    others: &[(f64, Vec<&MunroPoint>, Option<StatedSte>)],
    stated_ste: Option<StatedSte>,
    noise: (MunroNoise, ErrorChoice),
) -> Result<DesignLoadFit> {
    let peak = design
        .iter()
        .max_by(|a, b| a.dte_pp_um.total_cmp(&b.dte_pp_um))
        .map(|p| dim.mesh_frequency_hz(p.speed_rpm))
        .ok_or_else(|| GearError::Numerical("the design-load curve has no points".into()))?;
    // A stated STE is a measurement of the fitted STE (parameter 2).
    let mut measurements: Vec<Measurement> = stated_ste
        .map(|s| Measurement {
            param: 2,
            value: s.amplitude_um,
            sd: s.sd_um,
        })
        .into_iter()
        .collect();
    let e0 = measurements
        .first()
        .map_or((design[0].dte_pp_um / 2.0).max(1e-3), |m| m.value);
    let mut params = vec![
        Param::positive("zeta", 0.03),
        Param::positive("omega_n_hz", peak),
        Param::positive("ste_um", e0),
    ];
    let starts = [0.01, 0.03, 0.08]
        .into_iter()
        .flat_map(|z| [0.9, 1.0, 1.1].map(|f| vec![z, peak * f, e0]))
        .collect();
    let stop = Stop::converged(FIT_JACOBIANS).central();
    let alone = Curves {
        dim,
        design_fm: dim.mean_force(design_load_n),
        design,
        design_model: DesignModel::Linear,
        others: Vec::new(),
    };
    let run =
        |c: &Curves, params: &[Param], starts: Vec<Vec<f64>>, stop: Stop, m: &[Measurement]| {
            let model = |p: &[f64]| c.model(p);
            let opts = c.options(noise, stop, (starts, m.to_vec()))?;
            estimate(&model, &c.data(), params, &opts)
        };
    let first = run(&alone, &params, starts, stop, &measurements)?;
    let (zeta, wn) = (first.params[0], first.params[1]);
    let mut joined = Curves {
        others: Vec::new(),
        ..alone
    };
    let mut other_loads = Vec::new();
    let mut start = first.params.clone();
    for (load, pts, stated) in others {
        let part = low_speed_part(dim, pts, *load, zeta, wn);
        if part.is_empty() {
            continue;
        }
        let e = match stated {
            Some(s) => {
                measurements.push(Measurement {
                    param: params.len(),
                    value: s.amplitude_um,
                    sd: s.sd_um,
                });
                s.amplitude_um
            }
            None => (part[0].dte_pp_um / 2.0).max(1e-3),
        };
        params.push(Param::positive(&format!("ste_um at {load} N"), e));
        start.push(e);
        other_loads.push((*load, part.len()));
        joined.others.push(part);
    }
    let mut estimate = if other_loads.is_empty() {
        first
    } else {
        run(&joined, &params, vec![start], stop, &measurements)?
    };
    let mut profile_stop = stop;
    if !joined.design_in_contact(&estimate.params) {
        joined.design_model = DesignModel::Swept;
        let swept = Stop::converged(SWEPT_JACOBIANS).central();
        params[0] = swept_zeta(&params[0]);
        estimate = run(
            &joined,
            &params,
            vec![estimate.params.clone()],
            swept.or_stalled(SWEPT_FIT_STALL),
            &measurements,
        )?;
        profile_stop = swept.or_stalled(SWEPT_PROFILE_STALL);
    }
    let model = |p: &[f64]| joined.model(p);
    let y = joined.data();
    let ci95_profile = (0..3)
        .map(|i| profile_interval(&model, &y, &estimate, i, profile_stop))
        .collect::<Result<Vec<_>>>()?;
    Ok(DesignLoadFit {
        estimate,
        ci95_profile,
        other_loads,
        design_points: design.len(),
        design_model: joined.design_model,
    })
}

/// The design-load fit of the geometry path (`validate munro --ste geometry`): zeta, omega_n
/// and, when `relief.1` is true, the relief depth (um, started at `relief.0`) fitted to the
/// design-load curve alone, its STE harmonics (order, e_j um, phi_j) given by `ste_at(depth)`
/// (the tooth-contact model) and the pp DTE by the multi-harmonic form of eq. 13
/// ([`dte_pp_um_harmonics`]). With `relief.1` false the depth is `relief.0` (the design rule's,
/// or given) and only zeta and omega_n are fitted. Same engine, noise setting and starts as
/// [`fit_design_load`] (three depths, 0.7, 1 and 1.4 times the start, when it is fitted), and
/// as there, where that fit separates the teeth (`design_fm`: the design load's mean force,
/// dimensionless), the fit again through simulated up-sweeps ([`DesignModel::Swept`]).
pub fn fit_design_geometry(
    dim: &Dimensional,
    (design_fm, design): (f64, &[&MunroPoint]),
    ste_at: &(dyn Fn(f64) -> Result<Vec<(u32, f64, f64)>> + Sync),
    relief: (f64, bool),
    noise: (MunroNoise, ErrorChoice),
) -> Result<DesignLoadFit> {
    let peak = design
        .iter()
        .max_by(|a, b| a.dte_pp_um.total_cmp(&b.dte_pp_um))
        .map(|p| dim.mesh_frequency_hz(p.speed_rpm))
        .ok_or_else(|| GearError::Numerical("the design-load curve has no points".into()))?;
    let (depth, fit_depth) = relief;
    let mut params = vec![
        Param::positive("zeta", 0.03),
        Param::positive("omega_n_hz", peak),
    ];
    if fit_depth {
        params.push(Param::positive("tip_relief_um", depth.max(1e-3)));
    }
    let mut starts = Vec::new();
    let depths: &[f64] = if fit_depth { &[0.7, 1.0, 1.4] } else { &[1.0] };
    for z in [0.01, 0.03, 0.08] {
        for f in [0.9, 1.0, 1.1] {
            for d in depths {
                let mut s = vec![z, peak * f];
                if fit_depth {
                    s.push((depth * d).max(1e-3));
                }
                starts.push(s);
            }
        }
    }
    let fixed = if fit_depth {
        None
    } else {
        Some(ste_at(depth)?)
    };
    let ste_of = |p: &[f64]| -> Result<Vec<(u32, f64, f64)>> {
        match &fixed {
            Some(s) => Ok(s.clone()),
            None => ste_at(p[2]),
        }
    };
    let closed_form = |p: &[f64]| -> Result<Vec<f64>> {
        let ste = ste_of(p)?;
        Ok(design
            .iter()
            .map(|pt| dte_pp_um_harmonics(&ste, p[0], dim.omega(pt.speed_rpm, p[1])))
            .collect())
    };
    let swept = |p: &[f64]| swept_curve(dim, design, design_fm, (p[0], p[1]), &ste_of(p)?);
    // Only the data and the noise setting of the curves are used: the model is `closed_form`
    // or `swept`.
    let curves = Curves {
        dim,
        design_fm,
        design,
        design_model: DesignModel::Linear,
        others: Vec::new(),
    };
    let y = curves.data();
    let options =
        |stop: Stop, starts: Vec<Vec<f64>>| curves.options(noise, stop, (starts, Vec::new()));
    let stop = Stop::converged(FIT_JACOBIANS).central();
    let mut fit = estimate(&closed_form, &y, &params, &options(stop, starts)?)?;
    let mut design_model = DesignModel::Linear;
    let mut profile_stop = stop;
    // As `fit_design_load`: where the closed form separates the teeth somewhere, it does not
    // hold there, and the curve is fitted again through the exact solver's up-sweeps.
    let fitted = (fit.params[0], fit.params[1]);
    if !curve_in_contact_harmonics(dim, design_fm, design, fitted, &ste_of(&fit.params)?) {
        design_model = DesignModel::Swept;
        let sweeps = Stop::converged(SWEPT_JACOBIANS).central();
        let start = vec![fit.params.clone()];
        params[0] = swept_zeta(&params[0]);
        fit = estimate(
            &swept,
            &y,
            &params,
            &options(sweeps.or_stalled(SWEPT_FIT_STALL), start)?,
        )?;
        profile_stop = sweeps.or_stalled(SWEPT_PROFILE_STALL);
    }
    let model = |p: &[f64]| match design_model {
        DesignModel::Linear => closed_form(p),
        DesignModel::Swept => swept(p),
    };
    let ci95_profile = (0..params.len())
        .map(|i| profile_interval(&model, &y, &fit, i, profile_stop))
        .collect::<Result<Vec<_>>>()?;
    Ok(DesignLoadFit {
        estimate: fit,
        ci95_profile,
        other_loads: Vec::new(),
        design_points: design.len(),
        design_model,
    })
}
