//! Superposition of the STE harmonics (Sec. 8.2, Figs 26, 27): simulation sweeps (carried up) of
//! eq. 20 with F_ah1 0.05, F_ah2 0.02, F_ah3 0.01 simultaneously, and of each harmonic alone
//! (only the STE term (j Omega)^2 F_ahj sin(j Omega t)); the superposition with phases is the
//! q_a of the sum of the three single-harmonic steady-state time histories.

use super::figures::{panel, Figure};
use super::output::{StudyOutput, StudyRow};
use crate::error::{GearError, Result};
use crate::model::{GearPair, Term};
use crate::plot::{Marker, Series};
use crate::progress::NoProgress;
use crate::sim::{
    sample_trajectory, sweep, Branch, ExactFlow, IcGrid, PeriodFlow, SteadyOptions, SweepPlan,
    SweepPoint, MAX_PERIOD,
};
use rayon::prelude::*;

const FM: f64 = 0.1;
const ZETA: f64 = 0.05;
const FAH: [f64; 3] = [0.05, 0.02, 0.01];
const OMEGA: (f64, f64) = (0.2, 1.6);
/// Time samples per forcing period of the superposed history (the third harmonic gets ~170 per
/// cycle: the sampled extreme is low by at most ~2e-4 relative).
const PER_PERIOD: usize = 512;

fn model(terms: Vec<Term>) -> Result<GearPair> {
    GearPair {
        zeta: ZETA,
        mean_force: FM,
        omega: OMEGA.0,
        ste: terms,
        torque: Vec::new(),
        stiffness: Vec::new(),
    }
    .validated()
}

fn lcm(a: u32, b: u32) -> u32 {
    let gcd = |mut x: u32, mut y: u32| {
        while y != 0 {
            (x, y) = (y, x % y);
        }
        x
    };
    a / gcd(a, b) * b
}

/// q_a of the sum of the single-harmonic time histories at one Omega; also whether every single
/// response was periodic (otherwise the superposition is over 16 periods of non-periodic motion).
fn superpose(omega: f64, singles: &[&SweepPoint], models: &[GearPair]) -> Result<(f64, bool)> {
    let mut periodic = true;
    let mut span = 1u32;
    for s in singles {
        match s.steady.period {
            Some(p) => span = lcm(span, p),
            None => periodic = false,
        }
    }
    let periods = if periodic { span.min(MAX_PERIOD) } else { 16 } as usize;
    let mut sum: Vec<f64> = Vec::new();
    for (s, m) in singles.iter().zip(models) {
        let flow = ExactFlow::new(&m.at_omega(omega)?)?;
        let x0 = s
            .steady
            .poincare
            .first()
            .copied()
            .ok_or_else(|| GearError::Numerical("steady state without section point".into()))?;
        let (samples, _) = sample_trajectory(&flow, x0, periods, PER_PERIOD)?;
        if sum.is_empty() {
            sum = vec![0.0; samples.len()];
        }
        for (acc, smp) in sum.iter_mut().zip(&samples) {
            *acc += smp.q;
        }
    }
    let hi = sum.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = sum.iter().copied().fold(f64::INFINITY, f64::min);
    Ok((0.5 * (hi - lo), periodic))
}

fn rms(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt())
}

pub(crate) fn run(n: usize) -> Result<StudyOutput> {
    let omegas = super::grid(OMEGA.0, OMEGA.1, n)?;
    let mut models = vec![model(
        FAH.iter()
            .enumerate()
            .map(|(j, &a)| Term::new(j as u32 + 1, a))
            .collect(),
    )?];
    for (j, &a) in FAH.iter().enumerate() {
        models.push(model(vec![Term::new(j as u32 + 1, a)])?);
    }
    let sweeps = swept(&models, &omegas)?;
    let singles_models = &models[1..];
    let sup: Vec<Result<(f64, bool)>> = (0..omegas.len())
        .into_par_iter()
        .map(|i| {
            let singles: Vec<&SweepPoint> = sweeps[1..].iter().map(|s| &s[i]).collect();
            superpose(omegas[i], &singles, singles_models)
        })
        .collect();
    let sup: Vec<(f64, bool)> = sup.into_iter().collect::<Result<_>>()?;
    let mut rows = Vec::new();
    for (s, name) in sweeps.iter().zip(NAMES) {
        rows.extend(s.iter().map(|p| StudyRow {
            series: format!("simulation, {name}"),
            omega: p.omega,
            qa: p.steady.qa,
            qm: Some(p.steady.qm),
            case: Some(p.steady.impact),
            stable: Some(true),
            period: p.steady.period,
        }));
    }
    rows.extend(omegas.iter().zip(&sup).map(|(&w, &(qa, _))| StudyRow {
        series: "superposition with phases".into(),
        omega: w,
        qa,
        qm: None,
        case: None,
        stable: None,
        period: None,
    }));
    Ok(StudyOutput {
        name: "superposition".into(),
        figures: vec![figure(n, &omegas, &sweeps, &sup)],
        rows,
        summary: summary(n, &omegas, &sweeps, &sup),
    })
}

/// The series names of the simultaneous response and of each harmonic alone.
const NAMES: [&str; 4] = [
    "simultaneous",
    "1st harmonic alone",
    "2nd harmonic alone",
    "3rd harmonic alone",
];

/// Each model's exact-simulation sweep up `omegas`, carried from (1 + F_m, 0).
fn swept(models: &[GearPair], omegas: &[f64]) -> Result<Vec<Vec<SweepPoint>>> {
    let factory =
        |m: &GearPair| -> Result<Box<dyn PeriodFlow>> { Ok(Box::new(ExactFlow::new(m)?)) };
    let grid = IcGrid::new(-2.0, 2.0, 2)?;
    let sweeps: Vec<Result<Vec<SweepPoint>>> = models
        .par_iter()
        .map(|m| {
            let plan = SweepPlan {
                omegas: omegas.to_vec(),
                branch: Branch::Up,
                x0: [1.0 + FM, 0.0],
                grid,
                opts: SteadyOptions::default(),
            };
            sweep(&factory, m, &plan, &NoProgress)
        })
        .collect();
    let sweeps: Vec<Vec<SweepPoint>> = sweeps.into_iter().collect::<Result<_>>()?;
    if sweeps.iter().any(|s| s.len() != omegas.len()) {
        return Err(GearError::Numerical("sweep lost a frequency".into()));
    }
    Ok(sweeps)
}

/// The superposition `sup` (q_a, all singles periodic) against the simultaneous sweep: overall
/// and in windows of +-8% about Omega 1, 1/2, 1/3, with each harmonic alone there.
fn summary(
    n: usize,
    omegas: &[f64],
    sweeps: &[Vec<SweepPoint>],
    sup: &[(f64, bool)],
) -> serde_json::Value {
    let sim: Vec<f64> = sweeps[0].iter().map(|p| p.steady.qa).collect();
    let diff: Vec<f64> = sup.iter().zip(&sim).map(|(s, q)| s.0 - q).collect();
    let window = |j: usize| {
        let c = 1.0 / j as f64;
        let idx: Vec<usize> = (0..omegas.len())
            .filter(|&i| (omegas[i] - c).abs() <= 0.08 * c)
            .collect();
        let d: Vec<f64> = idx.iter().map(|&i| diff[i]).collect();
        let alone: Vec<f64> = idx
            .iter()
            .map(|&i| sweeps[j][i].steady.qa - sim[i])
            .collect();
        let peak = idx.iter().map(|&i| sim[i]).fold(0.0, f64::max);
        serde_json::json!({
            "omega_window": [0.92 * c, 1.08 * c], "points": idx.len(),
            "peak_qa_simultaneous": peak,
            "rms_superposition_minus_simultaneous": rms(&d),
            "rms_harmonic_alone_minus_simultaneous": rms(&alone),
        })
    };
    let rel: Vec<f64> = diff.iter().zip(&sim).map(|(d, q)| d / q).collect();
    serde_json::json!({
        "study": "superposition", "fm": FM, "zeta": ZETA, "fah": FAH,
        "method": "exact simulation, carried sweep up from (1 + F_m, 0)",
        "omega_range": [OMEGA.0, OMEGA.1], "points": n,
        "rms_superposition_minus_simultaneous": rms(&diff),
        "max_abs_superposition_minus_simultaneous": diff.iter().fold(0.0f64, |m, d| m.max(d.abs())),
        "rms_relative": rms(&rel),
        "all_single_responses_periodic": sup.iter().all(|s| s.1),
        "non_period1_simultaneous": sweeps[0].iter().filter(|p| p.steady.period != Some(1)).count(),
        "near_resonance": {"omega_1": window(1), "omega_1_2": window(2), "omega_1_3": window(3)},
    })
}

/// Figs 26 and 27: each harmonic alone, and the superposition with phases, over the
/// simultaneous response.
fn figure(n: usize, omegas: &[f64], sweeps: &[Vec<SweepPoint>], sup: &[(f64, bool)]) -> Figure {
    let caption = format!(
        "F_m {FM}, zeta {ZETA}, F_ah1..3 = {}, {}, {}; sim. sweep up, {n} pts",
        FAH[0], FAH[1], FAH[2]
    );
    let line = |i: usize| -> Vec<(f64, f64)> {
        sweeps[i].iter().map(|p| (p.omega, p.steady.qa)).collect()
    };
    let mut fig26 = vec![Series::line("three harmonics simultaneously", line(0)).with_color(0)];
    for (j, name) in NAMES.iter().enumerate().skip(1) {
        fig26.push(Series::dashed(*name, line(j)).with_color(j));
    }
    let fig27 = vec![
        Series::line("three harmonics simultaneously", line(0)).with_color(0),
        Series::line_markers(
            "superposition with phases",
            omegas.iter().zip(sup).map(|(&w, s)| (w, s.0)).collect(),
        )
        .with_color(1)
        .with_marker(Marker::Square),
    ];
    Figure {
        name: "fig26-27-superposition".into(),
        title: "STE harmonics: simultaneous vs separate (Fig. 26) and superposed (Fig. 27)".into(),
        panels: vec![
            panel(
                "Fig. 26: each harmonic alone".into(),
                caption.clone(),
                "q_a",
                fig26,
            ),
            panel(
                "Fig. 27: superposition with phases".into(),
                caption,
                "q_a",
                fig27,
            ),
        ],
        cols: 2,
    }
}
