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
    let (res, extra_branch) = traced(&omegas, &opts)?;
    let mut rows = Vec::new();
    for ((branch, _), name) in res.iter().zip(NAMES) {
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
    let cmp = Comparison::of(&res, &omegas, (peak_t, peak_h));
    rows.extend(cmp.superposed.iter().map(|&(w, qa)| StudyRow {
        series: "superposition of single-excitation AFT".into(),
        omega: w,
        qa,
        qm: None,
        case: None,
        stable: None,
        period: Some(1),
    }));
    let max_abs = cmp.nearest.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let summary = serde_json::json!({
        "study": "combined", "fm": FM, "zeta": ZETA, "fah": FAH, "fat": FAT,
        "omega_h_over_omega_t": 2, "harmonics": HARMONICS,
        "omega_range": [OMEGA.0, OMEGA.1], "points": n,
        "single_valued_points": cmp.single.len(),
        "rms_superposition_minus_simultaneous_single_valued": rms(&cmp.single),
        "simultaneous_stable_solutions_compared": cmp.nearest.len(),
        "rms_nearest_superposition_minus_simultaneous": rms(&cmp.nearest),
        "max_abs_nearest_superposition_minus_simultaneous": max_abs,
        "torque_alone_peak_omega_t": peak_t,
        "ste_alone_peak_omega_t": peak_h,
        "rms_near_torque_peak": rms(&cmp.near_torque),
        "rms_near_ste_peak": rms(&cmp.near_ste),
        "omegas_without_stable_simultaneous_period1": cmp.no_stable,
    });
    Ok(StudyOutput {
        name: "combined".into(),
        figures: vec![figure(n, &res, &extra_branch, cmp.superposed)],
        rows,
        summary,
    })
}

/// The three responses' series names: torque alone, STE alone, both.
const NAMES: [&str; 3] = [
    "torque alone (AFT)",
    "STE alone (AFT)",
    "both simultaneously (AFT)",
];

/// The torque-alone, STE-alone and simultaneous branches with their solutions at `omegas`
/// (the simultaneous one's completed by the branches that superposed solutions seed), and the
/// seeded branch.
fn traced(omegas: &[f64], opts: &AftOptions) -> Result<(Vec<super::Traced>, Vec<HbPoint>)> {
    let kinds = [(true, false), (false, true), (true, true)];
    let res: Vec<Result<super::Traced>> = kinds
        .par_iter()
        .map(|&(t, s)| {
            let m = model(t, s)?;
            let b = branch_from_start(&m, OMEGA.0, OMEGA.1, opts, &ContinuationOptions::default())?;
            let at = branch_at(&m, &b, omegas, opts);
            Ok((b, at))
        })
        .collect();
    let mut res: Vec<super::Traced> = res.into_iter().collect::<Result<_>>()?;
    let extra = seeded_branches(&res, omegas, opts)?;
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
    Ok((res, extra.0))
}

/// The superposition of the single-excitation solutions against the simultaneous ones at each
/// Omega_T.
struct Comparison {
    /// (Omega_T, q_a) of every superposed pair of stable single-excitation solutions.
    superposed: Vec<(f64, f64)>,
    /// Omega_T without a stable simultaneous period-1 solution.
    no_stable: Vec<f64>,
    /// Superposed minus simultaneous where each is single-valued.
    single: Vec<f64>,
    /// Every stable simultaneous solution against the nearest superposed one, and those
    /// within 0.05 of the torque-alone and STE-alone peaks.
    nearest: Vec<f64>,
    near_torque: Vec<f64>,
    near_ste: Vec<f64>,
}

impl Comparison {
    fn of(res: &[super::Traced], omegas: &[f64], peaks: (Option<f64>, Option<f64>)) -> Self {
        let near = |w: f64, c: Option<f64>| c.is_some_and(|c| (w - c).abs() <= 0.05);
        let mut c = Comparison {
            superposed: Vec::new(),
            no_stable: Vec::new(),
            single: Vec::new(),
            nearest: Vec::new(),
            near_torque: Vec::new(),
            near_ste: Vec::new(),
        };
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
                    c.superposed.push((w, qa));
                }
            }
            if both.is_empty() {
                c.no_stable.push(w);
            }
            if here.len() == 1 && both.len() == 1 {
                c.single.push(here[0] - both[0].qa);
            }
            for s in &both {
                let d = here
                    .iter()
                    .map(|q| q - s.qa)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()));
                if let Some(d) = d {
                    c.nearest.push(d);
                    if near(w, peaks.0) {
                        c.near_torque.push(d);
                    }
                    if near(w, peaks.1) {
                        c.near_ste.push(d);
                    }
                }
            }
        }
        c
    }
}

/// Fig. 29: the three branches, the seeded branch and the superposed points.
fn figure(
    n: usize,
    res: &[super::Traced],
    extra_branch: &[HbPoint],
    superposed: Vec<(f64, f64)>,
) -> Figure {
    let caption = format!(
        "F_m = {FM}, zeta = {ZETA}, F_ah = {FAH}, F_aT = {FAT}, Omega_h = 2 Omega_T; AFT H = {HARMONICS}, {n} frequencies"
    );
    let tri_of = |branch: &[HbPoint]| -> Vec<(f64, f64, Option<bool>)> {
        branch.iter().map(|p| (p.omega, p.qa, p.stable)).collect()
    };
    let mut series = Vec::new();
    for (k, (branch, _)) in res.iter().enumerate() {
        series.extend(branch_series(&tri_of(branch), NAMES[k], [2, 3, 0][k]));
    }
    series.extend(branch_series(
        &tri_of(extra_branch),
        "both, branch seeded by superposition",
        5,
    ));
    series.push(
        Series::markers("superposition (stable singles)", superposed)
            .with_color(1)
            .with_marker(Marker::Square),
    );
    Figure {
        name: "fig29-combined".into(),
        title: "Torque and STE excitation combined (Fig. 29)".into(),
        panels: vec![panel("q_a versus Omega_T".into(), caption, "q_a", series)],
        cols: 1,
    }
}
