//! Starting values of the discovery fits: zeta, omega_n and the design load's STE from eq. 13's
//! closed form, each other curve's STE from its quasi-static end, and a held-out curve's STE
//! from a scan over amplitudes ([`fit_ste`]), its residuals in units of each point's noise.

use super::compare::Mask;
use super::effects::Effect;
use super::forward::{predict, simulate, CurvePrediction, Globals, Setup, MIN_ZETA};
use super::noise::Scales;
use crate::error::{GearError, Result};
use crate::fit::{least_squares, least_squares_warm, rss, LmFit, Param, Stop};
use crate::validate::{dte_gain, dte_pp_um};
use rayon::prelude::*;

/// Masked residuals of the prediction `pred` of curve `i`, each in units of its point's noise
/// scale.
fn residuals_of(
    setup: &Setup,
    i: usize,
    pred: &CurvePrediction,
    mask: &Mask,
    scales: &Scales,
) -> Vec<f64> {
    let y = &setup.curves[i].dte_pp_um;
    (0..y.len())
        .filter(|&j| mask[i][j])
        .map(|j| (y[j] - pred.dte_pp_um[j]) / scales[i][j])
        .collect()
}

/// Relative STE amplitudes scanned around the start of [`fit_ste`].
const STE_SCAN: [f64; 12] = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4, 1.6, 1.8, 2.0];
/// Then around the best of those, in 2% steps (the coarse scan's are 10-15%); the factor 1,
/// the coarse best itself, is already evaluated.
const STE_SCAN_FINE: [f64; 8] = [0.92, 0.94, 0.96, 0.98, 1.02, 1.04, 1.06, 1.08];

/// STE amplitude of curve `i` alone, zeta, omega_n and the effect fixed. The pp response is not
/// smooth in the STE (a jump moves by a grid step), so a local fit can stop on the wrong side of
/// a jump: the best of a scan over [`STE_SCAN`] x `start`, refined, starts Levenberg-Marquardt.
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
        Ok(residuals_of(setup, i, &pred, mask, scales))
    };
    // The base point was evaluated by `f` (the memo has it); its column continues its sweep.
    let near = |p: &[f64], base: &[f64]| -> Result<Vec<f64>> {
        let at_base = predict(setup, i, g, base[0], effect)?;
        let pred = simulate(setup, i, g, p[0], effect, Some(&at_base))?;
        Ok(residuals_of(setup, i, &pred, mask, scales))
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
            // Not below the fits' floor, where every prediction is refused: eq. 13 narrows a
            // peak that falls between two speeds of a coarse grid towards zeta 0.
            zeta: b.params[0].abs().clamp(MIN_ZETA, 0.5),
            // Eq. 13 depends on Omega^2 only: the signed fit can end at -omega_n.
            omega_n_hz: b.params[1].abs(),
        },
        b.params[2].abs(),
    ))
}
