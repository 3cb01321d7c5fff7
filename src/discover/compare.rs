//! Where a model and the measured curves are compared: the training / held-out split, the
//! mask of points a point-wise likelihood can use (period-1 and away from jumps), the gaps
//! (RMS residuals per load and Omega window) and the residual curves of the report.

use super::forward::{jumps_between, CurvePrediction, Setup};
use super::noise::DiscoveryNoise;
use super::result::{Gap, ResidualCurve};
use super::windows::Window;
use crate::error::Result;
use rayon::prelude::*;

/// Points kept per curve (same shape as the curves).
pub type Mask = Vec<Vec<bool>>;

/// Training loads: every other load from the highest (the design load) down; the rest are
/// held out (with one load there is nothing to hold out).
pub fn split(n: usize) -> (Vec<usize>, Vec<usize>) {
    (0..n).partition(|i| i % 2 == 0)
}

/// Widest interval between two speeds, relative to the higher, across which a change of regime
/// with a step over 10 noise scales drops both points unrefined (a 50 or 100 rpm grid near
/// resonance): a refit moves such a boundary that far; kept, they can pull zeta to hide an effect.
const NARROW_INTERVAL: f64 = 0.05;

/// Mask: drop points whose predicted steady state is not period-1 (chaotic, subharmonic: the
/// measured pp there depends on history beyond the model) and the two points around every
/// predicted change of impact regime (Fig. 9: none, single-sided, double-sided) with a step over
/// 10 noise scales (at the higher level), a jump, which displaced by one grid step would dominate
/// every statistic and say nothing of a missing effect (a resonance peak in contact is steep too,
/// but smooth in the parameters). Across an interval wider than [`NARROW_INTERVAL`] the change
/// must also be discontinuous in the sweep ([`jumps_between`]): one along a continuous branch
/// moves smoothly with the parameters and carries zeta. `curves[k]` is what `preds[k]` predicts.
pub fn make_mask(
    setup: &Setup,
    preds: &[CurvePrediction],
    curves: &[usize],
    noise: &DiscoveryNoise,
) -> Result<Mask> {
    preds
        .par_iter()
        .zip(curves)
        .map(|(p, &i)| {
            let n = p.dte_pp_um.len();
            let mut m: Vec<bool> = p.period1.clone();
            for j in 1..n {
                // A jump onto the back flank counts though the teeth are separated on both
                // sides: a fit whose jump comes one speed early would keep a point far off.
                let regime_changed = p.separated[j] != p.separated[j - 1]
                    || p.back_contact[j] != p.back_contact[j - 1];
                let (a, b) = (p.dte_pp_um[j - 1], p.dte_pp_um[j]);
                let top = a.abs().max(b.abs());
                let step = 10.0 * noise.scale_at(i, j, top).max(noise.scale_at(i, j - 1, top));
                let speeds = &setup.curves[i].speeds_rpm;
                let narrow = speeds[j] - speeds[j - 1] <= NARROW_INTERVAL * speeds[j];
                if regime_changed
                    && (b - a).abs() > step
                    && (narrow || jumps_between(p, speeds, j, step)?)
                {
                    m[j] = false;
                    m[j - 1] = false;
                }
            }
            Ok(m)
        })
        .collect()
}

/// The points where the held-out curves `held` are compared: those `base` and the mask of each
/// model's predictions (`models`, every curve's) keep, whose neighbours are kept too. A training
/// curve's jumps and chaotic ranges are fitted to the measured speeds; a held-out curve's are
/// predicted within a grid step, and one point on the wrong side could decide the comparison.
/// The other curves' rows are `base`'s.
pub fn held_mask(
    setup: &Setup,
    held: &[usize],
    models: &[&[CurvePrediction]],
    noise: &DiscoveryNoise,
    base: &Mask,
) -> Result<Mask> {
    let mut out = base.clone();
    for preds in models {
        let rows: Vec<CurvePrediction> = held.iter().map(|&i| preds[i].clone()).collect();
        for (row, &i) in make_mask(setup, &rows, held, noise)?.into_iter().zip(held) {
            for (kept, m) in out[i].iter_mut().zip(row) {
                *kept &= m;
            }
        }
    }
    for &i in held {
        let row = &out[i];
        let n = row.len();
        out[i] = (0..n)
            .map(|j| row[j] && (j == 0 || row[j - 1]) && (j + 1 == n || row[j + 1]))
            .collect();
    }
    Ok(out)
}

/// The RMS residual of `preds` about the curves `idx` at the kept points, per load and at the
/// worst Omega window of `ws`.
pub fn gap(
    setup: &Setup,
    idx: &[usize],
    preds: &[CurvePrediction],
    mask: &Mask,
    omega: &[Vec<f64>],
    ws: &[Window],
) -> Gap {
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
    let mut all = Vec::new();
    let mut per_w = vec![Vec::new(); ws.len()];
    let mut per_load = Vec::new();
    for &i in idx {
        let mut this = Vec::new();
        for (j, y) in setup.curves[i].dte_pp_um.iter().enumerate() {
            if mask[i][j] {
                let r = y - preds[i].dte_pp_um[j];
                all.push(r);
                this.push(r);
                for (k, w) in ws.iter().enumerate() {
                    if w.contains(omega[i][j]) {
                        per_w[k].push(r);
                    }
                }
            }
        }
        per_load.push((setup.curves[i].load_n, rms(&this), this.len()));
    }
    let worst = per_w
        .iter()
        .enumerate()
        .filter(|(_, v)| v.len() >= 3)
        .map(|(k, v)| (k, rms(v)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    Gap {
        rms_um: rms(&all),
        worst_window_rms_um: worst.map_or(0.0, |w| w.1),
        worst_window: worst.map(|w| ws[w.0].label.to_string()),
        points: all.len(),
        per_load,
    }
}

pub fn residual_curves(
    setup: &Setup,
    train: &[usize],
    preds: &[CurvePrediction],
    mask: &Mask,
    omega: &[Vec<f64>],
) -> Vec<ResidualCurve> {
    setup
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| ResidualCurve {
            load_n: c.load_n,
            training: train.contains(&i),
            points: (0..c.speeds_rpm.len())
                .map(|j| {
                    (
                        c.speeds_rpm[j],
                        omega[i][j],
                        c.dte_pp_um[j] - preds[i].dte_pp_um[j],
                        mask[i][j],
                    )
                })
                .collect(),
        })
        .collect()
}

/// Of the points `dropped` of curve `i`, those whose measured pp lies outside the model range
/// `range` (um) by more than 3 noise scales (at its largest pp) plus 10% of that pp.
pub fn far_from(
    setup: &Setup,
    noise: &DiscoveryNoise,
    i: usize,
    dropped: &[usize],
    range: (f64, f64),
) -> usize {
    let top = range.1.abs();
    let margin = |j: usize| 3.0 * noise.scale_at(i, j, top) + 0.1 * top;
    dropped
        .iter()
        .filter(|&&j| {
            let v = setup.curves[i].dte_pp_um[j];
            v > range.1 + margin(j) || v < range.0 - margin(j)
        })
        .count()
}

#[cfg(test)]
pub(super) mod tests {
    use super::{held_mask, make_mask};
    use crate::discover::forward::{Curve, CurvePrediction, Setup};
    use crate::discover::noise::{DiscoveryNoise, NoiseOrigin};

    /// A set of curves of `n` points 100 rpm apart at `loads` (N), and a noise of 0.15 um.
    pub(in crate::discover) fn set_of(n: usize, loads: &[f64]) -> (Setup, DiscoveryNoise) {
        let curve = |&load_n: &f64| Curve {
            load_n,
            speeds_rpm: (0..n).map(|k| 1000.0 + 100.0 * k as f64).collect(),
            dte_pp_um: vec![1.0; n],
            sd_um: None,
            stated_ste: None,
        };
        let setup = Setup::new(
            crate::data::munro_rig().dimensional().unwrap(),
            3780.0,
            loads.iter().map(curve).collect(),
            crate::validate::MunroNoise::Estimate { floor_min: 0.0 },
        );
        let noise = DiscoveryNoise::stated(
            NoiseOrigin::StatedOption,
            crate::fit::NoiseModel::constant(0.15),
        );
        (setup, noise)
    }

    /// A jump from single-sided impacts (30 um) onto the back flank (157 um) drops the points
    /// on both sides although the teeth are separated on both; a jump out of contact does the
    /// same; a step in back contact smaller than 10 sigma, and a large step within one regime
    /// (a resonance peak), keep their points; a non-period-1 point is dropped. Without the
    /// model a regime change cannot be refined and counts as a jump.
    #[test]
    fn mask_drops_the_points_around_a_jump_onto_the_back_flank() {
        let p = CurvePrediction {
            dte_pp_um: vec![20.0, 28.0, 30.0, 157.0, 162.0, 162.5, 300.0, 10.0, 9.0],
            period1: vec![true, true, true, true, true, true, true, true, false],
            separated: vec![false, true, true, true, true, true, true, false, false],
            back_contact: vec![false, false, false, true, true, false, false, false, false],
            aperiodic_start: vec![None; 9],
            neighbour_starts: Vec::new(),
            sweep_model: None,
        };
        let (setup, noise) = set_of(9, &[3780.0]);
        let m = make_mask(&setup, &[p], &[0], &noise).unwrap();
        assert_eq!(
            m[0],
            vec![false, false, false, false, true, true, false, false, false]
        );
    }

    /// A held-out curve's comparison points: a point a model predicts non-period-1 is left out
    /// with its neighbours; the training curve's row is the base mask's, untouched.
    #[test]
    fn held_out_points_leave_out_the_neighbours_of_a_left_out_point() {
        let n = 7;
        let flat = |period1: Vec<bool>| CurvePrediction {
            dte_pp_um: vec![5.0; n],
            period1,
            separated: vec![false; n],
            back_contact: vec![false; n],
            aperiodic_start: vec![None; n],
            neighbour_starts: Vec::new(),
            sweep_model: None,
        };
        let (setup, noise) = set_of(n, &[3780.0, 2835.0]);
        let mut base = vec![vec![true; n]; 2];
        base[0][3] = false;
        let mut chaotic = vec![true; n];
        chaotic[4] = false;
        let preds = vec![flat(vec![true; n]), flat(chaotic)];
        let m = held_mask(&setup, &[1], &[&preds], &noise, &base).unwrap();
        assert_eq!(m[0], base[0]);
        assert_eq!(m[1], vec![true, true, true, false, false, false, true]);
    }
}
