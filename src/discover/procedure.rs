//! The discovery run, step by step, as the module's notes (`super`) and
//! docs/discover-method.md describe it; the bootstrap is [`super::calibration`]'s.

use super::calibration::{self, Columns, ErrorModel, NullModel, Replicate};
use super::compare::{far_from, gap, held_mask, make_mask, residual_curves, split, Mask};
use super::effects::{Candidate, Effect, LIBRARY};
use super::forward::{
    aperiodic_pp_range, fitted_damping_admissible, predict, CurvePrediction, Globals, Setup,
};
use super::noise::{DiscoveryNoise, NoiseOrigin, Scales};
use super::result::{
    check_options, CandidateResult, DiscoverOptions, Discovery, ExcludedPoints, GapSet, PowerBound,
    PredictionCheck, TestResult,
};
use super::start::{fit_ste, linear_start, ste_from_low_speed};
use super::stats::{bootstrap_p, holm};
use super::training::{Correlation, Curves, EffectParams, Family, Scale};
use super::windows::windows;
use crate::data::MunroData;
use crate::error::{GearError, Result};
use crate::fit::{
    profile_interval_or_better, Distribution, Estimate, EstimateOptions, NoiseModel, NoiseSetting,
    Profiled, Robust, Stop,
};
use crate::numeric::{chi_square_power, min_max};
use crate::progress::Progress;
use crate::validate::MunroNoise;
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::f64::consts::FRAC_PI_2;

/// Starts at most of a phase-carrying candidate's fit ([`starts_of`]).
const PHASE_STARTS: usize = 3;
/// Phases of two starts differ by more than this (rad): half the probes' phase step of 60
/// degrees, so that starts come from different probe phases.
const PHASE_APART: f64 = 0.5;

/// Jacobians at most, and the gain (sigma^2 over three Jacobians) below which a fit through
/// simulated sweeps stops: as `validate munro`'s swept fits.
fn fit_stop() -> Stop {
    Stop::converged(40).or_stalled(1e-3)
}

/// The run's error family before M0's fit: the scale as the options or the set state it, the
/// tails and the correlation as the options say; and the report's words for where the noise
/// came from.
fn family_of(setup: &Setup, opts: &DiscoverOptions) -> (Family, NoiseOrigin) {
    let (scale, origin) = match (opts.noise_um, &setup.noise) {
        (Some(s), _) => (
            Scale::Stated(NoiseModel::constant(s)),
            NoiseOrigin::StatedOption,
        ),
        (None, MunroNoise::Stated(m)) => (Scale::Stated(*m), NoiseOrigin::StatedRig),
        (None, MunroNoise::PerPoint) => (Scale::PerPoint, NoiseOrigin::PerPoint),
        (None, &MunroNoise::Estimate { floor_min }) => (
            Scale::Estimated { floor_min },
            NoiseOrigin::Fitted { floor_min },
        ),
    };
    // A length stated in rig.toml [noise] is the set's statement, as in validate munro.
    let correlation = match (&scale, opts.correlation) {
        (Scale::Stated(m), Correlation::Auto) if m.correlation_length > 0.0 => {
            Correlation::Stated(m.correlation_length)
        }
        (_, c) => c,
    };
    let family = Family {
        scale,
        robust: match opts.tails {
            super::noise::TailChoice::Gaussian => Robust::Off,
            super::noise::TailChoice::Auto => Robust::Auto,
        },
        correlation,
    };
    (family, origin)
}

/// M0 on the training loads, with what every later step is measured against.
struct NullFit<'a> {
    curves: Curves<'a>,
    est: Estimate,
    /// The run's family, its automatic choices made by this fit.
    family: Family,
    /// Every curve's prediction (held-out ones with their STE fitted alone) and STE (um).
    preds: Vec<CurvePrediction>,
    ste: Vec<f64>,
    globals: Globals,
    /// The noise at every point at M0's levels.
    noise: DiscoveryNoise,
    scales: Scales,
    /// M0's prediction of the held-out loads, where there are any.
    held: Option<HeldPrediction>,
    /// M0's held-out fits and the points each was made on.
    held_fits: Vec<HeldFit>,
}

/// A held-out fit and the points of its curve it was made on: a comparison on the same points
/// takes it as it is (the same start and points give the same fit).
type HeldFit = (Vec<bool>, HeldOut);

/// M0's prediction of the held-out loads on their compared points ([`held_mask`]): its
/// discrepancy ([`calibration::held_discrepancy`], each STE fitted alone under the training
/// loads' noise) and its linearisation.
struct HeldPrediction {
    deviance: f64,
    linear: calibration::HeldLinear,
}

/// Zeta, omega_n and each training STE to start M0 from: eq. 13's closed form at the design
/// load, the quasi-static end of every other curve.
fn null_start(setup: &Setup, train: &[usize]) -> Result<Vec<f64>> {
    let (g, e0) = linear_start(setup, train[0])?;
    let mut start = vec![g.zeta, g.omega_n_hz, e0];
    start.extend(train[1..].iter().map(|&i| ste_from_low_speed(setup, i, g)));
    Ok(start)
}

/// The first fit's weights: the stated noise, or a constant from the curves' second
/// differences (Gasser et al. 1986), which a jump hardly moves.
fn first_family(setup: &Setup, family: &Family) -> Result<Family> {
    let scale = match &family.scale {
        Scale::Estimated { floor_min } => {
            let measured: Vec<Vec<f64>> =
                setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
            let s = super::stats::noise_from_differences(&measured)
                .filter(|s| *s > 0.0)
                .ok_or_else(|| {
                    GearError::Numerical("cannot estimate the noise from the curves".into())
                })?;
            Scale::Stated(NoiseModel::constant(s.max(*floor_min)))
        }
        s => s.clone(),
    };
    Ok(Family {
        scale,
        robust: Robust::Off,
        correlation: Correlation::Stated(0.0),
    })
}

/// The noise of a fit as the mask and the held-out loads' STE scans weigh the points: its
/// scale at each level ([`DiscoveryNoise::scale_at`]), or the stated scales.
fn discovery_noise(setup: &Setup, origin: NoiseOrigin, model: NoiseModel) -> DiscoveryNoise {
    let model = NoiseModel {
        distribution: Distribution::Gaussian,
        ..model
    };
    match origin {
        NoiseOrigin::PerPoint => DiscoveryNoise::per_point(
            setup
                .curves
                .iter()
                .map(|c| {
                    c.sd_um
                        .clone()
                        .unwrap_or_else(|| vec![1.0; c.speeds_rpm.len()])
                })
                .collect(),
        ),
        o => DiscoveryNoise::stated(o, model),
    }
}

/// Every curve predicted at M0's globals: training ones with their fitted STE, held-out ones
/// from their quasi-static end.
fn rough_predictions(
    setup: &Setup,
    train: &[usize],
    g: Globals,
    ste: &[f64],
) -> Result<Vec<CurvePrediction>> {
    (0..setup.curves.len())
        .into_par_iter()
        .map(|i| {
            let e = train
                .iter()
                .position(|&t| t == i)
                .map_or_else(|| ste_from_low_speed(setup, i, g), |k| ste[k].abs());
            predict(setup, i, g, e, &Effect::none())
        })
        .collect()
}

/// M0 on the points of `mask` from the parameters of `previous`, from equal weights and from
/// `previous`'s fitted noise, the larger likelihood kept: where M0 misfits, which of its
/// likelihood's maxima a fit reaches depends on its first weights (as for [`fit_candidate`]).
fn fit_m0(
    setup: &Setup,
    train: &[usize],
    mask: &Mask,
    previous: &Estimate,
    family: &Family,
) -> Result<Estimate> {
    let curves = Curves::new(setup, train, mask, EffectParams::None);
    let axis = curves.axis()?;
    let from = |noise| curves.fit(vec![previous.params.clone()], family, fit_stop(), noise);
    let (equal, previous_noise) = rayon::join(|| from(None), || from(Some(previous.noise.model)));
    best_of(equal, previous_noise, &axis)
}

/// Fit M0: on every point under the first weights; the mask from that fit (points not
/// period-1, jumps); again on the kept points under the run's family; the mask once more from
/// that fit's noise, and a last fit if it moved.
fn fit_null<'a>(
    setup: &'a Setup,
    (train, held): (&[usize], &[usize]),
    family: &Family,
    origin: &NoiseOrigin,
    masks: &'a mut [Mask; 2],
) -> Result<NullFit<'a>> {
    let every: Vec<usize> = (0..setup.curves.len()).collect();
    let all: Mask = setup
        .curves
        .iter()
        .map(|c| vec![true; c.speeds_rpm.len()])
        .collect();
    let all_curves = Curves::new(setup, train, &all, EffectParams::None);
    // Every curve's predictions at a fit and the mask they and its noise make.
    let mask_of = |est: &Estimate| -> Result<(Vec<CurvePrediction>, Mask)> {
        let (g, ste, _) = all_curves.unpack(&est.params);
        let pre = rough_predictions(setup, train, g, &ste)?;
        let noise = discovery_noise(setup, origin.clone(), est.noise.model);
        let mask = make_mask(setup, &pre, &every, &noise)?;
        Ok((pre, mask))
    };
    let first = first_family(setup, family)?;
    let pass1 = all_curves.fit(vec![null_start(setup, train)?], &first, fit_stop(), None)?;
    masks[0] = mask_of(&pass1)?.1;
    let est = fit_m0(setup, train, &masks[0], &pass1, family)?;
    let pre;
    (pre, masks[1]) = mask_of(&est)?;
    let [m0_mask, m1_mask] = masks;
    let mask: &'a Mask = m1_mask;
    let est = if *mask == *m0_mask {
        est
    } else {
        fit_m0(setup, train, mask, &est, family)?
    };
    let curves = Curves::new(setup, train, mask, EffectParams::None);
    let (globals, ste, _) = curves.unpack(&est.params);
    let family = family.chosen_by(&est);
    let noise = discovery_noise(setup, origin.clone(), est.noise.model);
    let levels: Vec<Vec<f64>> = pre.iter().map(|p| p.dte_pp_um.clone()).collect();
    let scales = noise.scales(&levels);
    let mut preds = pre;
    for (k, p) in curves.predictions(&est.params)?.into_iter().enumerate() {
        preds[train[k]] = p;
    }
    let held_fits = held_out(
        setup,
        (held, mask, &scales),
        (globals, &Effect::none()),
        (&family, &est),
        None,
    )?;
    let (first_fits, held_ste) = place_held(held_fits, mask, &mut preds);
    let mut ste_all: Vec<f64> = vec![0.0; setup.curves.len()];
    let trained = train.iter().zip(&ste).map(|(&i, e)| (i, e.abs()));
    for (i, e) in trained.chain(held_ste) {
        ste_all[i] = e;
    }
    let mut null = NullFit {
        curves,
        est,
        family,
        preds,
        ste: ste_all,
        globals,
        noise,
        scales,
        held: None,
        held_fits: first_fits,
    };
    // Where M0's held-out prediction fails, the run goes on without that check (none reported).
    if !held.is_empty() {
        null.held = held_prediction(&mut null, held).ok();
    }
    Ok(null)
}

/// M0's prediction of the held-out loads on their compared points, each STE refitted there
/// (`null`'s predictions and STEs of those loads updated), with its linearisation.
fn held_prediction(null: &mut NullFit, held: &[usize]) -> Result<HeldPrediction> {
    let m0 = null.as_after(held);
    let (held_points, mut fits) = held_fits_on_common_points(null, held, &[&m0])?;
    let fits = fits.remove(0);
    let deviance = fits.iter().map(|h| h.discrepancy).sum::<f64>();
    let mut preds = m0.preds;
    let (refitted, held_ste) = place_held(fits, &held_points, &mut preds);
    let linear = held_linear(null, held, &held_points, &held_ste)?;
    null.preds = preds;
    null.held_fits = refitted;
    for &(i, e) in &held_ste {
        null.ste[i] = e;
    }
    Ok(HeldPrediction { deviance, linear })
}

impl NullFit<'_> {
    /// M0 as a fitted model's predictions are kept ([`After`]).
    fn as_after(&self, held: &[usize]) -> After {
        After {
            preds: self.preds.clone(),
            held_ste: held.iter().map(|&i| (i, self.ste[i])).collect(),
            globals: self.globals,
            effect: Effect::none(),
            held_fits: self.held_fits.clone(),
        }
    }
}

/// Each of `models`' held-out fits on the points where all of them are compared
/// ([`held_mask`]), each load's STE fitted again there from the model's own; and those points.
fn held_fits_on_common_points(
    null: &NullFit,
    held: &[usize],
    models: &[&After],
) -> Result<(Mask, Vec<Vec<HeldOut>>)> {
    let setup = null.curves.setup;
    let views: Vec<&[CurvePrediction]> = models.iter().map(|m| m.preds.as_slice()).collect();
    let mask = held_mask(setup, held, &views, &null.noise, null.curves.mask)?;
    let fits = models
        .iter()
        .map(|m| {
            let made = |i: usize| {
                m.held_fits
                    .iter()
                    .find(|(points, h)| h.curve == i && *points == mask[i])
                    .map(|(_, h)| h.clone())
            };
            let todo: Vec<usize> = held
                .iter()
                .copied()
                .filter(|&i| made(i).is_none())
                .collect();
            let mut new = held_out(
                setup,
                (&todo, &mask, &null.scales),
                (m.globals, &m.effect),
                (&null.family, &null.est),
                Some(&m.held_ste),
            )?
            .into_iter();
            Ok(held
                .iter()
                .filter_map(|&i| made(i).or_else(|| new.next()))
                .collect())
        })
        .collect::<Result<_>>()?;
    Ok((mask, fits))
}

/// Held-out log-likelihoods of `models` on their common points.
fn held_log_likelihoods(null: &NullFit, held: &[usize], models: &[&After]) -> Result<Vec<f64>> {
    let (_, fits) = held_fits_on_common_points(null, held, models)?;
    Ok(fits
        .iter()
        .map(|f| f.iter().map(|h| h.log_likelihood).sum())
        .collect())
}

/// M0's prediction of the held-out loads `held` at the points `mask` keeps, linearised at zeta,
/// omega_n and their STEs `held_ste` by central secants, whitened so that a side that changes
/// branch is told by the engine's rule ([`crate::fit::secant_jacobian`]). Zeta's and omega_n's
/// span their training standard errors, as a replicate moves them (near a fold the derivative
/// moves a point by many noise scales, the prediction little); the STEs' 1e-4 of their size.
fn held_linear(
    null: &NullFit,
    held: &[usize],
    mask: &Mask,
    held_ste: &[(usize, f64)],
) -> Result<calibration::HeldLinear> {
    let curves = Curves::new(null.curves.setup, held, mask, EffectParams::None);
    let mut p = vec![null.globals.zeta, null.globals.omega_n_hz];
    for &i in held {
        let refitted = held_ste.iter().find(|h| h.0 == i);
        p.push(refitted.map_or(null.ste[i], |h| h.1));
    }
    let f0 = curves.model(&p)?;
    let stated = match null.family.scale {
        Scale::PerPoint => curves.stated_scales(),
        _ => None,
    };
    let draw_scales: Vec<f64> = match &stated {
        Some(s) => s.clone(),
        None => f0.iter().map(|&f| null.est.noise.model.scale(f)).collect(),
    };
    let whitened =
        |v: Vec<f64>| -> Vec<f64> { v.iter().zip(&draw_scales).map(|(v, s)| v / s).collect() };
    let near =
        |q: &[f64], base: &[f64]| -> Result<Vec<f64>> { Ok(whitened(curves.near(q, base)?)) };
    let params = curves.params(&p);
    let steps: Vec<f64> = p
        .iter()
        .zip(&params)
        .enumerate()
        .map(|(k, (v, d))| {
            let engine = 1e-4 * v.abs().max(d.scale);
            match null.est.std_errors.get(k) {
                Some(&se) if k < 2 && se.is_finite() && se > engine => se,
                _ => engine,
            }
        })
        .collect();
    let zero = DMatrix::zeros(f0.len(), p.len());
    let mut jac = crate::fit::secant_jacobian(&near, &p, &whitened(f0.clone()), &steps, &zero);
    for (mut row, s) in jac.row_iter_mut().zip(&draw_scales) {
        row *= *s;
    }
    Ok(calibration::HeldLinear {
        globals: jac.columns(0, 2).into_owned(),
        ste: jac.columns(2, held.len()).into_owned(),
        ste_sd: held
            .iter()
            .map(|&i| null.curves.setup.curves[i].stated_ste.map(|s| s.1))
            .collect(),
        axis: curves.axis()?,
        f0,
        stated,
        draw_scales,
    })
}

/// The held-out loads' predictions put in place among `preds`; the fits with the points of
/// `mask` they were made on, and their STEs (curve, um).
fn place_held(
    fits: Vec<HeldOut>,
    mask: &Mask,
    preds: &mut [CurvePrediction],
) -> (Vec<HeldFit>, Vec<(usize, f64)>) {
    let ste = fits.iter().map(|h| (h.curve, h.ste_um)).collect();
    for h in &fits {
        preds[h.curve] = h.prediction.clone();
    }
    (
        fits.into_iter()
            .map(|h| (mask[h.curve].clone(), h))
            .collect(),
        ste,
    )
}

/// A held-out load predicted by a fitted model: its STE fitted alone.
#[derive(Clone)]
struct HeldOut {
    curve: usize,
    ste_um: f64,
    prediction: CurvePrediction,
    /// Log-likelihood of its kept points under the training loads' noise.
    log_likelihood: f64,
    /// M0's held-out check's discrepancy ([`calibration::held_discrepancy`]).
    discrepancy: f64,
    /// Its load's stated STE against this fit, where one is stated.
    stated: Option<crate::fit::MeasurementFit>,
}

/// Each held-out curve's STE fitted alone (a property of that load, which the training loads
/// do not predict), zeta, omega_n and the effect held at `g`, `effect`, the run's `family` at
/// M0's training fit `m0` ([`Family::held_at`]), its log-likelihood under `m0`'s distribution.
/// The start is `starts`' value where given, else [`fit_ste`]'s scan under the diagonal scales
/// `scales` (the response is not smooth in the STE: a jump moves by a grid step).
fn held_out(
    setup: &Setup,
    (held, mask, scales): (&[usize], &Mask, &Scales),
    (g, effect): (Globals, &Effect),
    (family, m0): (&Family, &Estimate),
    starts: Option<&[(usize, f64)]>,
) -> Result<Vec<HeldOut>> {
    let (family, distribution) = (&family.held_at(m0), m0.noise.model.distribution);
    held.par_iter()
        .map(|&i| {
            fitted_damping_admissible(setup, &[i], g, effect)?;
            let e = match starts.and_then(|s| s.iter().find(|h| h.0 == i)) {
                Some(&(_, e)) => e,
                None => {
                    let start = ste_from_low_speed(setup, i, g);
                    fit_ste(setup, i, mask, scales, g, effect, start)?.0
                }
            };
            let curves = Curves::ste_of(setup, i, mask, g, effect.clone());
            let est = curves.fit(vec![vec![e]], family, Stop::converged(8), None)?;
            let ste_um = est.params[0].abs();
            let axis = curves.axis()?;
            Ok(HeldOut {
                curve: i,
                ste_um,
                prediction: predict(setup, i, g, ste_um, effect)?,
                log_likelihood: calibration::log_likelihood_under(&est, &axis, distribution),
                discrepancy: calibration::held_discrepancy(&est, distribution),
                stated: est.measurements.first().copied(),
            })
        })
        .collect()
}

/// One candidate fitted to the training loads.
struct CandidateFit {
    candidate: Candidate,
    /// Its fit, or why it failed.
    est: std::result::Result<Estimate, String>,
    /// 2 (log L_c - log L_0).
    lr: f64,
    /// Whether its largest probe moves the training curves, off M0's own directions, by the
    /// noise (else it cannot be seen in these data and is not tested).
    identifiable: bool,
    note: Option<String>,
    /// Its derivative columns at delta = 0 on the kept points (um per unit of delta).
    columns: Option<DMatrix<f64>>,
}

/// M0's whitened Jacobian and its SVD: the directions M0's own parameters can move the curves
/// in, whitened by M0's noise (computed once per candidate's probes, not once per probe).
struct M0Directions {
    g: DMatrix<f64>,
    svd: nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>,
}

impl M0Directions {
    fn of(null: &NullFit) -> Self {
        let g = null
            .est
            .whitener
            .innovations_of_columns(&null.est.model_jacobian);
        M0Directions {
            svd: g.clone().svd(true, true),
            g,
        }
    }

    /// The sum of squares of `v` whitened (M0's innovations of a change of the curves) with
    /// its projection on M0's whitened Jacobian removed, what no change of M0's own parameters
    /// can do: for a change of the curves, the likelihood ratio's non-centrality; for
    /// residuals, what no move of M0's parameters fits.
    fn squares_off(&self, null: &NullFit, v: &[f64]) -> f64 {
        let x = nalgebra::DVector::from_vec(null.est.whitener.innovations(v));
        let proj = self
            .svd
            .solve(&x, 1e-10)
            .map(|beta| &self.g * beta)
            .unwrap_or_else(|_| nalgebra::DVector::zeros(x.len()));
        (x - proj).iter().map(|x| x * x).sum()
    }
}

/// A probe of a candidate at M0's other parameters (failed probes left out): how far it moves
/// the training curves, and its sum of squared innovations, both off M0's own directions (held
/// at M0's values, M0's STEs and damping would hide a strong effect they made up for).
struct Probe {
    delta: Vec<f64>,
    moved: f64,
    rss: f64,
}

fn probe_all(
    null: &NullFit,
    m0: &M0Directions,
    curves: &Curves,
    at: &(dyn Fn(Vec<f64>) -> Vec<f64> + Sync),
    c: Candidate,
) -> Vec<Probe> {
    let y = curves.data();
    let f0 = null.curves.model(&null.est.params).unwrap_or_default();
    c.probes()
        .into_par_iter()
        .filter_map(|delta| {
            let f = curves.model(&at(delta.clone())).ok()?;
            let off: Vec<f64> = f.iter().zip(&f0).map(|(a, b)| a - b).collect();
            let r: Vec<f64> = y.iter().zip(&f).map(|(y, f)| y - f).collect();
            Some(Probe {
                delta,
                moved: m0.squares_off(null, &off).sqrt(),
                rss: m0.squares_off(null, &r),
            })
        })
        .collect()
}

/// The power of the test of `effect` against M0 at `level` ([`PowerBound`]): the effect set on
/// M0's fit, its change of the training curves that M0's own parameters cannot make, to first
/// order ([`M0Directions::squares_off`]). None for M0 itself, or where the model fails there.
fn power_bound(null: &NullFit, effect: &Effect, level: f64) -> Option<PowerBound> {
    let c = effect.candidate?;
    let curves = null.curves.with_effect(EffectParams::Delta(c));
    let (_, ste, _) = null.curves.unpack(&null.est.params);
    let f0 = null.curves.model(&null.est.params).ok()?;
    let f = curves
        .model(&curves.pack(null.globals, &ste, effect))
        .ok()?;
    let change: Vec<f64> = f.iter().zip(&f0).map(|(a, b)| a - b).collect();
    let lambda = M0Directions::of(null).squares_off(null, &change);
    Some(PowerBound {
        candidate: c.name().to_string(),
        delta: effect.delta.clone(),
        noncentrality: lambda,
        level,
        power: chi_square_power(c.dim() as f64, lambda, level)?,
    })
}

/// Candidate `c` fitted from its best probes ([`starts_of`]) and, where needed, from M0.
fn fit_candidate(null: &NullFit, c: Candidate, l0: f64, axis: &crate::fit::Axis) -> CandidateFit {
    let curves = null.curves.with_effect(EffectParams::Delta(c));
    let (_, ste, _) = null.curves.unpack(&null.est.params);
    let at = |delta: Vec<f64>| curves.pack(null.globals, &ste, &Effect::of(c, delta));
    let m0 = M0Directions::of(null);
    let probes = probe_all(null, &m0, &curves, &at, c);
    let moved = probes.iter().map(|p| p.moved).fold(0.0, f64::max);
    let starts = starts_of(null, &m0, &probes, c);
    // A candidate that no probe lets change the curves by a tenth of the noise beyond M0's own
    // parameters cannot reach a likelihood ratio of 0.01: it is reported, not tested.
    let identifiable = moved >= 0.1;
    let note = (!identifiable).then(|| {
        format!(
            "not identifiable: its largest probe changes the training curves by {moved:.2} \
             noise standard deviations beyond what M0's own parameters can do{}",
            if c == Candidate::Backlash {
                "; in contact or with single-sided impacts the response in um does not depend on b"
            } else {
                ""
            }
        )
    });
    // The probes' fits begin at equal weights, as M0's own first fit did (their basins are
    // the probes'); the fit from M0 begins at M0's fitted noise, where M0 ended.
    let fit = |starts: Vec<Vec<f64>>, noise_start: Option<NoiseModel>| -> Result<Estimate> {
        starts
            .into_par_iter()
            .map(|d| curves.fit(vec![at(d)], &null.family, fit_stop(), noise_start))
            .reduce_with(|a, b| best_of(a, b, axis))
            .unwrap_or_else(|| Err(GearError::Numerical("no start".into())))
    };
    // The candidate holds M0 (delta 0), so its fit must reach M0's likelihood: where its starts
    // ended below it, or began at M0 (then side by side), it is fitted from M0 at M0's noise too
    // and the larger likelihood kept, as heavy tails give the likelihood several maxima.
    let from_m0 = || fit(vec![vec![0.0; c.dim()]], Some(null.est.noise.model));
    let from_zero = starts.iter().all(|d| d.iter().all(|v| *v == 0.0));
    let est = if from_zero {
        let (probed, from_m0) = rayon::join(|| fit(starts, None), from_m0);
        best_of(probed, from_m0, axis)
    } else {
        let probed = fit(starts, None);
        let short = probed
            .as_ref()
            .map_or(true, |e| calibration::log_likelihood(e, axis) < l0);
        if short {
            best_of(probed, from_m0(), axis)
        } else {
            probed
        }
    };
    let est = est.map_err(|e| e.to_string());
    let lr = est.as_ref().map_or(f64::NAN, |e| {
        2.0 * (calibration::log_likelihood(e, axis) - l0)
    });
    let columns = identifiable
        .then(|| candidate_columns(&curves, &at, c).ok())
        .flatten();
    CandidateFit {
        candidate: c,
        est,
        lr,
        identifiable,
        note,
        columns,
    }
}

/// Starts of a candidate's fit: its best probes where they fit better than M0, else M0 itself.
/// A phase-carrying candidate gets up to [`PHASE_STARTS`] in different phases, one more than a
/// quarter turn from the best where such a probe fits better than M0: the damping and STEs can
/// make up for a wrong phase, leaving several phase basins. Each start is its own fit, the
/// largest likelihood kept (the engine would compare several starts under equal weights).
fn starts_of(null: &NullFit, m0: &M0Directions, probes: &[Probe], c: Candidate) -> Vec<Vec<f64>> {
    let m0_rss = m0.squares_off(null, &null.est.residuals);
    let mut better: Vec<&Probe> = probes.iter().filter(|p| p.rss < m0_rss).collect();
    better.sort_by(|a, b| a.rss.total_cmp(&b.rss));
    let Some(first) = better.first() else {
        return vec![vec![0.0; c.dim()]];
    };
    if !c.has_phase() {
        return vec![first.delta.clone()];
    }
    let phase_of = |p: &Probe| Candidate::phase_distance(&p.delta, &first.delta);
    let mut starts = vec![first.delta.clone()];
    if let Some(far) = better.iter().find(|p| phase_of(p) > FRAC_PI_2) {
        starts.push(far.delta.clone());
    }
    for p in &better {
        if starts.len() >= PHASE_STARTS {
            break;
        }
        if starts
            .iter()
            .all(|s| Candidate::phase_distance(&p.delta, s) > PHASE_APART)
        {
            starts.push(p.delta.clone());
        }
    }
    starts
}

/// The better of two fits by their likelihood on `axis` (a failed one loses).
fn best_of(a: Result<Estimate>, b: Result<Estimate>, axis: &crate::fit::Axis) -> Result<Estimate> {
    match (a, b) {
        (Ok(x), Ok(y)) => Ok(
            if calibration::log_likelihood(&y, axis) > calibration::log_likelihood(&x, axis) {
                y
            } else {
                x
            },
        ),
        (Ok(x), Err(_)) | (Err(_), Ok(x)) => Ok(x),
        (Err(e), Err(_)) => Err(e),
    }
}

/// The candidate's derivative columns at delta = 0 (central differences over its typical
/// size, each side continuing M0's sweep).
fn candidate_columns(
    curves: &Curves,
    at: &(dyn Fn(Vec<f64>) -> Vec<f64> + Sync),
    c: Candidate,
) -> Result<DMatrix<f64>> {
    let base = at(vec![0.0; c.dim()]);
    curves.model(&base)?;
    let h = c.scale();
    let cols: Vec<Vec<f64>> = (0..c.dim())
        .into_par_iter()
        .map(|k| {
            let side = |s: f64| {
                let mut d = vec![0.0; c.dim()];
                d[k] = s * h;
                curves.near(&at(d), &base)
            };
            let (plus, minus) = (side(1.0)?, side(-1.0)?);
            Ok(plus
                .iter()
                .zip(&minus)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect())
        })
        .collect::<Result<_>>()?;
    let n = cols.first().map_or(0, Vec::len);
    Ok(DMatrix::from_fn(n, c.dim(), |i, k| cols[k][i]))
}

/// The named effect's size and its 95% profile-likelihood interval (Wald where the profile
/// fails), with the phase's Wald arc (degrees) for a phase-carrying candidate, set in `r`.
fn named_size(null: &NullFit, c: Candidate, est: &Estimate, r: &mut CandidateResult) -> Result<()> {
    let delta_curves = null.curves.with_effect(EffectParams::Delta(c));
    let (g, ste, effect) = delta_curves.unpack(&est.params);
    let curves = null.curves.with_effect(EffectParams::Profiled(c));
    let polar = curves.fit(
        vec![curves.pack(g, &ste, &effect)],
        &null.family,
        fit_stop(),
        Some(est.noise.model),
    )?;
    let k = 2 + curves.idx.len();
    let u = polar.params[k];
    let to_estimate = |(a, b): (f64, f64)| {
        let (x, y) = (c.estimate_of_profiled(a), c.estimate_of_profiled(b));
        (x.min(y), x.max(y))
    };
    let wald = to_estimate(polar.ci95[k]);
    let model = |p: &[f64]| curves.model(p);
    let near = |p: &[f64], base: &[f64]| curves.near(p, base);
    let profile = match profile_interval_or_better(
        &model,
        Some(&near),
        &curves.data(),
        &polar,
        k,
        fit_stop(),
        None,
    ) {
        Ok(Profiled::Interval(p)) => Some(p),
        _ => None,
    };
    let mapped = |(lo, hi): (Option<f64>, Option<f64>)| {
        (
            lo.map(|v| c.estimate_of_profiled(v)),
            hi.map(|v| c.estimate_of_profiled(v)),
        )
    };
    (r.ci95, r.ci95_method) = match &profile {
        Some(p) => {
            let (lo, hi) = mapped(p.ends());
            let floor = if c.has_phase() { 0.0 } else { -f64::INFINITY };
            (
                Some((lo.unwrap_or(floor), hi.unwrap_or(f64::INFINITY))),
                // A side whose profile steps, or whose inner fits fail, ends at Wald's end
                // (fit::profile); the method says so.
                if p.stepped.contains(&true) {
                    "profile likelihood, a side at Wald's end (its profile steps or cannot be fitted there)"
                } else {
                    "profile likelihood"
                },
            )
        }
        None => (Some(wald), "Wald"),
    };
    r.estimate = Some(c.estimate_of_profiled(u));
    r.wald_ci95 = Some(wald);
    r.profile_ci95 = profile.map(|p| mapped(p.ends()));
    if c.has_phase() {
        let (lo, hi) = polar.ci95[k + 1];
        r.phase_deg = Some(polar.params[k + 1].to_degrees());
        r.phase_wald95_deg = Some((lo.to_degrees(), hi.to_degrees()));
    }
    Ok(())
}

/// Run the discovery on a Munro-style data set (docs/discover-method.md). Reads the curves and
/// the rig's stated geometry only: never `[source.truth]`.
pub fn discover(
    data: &MunroData,
    opts: &DiscoverOptions,
    progress: &dyn Progress,
) -> Result<Discovery> {
    check_options(opts)?;
    let setup = Setup::from_munro(data)?;
    discover_setup(&setup, opts, progress)
}

/// [`discover`] on an already built setup.
pub fn discover_setup(
    setup: &Setup,
    opts: &DiscoverOptions,
    progress: &dyn Progress,
) -> Result<Discovery> {
    check_options(opts)?;
    let (train, held) = split(setup.curves.len());
    // Each stage its own job, named: their lengths differ by a hundredfold, so that one count
    // over all of them would promise an end it cannot keep.
    progress.start(1, "discovery, M0 fitted to the training loads");
    let (family, origin) = family_of(setup, opts);
    let mut masks: [Mask; 2] = [Vec::new(), Vec::new()];
    let null = fit_null(setup, (&train, &held), &family, &origin, &mut masks).map_err(|e| {
        GearError::Numerical(format!(
            "the null model M0 failed in its fit to the training loads, so nothing can be \
             tested against it: {e}"
        ))
    })?;
    progress.advance(1);
    let axis = null.curves.axis()?;
    let l0 = calibration::log_likelihood(&null.est, &axis);
    progress.start(LIBRARY.len() as u64, "discovery, candidates fitted");
    // The candidates' fits are independent: side by side, as each fit's own parallel parts
    // leave cores idle between its steps.
    let fits: Vec<CandidateFit> = LIBRARY
        .par_iter()
        .map(|&c| {
            let f = fit_candidate(&null, c, l0, &axis);
            progress.advance(1);
            f
        })
        .collect();
    progress.start(opts.bootstrap as u64, "discovery, bootstrap replicates");
    let reps = bootstrap(&null, &fits, &axis, opts, progress)?;
    progress.start(
        2,
        "discovery, the answer: held-out predictions and the effect's interval",
    );
    let mut cands: Vec<CandidateResult> = fits
        .iter()
        .enumerate()
        .map(|(k, f)| candidate_result(f, k, &reps))
        .collect();
    let mut gof = goodness_of_fit(&null, &reps);
    let gof_decides = !matches!(origin, NoiseOrigin::Fitted { .. });
    let mut held_check = held_prediction_test(&null, &reps);
    adjust(
        &mut cands,
        gof_decides.then_some(&mut gof),
        held_check.as_mut(),
    );
    let (best, rivals) = select(&fits, &cands, opts);
    let misfit = misfit_of(&null, &gof, held_check.as_ref(), opts.alpha);
    let (effect, closest, ambiguous_with, check, after) = answer(
        &null,
        &fits,
        &mut cands,
        (best, &rivals),
        misfit.is_some(),
        &held,
    );
    progress.advance(1);
    let excluded = excluded_points(setup, &null)?;
    progress.advance(1);
    progress.finish();
    let misfit = if best.is_none() { misfit } else { None };
    let power_bound = opts
        .power_at
        .as_ref()
        .and_then(|e| power_bound(&null, e, opts.alpha / LIBRARY.len() as f64));
    let mask = null.curves.mask;
    let ws = windows();
    let omega: Vec<Vec<f64>> = setup
        .curves
        .iter()
        .map(|c| {
            c.speeds_rpm
                .iter()
                .map(|s| setup.dim.omega(*s, null.globals.omega_n_hz))
                .collect()
        })
        .collect();
    let gap_set = |preds: &[CurvePrediction]| GapSet {
        training: gap(setup, &train, preds, mask, &omega, &ws),
        held_out: (!held.is_empty()).then(|| gap(setup, &held, preds, mask, &omega, &ws)),
    };
    let named = effect != "none" && effect != "unexplained";
    let (after_preds, gap_after_model) = match (&after, named || closest.is_some()) {
        (Some(after), true) => (
            after.preds.clone(),
            format!("M0 + {}", closest.as_deref().unwrap_or(&effect)),
        ),
        _ => (null.preds.clone(), "M0, no candidate refitted".to_string()),
    };
    let kept_scales = null
        .scales
        .iter()
        .zip(mask)
        .flat_map(|(s, m)| s.iter().zip(m).filter(|(_, k)| **k).map(|(s, _)| *s));
    Ok(Discovery {
        effect,
        ambiguous_with,
        closest_candidate: closest,
        misfit,
        goodness_of_fit: gof,
        held_out_prediction: held_check,
        candidates: cands,
        noise: DiscoveryNoise {
            origin,
            model: null.est.noise.model,
            ..null.noise.clone()
        },
        noise_range_um: min_max(kept_scales).unwrap_or((0.0, 0.0)),
        zeta_m0: null.globals.zeta,
        omega_n_hz_m0: null.globals.omega_n_hz,
        design_load_n: setup.design_load_n,
        training_loads_n: train.iter().map(|&i| setup.curves[i].load_n).collect(),
        held_out_loads_n: held.iter().map(|&i| setup.curves[i].load_n).collect(),
        held_out_ste_um: held
            .iter()
            .map(|&i| {
                let ste_after = after
                    .as_ref()
                    .and_then(|x| x.held_ste.iter().find(|h| h.0 == i))
                    .map_or(null.ste[i], |h| h.1);
                (setup.curves[i].load_n, null.ste[i], ste_after)
            })
            .collect(),
        excluded_points: mask.iter().flatten().filter(|m| !**m).count(),
        excluded_by_load: excluded,
        gap_before: gap_set(&null.preds),
        gap_after: gap_set(&after_preds),
        gap_after_model,
        residuals_before: residual_curves(setup, &train, &null.preds, mask, &omega),
        residuals_after: residual_curves(setup, &train, &after_preds, mask, &omega),
        windows: ws,
        bootstrap: opts.bootstrap,
        power_bound,
        noise_correlation: null.est.noise.correlation.clone(),
        stated_ste: null
            .est
            .measurements
            .iter()
            .map(|m| (setup.curves[train[m.measurement.param - 2]].load_n, *m))
            .chain(
                null.held_fits
                    .iter()
                    .filter_map(|(_, h)| Some((setup.curves[h.curve].load_n, h.stated?))),
            )
            .collect(),
        prediction_check: check,
    })
}

/// What the run answers: the best passing candidate (`best`; `rivals`, those the training loads
/// cannot tell from it, [`select`]) is named when its refit predicts the held-out loads
/// better than M0, "ambiguous" when a rival predicts them about as well, "unexplained" when
/// worse; with none passing, "unexplained" where M0 misfits (with the closest candidate whose
/// prediction can be made), else "none". A failed prediction or interval is said in its result.
/// Returns the answer, the closest candidate, those it is ambiguous with, the check, the refit.
fn answer(
    null: &NullFit,
    fits: &[CandidateFit],
    cands: &mut [CandidateResult],
    (best, rivals): (Option<usize>, &[usize]),
    misfit: bool,
    held: &[usize],
) -> (
    String,
    Option<String>,
    Vec<String>,
    Option<PredictionCheck>,
    Option<After>,
) {
    // Where none passes but M0 misfits, the closest candidate by likelihood ratio whose
    // predictions can be made shows its gap after.
    let tried: Vec<usize> = match best {
        Some(b) => vec![b],
        None if misfit => by_lr(cands)
            .into_iter()
            .filter(|&k| fits[k].est.is_ok())
            .collect(),
        None => Vec::new(),
    };
    let mut after = None;
    let mut shown = None;
    for &b in &tried {
        match candidate_predictions(null, &fits[b], held) {
            Ok(a) => {
                (after, shown) = (Some(a), Some(b));
                break;
            }
            Err(e) => cands[b].prediction_failed = Some(e.to_string()),
        }
    }
    let ambiguous_with = match (&after, best) {
        (Some(a), Some(_)) if !held.is_empty() => held_out_rivals(null, fits, rivals, a, held),
        _ => rivals
            .iter()
            .map(|&k| fits[k].candidate.name().to_string())
            .collect(),
    };
    let check = match (&after, best) {
        (Some(a), Some(b)) if !held.is_empty() => {
            match held_log_likelihoods(null, held, &[&null.as_after(held), a]) {
                Ok(l) => Some(PredictionCheck {
                    candidate: fits[b].candidate.name(),
                    held_out_log_likelihood_m0: l[0],
                    held_out_log_likelihood_candidate: l[1],
                }),
                Err(e) => {
                    cands[b].prediction_failed = Some(e.to_string());
                    None
                }
            }
        }
        _ => None,
    };
    let predicts = match best {
        Some(_) if !held.is_empty() => check
            .as_ref()
            .is_some_and(PredictionCheck::candidate_predicts),
        _ => true,
    };
    if let (Some(b), true) = (best, predicts) {
        if let Ok(est) = &fits[b].est {
            if let Err(e) = named_size(null, fits[b].candidate, est, &mut cands[b]) {
                cands[b].note = Some(format!("its interval failed: {e}"));
            }
        }
    }
    let (effect, closest) = match (best, predicts) {
        (Some(b), true) if ambiguous_with.is_empty() => (cands[b].name.to_string(), None),
        (Some(b), true) => ("ambiguous".to_string(), Some(cands[b].name.to_string())),
        (Some(b), false) => ("unexplained".to_string(), Some(cands[b].name.to_string())),
        (None, _) if misfit => (
            "unexplained".to_string(),
            shown
                .or(tried.first().copied())
                .map(|k| cands[k].name.to_string()),
        ),
        (None, _) => ("none".to_string(), None),
    };
    (effect, closest, ambiguous_with, check, after)
}

/// Holm's adjustment of the tested candidates' p-values with M0's checks that can say
/// "unexplained", so that the family-wise error over every way of leaving "none" is alpha: its
/// held-out prediction and, with a stated noise (`gof` given), its goodness of fit.
fn adjust(
    cands: &mut [CandidateResult],
    gof: Option<&mut TestResult>,
    held: Option<&mut TestResult>,
) {
    let tested: Vec<usize> = (0..cands.len())
        .filter(|&k| cands[k].p_value.is_some())
        .collect();
    let mut checks: Vec<&mut TestResult> = gof
        .into_iter()
        .chain(held)
        .filter(|t| t.p_value.is_some())
        .collect();
    let family: Vec<f64> = tested
        .iter()
        .filter_map(|&k| cands[k].p_value)
        .chain(checks.iter().filter_map(|t| t.p_value))
        .collect();
    let adj = holm(&family);
    for (&k, p) in tested.iter().zip(&adj) {
        cands[k].p_holm = Some(*p);
    }
    for (t, p) in checks.iter_mut().zip(&adj[tested.len()..]) {
        t.p_holm = Some(*p);
    }
}

/// M0's prediction of the held-out loads tested, its deviance against its bootstrap
/// replicates': an effect outside the library that the training fit absorbs in its zeta,
/// omega_n and STEs shows where those are not refitted.
fn held_prediction_test(null: &NullFit, reps: &[Replicate]) -> Option<TestResult> {
    let dev = reps.iter().filter_map(|r| r.held_deviance).collect();
    Some(bootstrap_test(
        "m0_held_out_prediction",
        null.held.as_ref()?.deviance,
        dev,
    ))
}

/// A statistic's test against its bootstrap replicates `reps` (no p-value without any).
fn bootstrap_test(name: &str, statistic: f64, reps: Vec<f64>) -> TestResult {
    TestResult {
        name: name.to_string(),
        statistic,
        p_value: (!reps.is_empty()).then(|| bootstrap_p(statistic, &reps)),
        p_holm: None,
    }
}

/// Of the `rivals` of `best` ([`select`]), those whose held-out log-likelihood is within half of
/// chi2(0.95; 1) = 3.84 of its or better (one that cannot predict stays a rival): effects alike
/// at the training loads can part at others (a torque ripple is the same newtons at every load,
/// a stiffness variation scales with the mean deflection).
fn held_out_rivals(
    null: &NullFit,
    fits: &[CandidateFit],
    rivals: &[usize],
    best: &After,
    held: &[usize],
) -> Vec<String> {
    rivals
        .iter()
        .filter(|&&k| {
            candidate_predictions(null, &fits[k], held)
                .and_then(|r| held_log_likelihoods(null, held, &[best, &r]))
                .map_or(true, |l| l[1] > l[0] - 0.5 * SUPPORT_95)
        })
        .map(|&k| fits[k].candidate.name().to_string())
        .collect()
}

/// The best passing candidate (Holm below alpha) by the least AIC, -2 log L + 2 parameters
/// (Akaike 1974), and its rivals: the other tested candidates, passing or not, whose AIC lies
/// within chi2(0.95; 1) = 3.84 of the best one's. The training loads cannot tell those from the
/// best, however differently they change the curves, and whether a rival passes on its own says
/// how it fares against M0, not against the best: the held-out loads tell them apart, or
/// nothing does.
fn select(
    fits: &[CandidateFit],
    cands: &[CandidateResult],
    opts: &DiscoverOptions,
) -> (Option<usize>, Vec<usize>) {
    let score = |k: usize| fits[k].lr - 2.0 * fits[k].candidate.dim() as f64;
    let best = (0..cands.len())
        .filter(|&k| cands[k].p_holm.is_some_and(|p| p < opts.alpha))
        .max_by(|&a, &b| score(a).total_cmp(&score(b)));
    let rivals = best
        .map(|b| {
            (0..cands.len())
                .filter(|&k| k != b && cands[k].p_value.is_some() && fits[k].est.is_ok())
                .filter(|&k| score(b) - score(k) <= SUPPORT_95)
                .collect()
        })
        .unwrap_or_default();
    (best, rivals)
}

/// chi2(0.95; 1): how far below the best candidate's AIC a rival's may lie.
const SUPPORT_95: f64 = 3.841_458_820_694_124;

/// Why M0 does not explain the training curves on its own, if it does not: its held-out
/// prediction or (with a stated noise, where `p_holm` is set) its chi-square beyond their
/// bootstrap replicates' after Holm's correction; with any noise, a correlation length whose
/// interval passes the widest curve (`crate::fit::CorrelationFit::unbounded_length`): the
/// residuals are one smooth curve, a misfit the noise cannot be.
fn misfit_of(
    null: &NullFit,
    gof: &TestResult,
    held: Option<&TestResult>,
    alpha: f64,
) -> Option<String> {
    if let Some((h, p)) = held.and_then(|h| Some((h, h.p_holm.filter(|p| *p < alpha)?))) {
        return Some(format!(
            "M0 predicts the held-out loads worse than its errors allow: their standardized deviance {:.1} lies beyond its bootstrap replicates' (Holm p {p:.3})",
            h.statistic
        ));
    }
    if let Some(p) = gof.p_holm.filter(|p| *p < alpha) {
        return Some(format!(
            "M0's chi-square of innovations {:.1} lies beyond its bootstrap replicates' (Holm p {p:.3})",
            gof.statistic
        ));
    }
    let c = null.est.noise.correlation.as_ref()?;
    c.unbounded_length()?;
    Some(format!(
        "M0's residuals are one smooth curve across the speeds: their correlation length {:.0} rpm has a 95% interval reaching beyond the widest curve's {:.0} rpm",
        c.length_rpm, c.span_rpm
    ))
}

/// The identifiable fitted candidates, largest likelihood ratio first (one that cannot change
/// the curves gains only by moving M0's own parameters).
fn by_lr(cands: &[CandidateResult]) -> Vec<usize> {
    let mut k: Vec<usize> = (0..cands.len())
        .filter(|&k| cands[k].identifiable && cands[k].lr.is_finite())
        .collect();
    k.sort_by(|&a, &b| cands[b].lr.total_cmp(&cands[a].lr));
    k
}

/// The bootstrap replicates of M0 and every identifiable, fitted candidate.
fn bootstrap(
    null: &NullFit,
    fits: &[CandidateFit],
    axis: &crate::fit::Axis,
    opts: &DiscoverOptions,
    progress: &dyn Progress,
) -> Result<Vec<Replicate>> {
    let columns: Vec<Columns> = fits
        .iter()
        .filter_map(|f| {
            let est = f.est.as_ref().ok()?;
            f.columns.clone().map(|d| Columns {
                candidate: f.candidate,
                d,
                options: replicate_options(&null.family, est, axis),
            })
        })
        .collect();
    let f0 = null.curves.model(&null.est.params)?;
    let errors = ErrorModel {
        scales: &null.est.noise.scales,
        distribution: null.est.noise.model.distribution,
        length: null.est.noise.model.correlation_length,
        axis,
    };
    let reps = calibration::replicates(
        &NullModel {
            f0: &f0,
            p0: &null.est.params,
            params: &null.est.param_defs,
            j0: &null.est.model_jacobian,
            options: replicate_options(&null.family, &null.est, axis),
        },
        &columns,
        &errors,
        null.held.as_ref().map(|h| &h.linear),
        (opts.bootstrap, opts.seed),
        progress,
    );
    // Each replicate's ratios in the order of the fits, None where the candidate is not tested.
    Ok(reps
        .into_iter()
        .map(|r| {
            let mut it = r.lr.into_iter();
            let lr = fits.iter().map(|f| {
                let tested = f.est.is_ok() && f.columns.is_some();
                tested.then(|| it.next().flatten()).flatten()
            });
            Replicate {
                lr: lr.collect(),
                ..r
            }
        })
        .collect())
}

/// How a replicate is fitted by a model whose data fit is `fit`: the noise's scale re-estimated
/// as the run's family says, its shape (tails, correlation length) held at `fit`'s, sparing a
/// search per fit at the cost of the shape's share of the ratio: of second order under M0,
/// where the fits' shapes agree.
fn replicate_options(family: &Family, fit: &Estimate, axis: &crate::fit::Axis) -> EstimateOptions {
    let model = fit.noise.model;
    EstimateOptions {
        noise: match &family.scale {
            Scale::PerPoint => NoiseSetting::PerPoint(fit.noise.scales.clone()),
            Scale::Stated(m) => NoiseSetting::Stated(*m),
            Scale::Estimated { floor_min } => NoiseSetting::Estimate(crate::fit::NoiseFreedom {
                floor_min: *floor_min,
                relative: true,
            }),
        },
        correlation: crate::fit::CorrelationSetting::Stated(axis.clone(), model.correlation_length),
        robust: match model.distribution {
            Distribution::Gaussian => Robust::Off,
            Distribution::StudentT { dof } => Robust::StudentT(dof),
        },
        stop: Stop::converged(20),
        starts: Vec::new(),
        // The replicates are drawn from about this model: their fits start at its weights.
        noise_start: Some(model),
        // The same statements of STEs as the data's fit (each replicate draws their values).
        measurements: fit.measurements.iter().map(|m| m.measurement).collect(),
    }
}

/// A candidate's line of the report: its fit, its likelihood ratio and the ratio's bootstrap
/// p-value (identifiable, fitted candidates only).
fn candidate_result(f: &CandidateFit, k: usize, reps: &[Replicate]) -> CandidateResult {
    let null: Vec<f64> = reps.iter().filter_map(|r| r.lr[k]).collect();
    let tested = f.identifiable && f.est.is_ok() && f.columns.is_some() && !null.is_empty();
    let delta = f.est.as_ref().ok().map(|e| {
        let lead = e.params.len() - f.candidate.dim();
        e.params[lead..].to_vec()
    });
    // The named candidate's size, intervals and phase are set by `named_size`.
    CandidateResult {
        name: f.candidate.name(),
        candidate: f.candidate,
        identifiable: f.identifiable,
        note: f.note.clone(),
        failed: f.est.as_ref().err().cloned(),
        prediction_failed: None,
        lr: f.lr,
        p_value: tested.then(|| bootstrap_p(f.lr, &null)),
        p_holm: None,
        estimate_name: f.candidate.estimate_name(),
        estimate: None,
        ci95: None,
        ci95_method: "Wald",
        wald_ci95: None,
        profile_ci95: None,
        delta,
        zeta: f.est.as_ref().ok().map(|e| e.params[0]),
        omega_n_hz: f.est.as_ref().ok().map(|e| e.params[1]),
        phase_deg: None,
        phase_wald95_deg: None,
    }
}

/// M0's goodness of fit: the chi-square of its innovations against the replicates'. With an
/// estimated noise it is near its degrees of freedom by construction and tells little; with a
/// stated one it says whether the stated noise and M0 explain the scatter.
fn goodness_of_fit(null: &NullFit, reps: &[Replicate]) -> TestResult {
    let chi = reps.iter().map(|r| r.chi_square).collect();
    bootstrap_test("m0_goodness_of_fit", null.est.chi_square, chi)
}

/// A fitted model's predictions of every curve.
struct After {
    preds: Vec<CurvePrediction>,
    held_ste: Vec<(usize, f64)>,
    globals: Globals,
    effect: Effect,
    held_fits: Vec<HeldFit>,
}

fn candidate_predictions(null: &NullFit, f: &CandidateFit, held: &[usize]) -> Result<After> {
    let est = f
        .est
        .as_ref()
        .map_err(|e| GearError::Numerical(e.clone()))?;
    let curves = null.curves.with_effect(EffectParams::Delta(f.candidate));
    let (g, _, effect) = curves.unpack(&est.params);
    let mut preds = null.preds.clone();
    for (k, p) in curves.predictions(&est.params)?.into_iter().enumerate() {
        preds[curves.idx[k]] = p;
    }
    let fits = held_out(
        null.curves.setup,
        (held, null.curves.mask, &null.scales),
        (g, &effect),
        (&null.family, &null.est),
        None,
    )?;
    let (held_fits, held_ste) = place_held(fits, null.curves.mask, &mut preds);
    Ok(After {
        preds,
        held_ste,
        globals: g,
        effect,
        held_fits,
    })
}

/// The points M0's mask left out, per load, with M0's range there (its pp, and at a
/// non-periodic point every observation window's) and how many measured points lie far
/// outside it: reported, not tested.
fn excluded_points(setup: &Setup, null: &NullFit) -> Result<Vec<ExcludedPoints>> {
    let mask = null.curves.mask;
    mask.iter()
        .enumerate()
        .map(|(i, m)| (i, (0..m.len()).filter(|&j| !m[j]).collect::<Vec<_>>()))
        .filter(|(_, d)| !d.is_empty())
        .map(|(i, d)| {
            let c = &setup.curves[i];
            let p = &null.preds[i];
            let windows =
                aperiodic_pp_range(setup, i, null.globals, null.ste[i], &Effect::none(), p)?;
            let predicted = min_max(d.iter().map(|&j| p.dte_pp_um[j])).unwrap_or((0.0, 0.0));
            let range = d
                .iter()
                .filter_map(|&j| windows[j])
                .fold(predicted, |(lo, hi), (a, b)| (lo.min(a), hi.max(b)));
            Ok(ExcludedPoints {
                load_n: c.load_n,
                points: d.len(),
                non_period1: d.iter().filter(|&&j| !p.period1[j]).count(),
                measured_range_um: min_max(d.iter().map(|&j| c.dte_pp_um[j]))
                    .unwrap_or((f64::NAN, f64::NAN)),
                predicted_range_um: predicted,
                model_range_um: range,
                outside_model_range: far_from(setup, &null.noise, i, &d, range),
            })
        })
        .collect()
}
