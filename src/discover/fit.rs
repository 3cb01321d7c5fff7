//! Fits of M0 and M0 + effect to the training curves (zeta, omega_n, one STE amplitude per load,
//! and the effect's delta), and of the STE amplitude alone on a held-out curve with everything
//! else fixed (a held-out load's STE is a property of that load, not something the training
//! loads can predict). Residuals are (measured - model) / sigma_ij at the points kept by a
//! mask, sigma_ij the noise scale of each point ([`Scales`]). Every fit goes through the
//! estimation engine's least squares (`crate::fit::least_squares`).

use super::effects::{Candidate, Effect};
use super::forward::{
    fitted_damping_admissible, predict, predict_near, CurvePrediction, Globals, Setup, MIN_ZETA,
};
use super::noise::Scales;
use crate::error::{GearError, Result};
use crate::fit::{least_squares, least_squares_warm, rss, secant_jacobian, LmFit, Param, Stop};
use crate::validate::{dte_gain, dte_pp_um};
use rayon::prelude::*;

/// Points kept per curve (same shape as the curves).
pub type Mask = Vec<Vec<bool>>;

/// A fitted model on a set of curves.
#[derive(Clone, Debug)]
pub struct ModelFit {
    pub globals: Globals,
    /// STE amplitude (um) per fitted curve.
    pub ste_um: Vec<f64>,
    pub effect: Effect,
    /// Residuals (sigma units, masked points only) and Jacobian: parameter layout
    /// [zeta, omega_n_hz, ste_um per curve, delta...].
    pub lm: LmFit,
}

/// Masked residuals of predictions against the curves `idx`, each in units of its point's
/// noise scale.
pub fn residuals_of(
    setup: &Setup,
    idx: &[usize],
    preds: &[CurvePrediction],
    mask: &Mask,
    scales: &Scales,
) -> Vec<f64> {
    let mut r = Vec::new();
    for (k, &i) in idx.iter().enumerate() {
        let c = &setup.curves[i];
        for (j, y) in c.dte_pp_um.iter().enumerate() {
            if mask[i][j] {
                r.push((y - preds[k].dte_pp_um[j]) / scales[i][j]);
            }
        }
    }
    r
}

/// The parameters of a discovery fit from `start` (layout of [`ModelFit::lm`]): all signed with
/// the typical sizes the finite differences and the unseen-parameter rule use (a damping step
/// below the fits' floor is rejected by the residuals, not by a transform: `MIN_ZETA` is a
/// bound on the damping at every load after a damping law, which no transform of zeta alone
/// can express).
fn discovery_params(n_curves: usize, effect: EffectInFit, start: &[f64]) -> Vec<Param> {
    let mut p = vec![
        Param::signed("zeta", start[0], 0.005),
        Param::signed("omega_n_hz", start[1], 10.0),
    ];
    for k in 0..n_curves {
        p.push(Param::signed(&format!("ste_um_{k}"), start[2 + k], 0.05));
    }
    let tail = &start[2 + n_curves..];
    match effect {
        EffectInFit::Fitted(c) => {
            for (k, &v) in tail.iter().enumerate().take(c.dim()) {
                p.push(Param::signed(&format!("{}_{k}", c.name()), v, c.scale()));
            }
        }
        EffectInFit::Profiled(c, _) => {
            for (k, &v) in tail.iter().enumerate() {
                // The first free parameter of a phase-carrying candidate is its phase (rad).
                let step = if k == 0 && c.has_phase() {
                    0.05
                } else {
                    c.scale()
                };
                p.push(Param::signed(&format!("{}_free_{k}", c.name()), v, step));
            }
        }
        EffectInFit::PhaseHeld(c, _) => {
            // The amplitude is kept positive: a negative one would be the opposite phase, and
            // the profile at psi would take the likelihood of psi + pi.
            let rest = tail.iter().enumerate().skip(1);
            p.push(Param::positive(
                &format!("{}_amplitude", c.name()),
                tail[0].max(1e-3 * c.scale()),
            ));
            for (k, &v) in rest {
                p.push(Param::signed(
                    &format!("{}_free_{k}", c.name()),
                    v,
                    c.scale(),
                ));
            }
        }
        EffectInFit::None | EffectInFit::Held(_) => {}
    }
    p
}

/// What a fit does with the effect.
#[derive(Clone, Copy, Debug)]
pub enum EffectInFit<'a> {
    /// The paper's model, M0.
    None,
    /// M0 + the candidate, its delta fitted (the last parameters).
    Fitted(Candidate),
    /// M0 + this effect, held as it is.
    Held(&'a Effect),
    /// M0 + the candidate with its profile coordinate ([`Candidate::profiled`]: an amplitude,
    /// gamma or beta) held at this value and the rest of its delta fitted (the last
    /// parameters): one point of a profile likelihood.
    Profiled(Candidate, f64),
    /// M0 + a phase-carrying candidate with its first phase ([`Candidate::first_phase`], rad)
    /// held at this value and its amplitude (kept positive) and the rest of its delta fitted:
    /// one point of the phase's profile likelihood. The last parameters are (amplitude, the
    /// rest of [`Candidate::profiled`]'s free part after the phase).
    PhaseHeld(Candidate, f64),
}

impl EffectInFit<'_> {
    /// The effect that a fit's last parameters `tail` (after zeta, omega_n and the STEs) stand
    /// for.
    pub fn effect(&self, tail: &[f64]) -> Effect {
        match *self {
            EffectInFit::None => Effect::none(),
            EffectInFit::Fitted(c) => Effect::of(c, tail.to_vec()),
            EffectInFit::Held(e) => e.clone(),
            EffectInFit::Profiled(c, u) => Effect::of(c, c.unprofiled(u, tail)),
            EffectInFit::PhaseHeld(c, psi) => {
                let mut free = vec![psi];
                free.extend_from_slice(&tail[1..]);
                Effect::of(c, c.unprofiled(tail[0], &free))
            }
        }
    }
}

fn unpack(p: &[f64], n_curves: usize, effect: EffectInFit) -> (Globals, Vec<f64>, Effect) {
    let g = Globals {
        zeta: p[0],
        omega_n_hz: p[1],
    };
    let ste = p[2..2 + n_curves].to_vec();
    let effect = effect.effect(&p[2 + n_curves..]);
    (g, ste, effect)
}

/// The standardized residuals of a fit on the kept points of curves `idx`.
struct FitResiduals<'a> {
    setup: &'a Setup,
    idx: &'a [usize],
    mask: &'a Mask,
    scales: &'a Scales,
    effect_in_fit: EffectInFit<'a>,
}

impl<'a> FitResiduals<'a> {
    fn new(
        setup: &'a Setup,
        idx: &'a [usize],
        mask: &'a Mask,
        scales: &'a Scales,
        effect_in_fit: EffectInFit<'a>,
    ) -> Self {
        FitResiduals {
            setup,
            idx,
            mask,
            scales,
            effect_in_fit,
        }
    }

    /// At parameters `p` (layout of [`ModelFit::lm`]).
    fn at(&self, p: &[f64]) -> Result<Vec<f64>> {
        let (setup, idx) = (self.setup, self.idx);
        let (g, ste, effect) = unpack(p, idx.len(), self.effect_in_fit);
        fitted_damping_admissible(setup, idx, g, &effect)?;
        let preds: Vec<CurvePrediction> = idx
            .par_iter()
            .zip(&ste)
            .map(|(&i, &e)| predict(setup, i, g, e, &effect))
            .collect::<Result<_>>()?;
        Ok(residuals_of(setup, idx, &preds, self.mask, self.scales))
    }

    /// At parameters `p` near `base`: each curve whose parameters moved continues the base's
    /// sweep (a Jacobian column).
    fn near(&self, p: &[f64], base: &[f64]) -> Result<Vec<f64>> {
        let (setup, idx) = (self.setup, self.idx);
        let n = idx.len();
        let (g, ste, effect) = unpack(p, n, self.effect_in_fit);
        let (g0, ste0, effect0) = unpack(base, n, self.effect_in_fit);
        fitted_damping_admissible(setup, idx, g, &effect)?;
        let preds: Vec<CurvePrediction> = idx
            .par_iter()
            .zip(ste.par_iter().zip(&ste0))
            .map(|(&i, (&e, &e0))| {
                // The prediction `f` made there, from the set's memo: a column that moves one
                // curve's STE leaves the other curves as they were, and continues the base's
                // sweep.
                let at_base = predict(setup, i, g0, e0, &effect0)?;
                if g == g0 && e == e0 && effect.delta == effect0.delta {
                    return Ok(at_base);
                }
                predict_near(setup, i, g, e, &effect, &at_base)
            })
            .collect::<Result<_>>()?;
        Ok(residuals_of(setup, idx, &preds, self.mask, self.scales))
    }
}

/// Fit zeta, omega_n, the STE of each curve in `idx` and (with [`EffectInFit::Fitted`]) the
/// effect's delta from `start` (same layout as [`ModelFit::lm`]).
pub fn fit_model(
    setup: &Setup,
    idx: &[usize],
    mask: &Mask,
    scales: &Scales,
    effect_in_fit: EffectInFit,
    start: &[f64],
    stop: Stop,
) -> Result<ModelFit> {
    let r = FitResiduals::new(setup, idx, mask, scales, effect_in_fit);
    let f = |p: &[f64]| r.at(p);
    let near = |p: &[f64], base: &[f64]| r.near(p, base);
    let lm = least_squares_warm(
        &f,
        Some(&near),
        &discovery_params(idx.len(), effect_in_fit, start),
        stop,
    )?;
    let (globals, ste_um, effect) = unpack(&lm.params, idx.len(), effect_in_fit);
    Ok(ModelFit {
        globals,
        ste_um,
        effect,
        lm,
    })
}

/// `fit` (a [`fit_model`] on the same curves, mask, scales and layout) with its Jacobian also
/// taken as secants over `q` standard errors of each parameter either side
/// ([`secant_jacobian`], in [`LmFit::secant_jacobian`]): its Wald intervals of half-width `q`
/// standard errors then take the larger variance of the two linearisations. A Wald interval
/// assumes the residuals linear over its width; next to a kink or a fold of the up-sweep's
/// response the derivative is steep over a tiny range only. On a 2nd-STE-harmonic set (seed
/// 3) one such point's derivative in the harmonic's sine part was 200 times its neighbours'
/// and its secant a thousandth of it: that point alone set the phase's Wald arc (1.1-3.7 deg;
/// the likelihood's -2.5-6.7 deg, the truth 0). Unchanged where J'J is singular.
pub fn relinearized(
    setup: &Setup,
    idx: &[usize],
    mask: &Mask,
    scales: &Scales,
    effect_in_fit: EffectInFit,
    mut fit: ModelFit,
    q: f64,
) -> ModelFit {
    let jt = &fit.lm.jacobian;
    let Some(cov) = (jt.transpose() * jt).try_inverse() else {
        return fit;
    };
    let steps: Vec<f64> = (0..cov.nrows())
        .map(|k| q * cov[(k, k)].max(0.0).sqrt())
        .collect();
    let r = FitResiduals::new(setup, idx, mask, scales, effect_in_fit);
    let near = |p: &[f64], base: &[f64]| r.near(p, base);
    fit.lm.secant_jacobian = Some(secant_jacobian(
        &near,
        &fit.lm.params,
        &fit.lm.residuals,
        &steps,
        jt,
    ));
    fit
}

/// Relative STE amplitudes scanned around the start of [`fit_ste`].
const STE_SCAN: [f64; 12] = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4, 1.6, 1.8, 2.0];
/// Then around the best of those, in 2% steps (the coarse scan's are 10-15%); the factor 1,
/// the coarse best itself, is already evaluated.
const STE_SCAN_FINE: [f64; 8] = [0.92, 0.94, 0.96, 0.98, 1.02, 1.04, 1.06, 1.08];

/// STE amplitude of curve `i` alone, with zeta, omega_n and the effect fixed. The pp response
/// is not smooth in the STE (a jump moves by a grid step, a branch appears), so a local fit from
/// one start can stop on the wrong side of a jump: the start is the best of a scan over
/// [`STE_SCAN`] x `start` and a finer one around it, then Levenberg-Marquardt refines it.
pub fn fit_ste(
    setup: &Setup,
    i: usize,
    mask: &Mask,
    scales: &Scales,
    g: Globals,
    effect: &Effect,
    start: f64,
) -> Result<(f64, LmFit)> {
    let f = |p: &[f64]| -> Result<Vec<f64>> {
        let pred = predict(setup, i, g, p[0], effect)?;
        Ok(residuals_of(setup, &[i], &[pred], mask, scales))
    };
    // The base point was evaluated by `f` (the set's memo has it); its column continues its
    // sweep.
    let near = |p: &[f64], base: &[f64]| -> Result<Vec<f64>> {
        let at_base = predict(setup, i, g, base[0], effect)?;
        let pred = predict_near(setup, i, g, p[0], effect, &at_base)?;
        Ok(residuals_of(setup, &[i], &[pred], mask, scales))
    };
    // A scanned amplitude whose prediction fails is a rejected trial point, as a step of the
    // least squares is (`crate::fit::lm`): infinitely bad, not the end of the fit.
    let rss_at = |e: f64| f(&[e]).map_or(f64::INFINITY, |r| rss(&r));
    // (amplitude, RSS) of the best finite point of the scan, if any.
    let scan = |factors: &[f64], around: f64| -> Option<(f64, f64)> {
        let scanned: Vec<(f64, f64)> = factors
            .par_iter()
            .map(|k| {
                let e = k * around;
                (e, rss_at(e))
            })
            .collect();
        scanned
            .into_iter()
            .filter(|(_, r)| r.is_finite())
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let best = match scan(&STE_SCAN, start.abs()) {
        Some(coarse) => {
            scan(&STE_SCAN_FINE, coarse.0)
                // Ties go to the smaller amplitude, the first in scan order.
                .filter(|fine| fine.1 < coarse.1 || (fine.1 == coarse.1 && fine.0 < coarse.0))
                .unwrap_or(coarse)
                .0
        }
        None => scan(&STE_SCAN_FINE, start.abs()).map_or(start.abs(), |fine| fine.0),
    };
    let lm = least_squares_warm(
        &f,
        Some(&near),
        &[Param::signed("ste_um", best, 0.05)],
        Stop::converged(8),
    )?;
    Ok((lm.params[0].abs(), lm))
}

/// Quasi-static STE estimate of a curve from its lowest-speed point: pp DTE = 2 e |H_x|.
pub fn ste_from_low_speed(setup: &Setup, i: usize, g: Globals) -> f64 {
    let c = &setup.curves[i];
    let om = setup.dim.omega(c.speeds_rpm[0], g.omega_n_hz);
    (c.dte_pp_um[0] / (2.0 * dte_gain(g.zeta, om))).max(1e-3)
}

/// Starting zeta, omega_n and STE from the closed form of eq. 13 (teeth in contact) fitted to
/// the highest-load curve, `setup.curves[i0]`, from a few starts around its measured peak.
pub fn linear_start(setup: &Setup, i0: usize) -> Result<(Globals, f64)> {
    let c = &setup.curves[i0];
    let dim = &setup.dim;
    let f = |p: &[f64]| -> Result<Vec<f64>> {
        Ok(c.speeds_rpm
            .iter()
            .zip(&c.dte_pp_um)
            .map(|(s, y)| y - dte_pp_um(p[2].abs(), p[0].abs(), dim.omega(*s, p[1].abs())))
            .collect())
    };
    let peak = c
        .speeds_rpm
        .iter()
        .zip(&c.dte_pp_um)
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(s, _)| dim.mesh_frequency_hz(*s))
        .unwrap_or(1000.0);
    let e0 = (c.dte_pp_um[0] / 2.0).max(1e-3);
    let mut best: Option<LmFit> = None;
    for z in [0.01, 0.03, 0.08] {
        for w in [0.97, 1.0, 1.03] {
            let params = [
                Param::signed("zeta", z, 0.005),
                Param::signed("omega_n_hz", peak * w, 10.0),
                Param::signed("ste_um", e0, 0.05),
            ];
            if let Ok(fit) = least_squares(&f, &params, Stop::converged(60)) {
                if best.as_ref().is_none_or(|b| fit.rss < b.rss) {
                    best = Some(fit);
                }
            }
        }
    }
    let b = best.ok_or_else(|| {
        GearError::Numerical("no start of the linear (eq. 13) fit converged".into())
    })?;
    Ok((
        Globals {
            // Not below the fits' floor, where every prediction is refused: on a 300 rpm grid
            // the design load's peak can fall between two speeds, and eq. 13 then narrows it
            // towards zeta 0 (a null set, relative noise, study seed 2, ended at 1e-3 and the
            // whole run failed).
            zeta: b.params[0].abs().clamp(MIN_ZETA, 0.5),
            // Eq. 13 depends on Omega^2 only, so the signed fit can end at -omega_n (a Student-t
            // null set of the discover study did, and every later prediction was refused).
            omega_n_hz: b.params[1].abs(),
        },
        b.params[2].abs(),
    ))
}
