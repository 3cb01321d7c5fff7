//! Combined external torque and STE excitation (Sec. 8.3, Fig. 29): F_m 0.1, zeta 0.05,
//! F_ah 0.05, F_aT 0.05, Omega_h = 2 Omega_T. The fundamental is Omega = Omega_T: a torque term of
//! order 1 and an STE term of order 2 (eq. 20). The superposition of the two single-excitation
//! multi-harmonic balance responses (sum of their Fourier series) is compared with the AFT
//! response to both simultaneously.

use super::excitation::HARMONICS;
use super::figures::{branch_series, panel, Figure};
use super::output::{StudyOutput, StudyRow};
use crate::error::Result;
use crate::hb::{
    branch_at, branch_from_start, continue_from, solve_at, AftOptions, ContinuationOptions, HbPoint,
};
use crate::model::{GearPair, Term};
use crate::plot::{Marker, Series};
use crate::progress::NoProgress;
use rayon::prelude::*;
use std::f64::consts::TAU;

const FM: f64 = 0.1;
const ZETA: f64 = 0.05;
const FAH: f64 = 0.05;
const FAT: f64 = 0.05;
const OMEGA: (f64, f64) = (0.2, 1.6);
/// Phase samples of the superposed series (the 15th harmonic gets ~68 per cycle).
const SAMPLES: usize = 1024;

fn model(torque: bool, ste: bool) -> Result<GearPair> {
    GearPair {
        zeta: ZETA,
        mean_force: FM,
        omega: OMEGA.0,
        ste: if ste {
            vec![Term::new(2, FAH)]
        } else {
            Vec::new()
        },
        torque: if torque {
            vec![Term::new(1, FAT)]
        } else {
            Vec::new()
        },
        stiffness: Vec::new(),
    }
    .validated()
}

/// q_a of the sum of two Fourier series `[a_0, a_1, b_1, ...]` (period 2 pi in theta).
fn qa_of_sum(a: &[f64], b: &[f64]) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..SAMPLES {
        let th = TAU * i as f64 / SAMPLES as f64;
        let mut q = 0.0;
        for c in [a, b] {
            q += c.first().copied().unwrap_or(0.0);
            for k in 1..=(c.len().saturating_sub(1) / 2) {
                let (s, co) = (k as f64 * th).sin_cos();
                q += c[2 * k - 1] * co + c[2 * k] * s;
            }
        }
        lo = lo.min(q);
        hi = hi.max(q);
    }
    0.5 * (hi - lo)
}

/// The simultaneous response may have branches not connected to the one continued from low
/// Omega (e.g. around the torque resonance). Seed them from the superposed single-excitation
/// solutions at the peak of each single response (sum of the series, one mean 1 + F_m removed),
/// polish by Newton and continue both ways; return the branch and its points on the grid.
fn seeded_branches(
    res: &[super::Traced],
    omegas: &[f64],
    opts: &AftOptions,
) -> Result<super::Traced> {
    let both = model(true, true)?;
    let cont = ContinuationOptions::default();
    let mut branch: Vec<HbPoint> = Vec::new();
    for k in 0..2 {
        let Some(peak) = res[k]
            .0
            .iter()
            .filter(|p| p.stable != Some(false))
            .max_by(|a, b| a.qa.total_cmp(&b.qa))
        else {
            continue;
        };
        let i = omegas
            .iter()
            .enumerate()
            .min_by(|a, b| {
                (a.1 - peak.omega)
                    .abs()
                    .total_cmp(&(b.1 - peak.omega).abs())
            })
            .map_or(0, |(i, _)| i);
        let (t, h) = (stable(&res[0].1[i]), stable(&res[1].1[i]));
        for a in &t {
            for b in &h {
                let mut guess: Vec<f64> =
                    a.coeffs.iter().zip(&b.coeffs).map(|(x, y)| x + y).collect();
                if let Some(g0) = guess.first_mut() {
                    *g0 -= 1.0 + FM;
                }
                let Ok(m) = both.at_omega(omegas[i]) else {
                    continue;
                };
                let Ok(start) = solve_at(&m, &guess, opts) else {
                    continue;
                };
                let known = res[2].1[i]
                    .iter()
                    .chain(branch.iter().filter(|p| p.omega == omegas[i]))
                    .any(|o| (o.qa - start.qa).abs() <= 1e-4 * (1.0 + start.qa));
                if known {
                    continue;
                }
                let down = continue_from(&both, &start, OMEGA.0, opts, &cont, &NoProgress)
                    .unwrap_or_default();
                let up = continue_from(&both, &start, OMEGA.1, opts, &cont, &NoProgress)
                    .unwrap_or_default();
                branch.extend(down.into_iter().rev());
                branch.extend(up);
            }
        }
    }
    let at = branch_at(&both, &branch, omegas, opts);
    Ok((branch, at))
}

fn stable(l: &[HbPoint]) -> Vec<&HbPoint> {
    l.iter().filter(|p| p.stable != Some(false)).collect()
}

fn rms(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt())
}

pub(crate) fn run(n: usize) -> Result<StudyOutput> {
    let omegas = super::grid(OMEGA.0, OMEGA.1, n)?;
    let opts = AftOptions {
        harmonics: HARMONICS,
        ..AftOptions::default()
    };
    let kinds = [(true, false), (false, true), (true, true)];
    let res: Vec<Result<super::Traced>> = kinds
        .par_iter()
        .map(|&(t, s)| {
            let m = model(t, s)?;
            let b =
                branch_from_start(&m, OMEGA.0, OMEGA.1, &opts, &ContinuationOptions::default())?;
            let at = branch_at(&m, &b, &omegas, &opts);
            Ok((b, at))
        })
        .collect();
    let mut res: Vec<super::Traced> = res.into_iter().collect::<Result<_>>()?;
    let extra = seeded_branches(&res, &omegas, &opts)?;
    for (k, list) in extra.1.into_iter().enumerate() {
        for p in list {
            let dup = res[2].1[k]
                .iter()
                .any(|o| (o.qa - p.qa).abs() <= 1e-7 * (1.0 + p.qa));
            if !dup {
                res[2].1[k].push(p);
            }
        }
    }
    let extra_branch = extra.0;
    let names = [
        "torque alone (AFT)",
        "STE alone (AFT)",
        "both simultaneously (AFT)",
    ];
    let mut rows = Vec::new();
    for ((branch, _), name) in res.iter().zip(names) {
        rows.extend(branch.iter().map(|p| StudyRow::from_hb(name, p)));
    }
    // Resonance windows from the single-excitation responses themselves: +-0.05 around the
    // Omega of the largest stable q_a of each.
    let peak_omega = |k: usize| {
        res[k]
            .0
            .iter()
            .filter(|p| p.stable != Some(false))
            .max_by(|a, b| a.qa.total_cmp(&b.qa))
            .map(|p| p.omega)
    };
    let (peak_t, peak_h) = (peak_omega(0), peak_omega(1));
    let near = |w: f64, c: Option<f64>| c.is_some_and(|c| (w - c).abs() <= 0.05);
    let mut sup_pts = Vec::new();
    let mut no_stable: Vec<f64> = Vec::new();
    let (mut single, mut nearest) = (Vec::new(), Vec::new());
    let (mut near_t, mut near_h) = (Vec::new(), Vec::new());
    for (i, &w) in omegas.iter().enumerate() {
        let (t, h, both) = (
            stable(&res[0].1[i]),
            stable(&res[1].1[i]),
            stable(&res[2].1[i]),
        );
        let mut here = Vec::new();
        for a in &t {
            for b in &h {
                let qa = qa_of_sum(&a.coeffs, &b.coeffs);
                here.push(qa);
                rows.push(StudyRow {
                    series: "superposition of single-excitation AFT".into(),
                    omega: w,
                    qa,
                    qm: None,
                    case: None,
                    stable: None,
                    period: Some(1),
                });
                sup_pts.push((w, qa));
            }
        }
        if both.is_empty() {
            no_stable.push(w);
        }
        if here.len() == 1 && both.len() == 1 {
            single.push(here[0] - both[0].qa);
        }
        // Every simultaneous stable solution against the nearest superposed one.
        for s in &both {
            let d = here
                .iter()
                .map(|q| q - s.qa)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()));
            if let Some(d) = d {
                nearest.push(d);
                if near(w, peak_t) {
                    near_t.push(d);
                }
                if near(w, peak_h) {
                    near_h.push(d);
                }
            }
        }
    }
    let max_abs = nearest.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let summary = serde_json::json!({
        "study": "combined", "fm": FM, "zeta": ZETA, "fah": FAH, "fat": FAT,
        "omega_h_over_omega_t": 2, "harmonics": HARMONICS,
        "omega_range": [OMEGA.0, OMEGA.1], "points": n,
        "single_valued_points": single.len(),
        "rms_superposition_minus_simultaneous_single_valued": rms(&single),
        "simultaneous_stable_solutions_compared": nearest.len(),
        "rms_nearest_superposition_minus_simultaneous": rms(&nearest),
        "max_abs_nearest_superposition_minus_simultaneous": max_abs,
        "torque_alone_peak_omega_t": peak_t,
        "ste_alone_peak_omega_t": peak_h,
        "rms_near_torque_peak": rms(&near_t),
        "rms_near_ste_peak": rms(&near_h),
        "omegas_without_stable_simultaneous_period1": no_stable,
    });
    let caption = format!(
        "F_m = {FM}, zeta = {ZETA}, F_ah = {FAH}, F_aT = {FAT}, Omega_h = 2 Omega_T; AFT H = {HARMONICS}, {n} frequencies"
    );
    let mut series = Vec::new();
    for (k, (branch, _)) in res.iter().enumerate() {
        let tri: Vec<(f64, f64, Option<bool>)> =
            branch.iter().map(|p| (p.omega, p.qa, p.stable)).collect();
        series.extend(branch_series(&tri, names[k], [2, 3, 0][k]));
    }
    let tri: Vec<(f64, f64, Option<bool>)> = extra_branch
        .iter()
        .map(|p| (p.omega, p.qa, p.stable))
        .collect();
    series.extend(branch_series(
        &tri,
        "both, branch seeded by superposition",
        5,
    ));
    series.push(
        Series::markers("superposition (stable singles)", sup_pts)
            .with_color(1)
            .with_marker(Marker::Square),
    );
    Ok(StudyOutput {
        name: "combined".into(),
        figures: vec![Figure {
            name: "fig29-combined".into(),
            title: "Torque and STE excitation combined (Fig. 29)".into(),
            panels: vec![panel("q_a versus Omega_T".into(), caption, "q_a", series)],
            cols: 1,
        }],
        rows,
        summary,
    })
}
