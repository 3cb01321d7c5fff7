//! Internal STE excitation (eq. 5) versus external torque excitation (eq. 4) at equal force ratio
//! (Sec. 8.1, Figs 24, 25): F_m 0.1, zeta 0.05, F_hat 10, 2, 1, 0.5, Omega_h = Omega_T = Omega.
//! Both by AFT continuation (H = 15) with Floquet stability, plus the describing-function
//! solution of eq. 5.

use super::figures::{branch_series, case_markers, panel, Figure};
use super::output::{StudyOutput, StudyRow};
use crate::error::Result;
use crate::hb::{
    branch_at, branches_covering, df_response, AftOptions, ContinuationOptions, DfMethod,
    DfSolution, HbPoint,
};
use crate::model::{GearPair, Impact, Term};
use crate::plot::XyPlot;
use rayon::prelude::*;

const FM: f64 = 0.1;
const ZETA: f64 = 0.05;
const OMEGA: (f64, f64) = (0.2, 1.6);
const FORCE_RATIOS: [f64; 4] = [10.0, 2.0, 1.0, 0.5];
/// Harmonics of the AFT ansatz.
pub(crate) const HARMONICS: usize = 15;

/// eq. 5 (STE) or eq. 4 (torque, no STE) at force ratio F_hat.
fn model(internal: bool, fh: f64) -> Result<GearPair> {
    let amp = FM / fh;
    GearPair {
        zeta: ZETA,
        mean_force: FM,
        omega: OMEGA.0,
        ste: if internal {
            vec![Term::new(1, amp)]
        } else {
            Vec::new()
        },
        torque: if internal {
            Vec::new()
        } else {
            vec![Term::new(1, amp)]
        },
        stiffness: Vec::new(),
    }
    .validated()
}

/// The continued branches and their solutions on the grid (merged).
type Covered = (Vec<Vec<HbPoint>>, Vec<Vec<HbPoint>>);

/// Findings of one branch on the grid.
fn describe(at: &[Vec<HbPoint>], omegas: &[f64]) -> serde_json::Value {
    let stable = |l: &Vec<HbPoint>| l.iter().filter(|p| p.stable != Some(false)).count();
    let max_stable = at.iter().map(stable).max().unwrap_or(0);
    let max_all = at.iter().map(Vec::len).max().unwrap_or(0);
    let cases: Vec<u8> = {
        let mut c: Vec<u8> = at.iter().flatten().map(|p| p.case.case()).collect();
        c.sort_unstable();
        c.dedup();
        c
    };
    let first_case = at.first().and_then(|l| l.first()).map(|p| p.case.case());
    let peak = at
        .iter()
        .flatten()
        .filter(|p| p.stable != Some(false))
        .max_by(|a, b| a.qa.total_cmp(&b.qa));
    let multi: Vec<f64> = omegas
        .iter()
        .zip(at)
        .filter(|(_, l)| stable(l) > 1)
        .map(|(w, _)| *w)
        .collect();
    serde_json::json!({
        "max_coexisting_stable": max_stable,
        "max_coexisting_solutions": max_all,
        "cases_present": cases,
        "case_at_lowest_omega": first_case,
        "case_i_at_lowest_omega": at.first().is_some_and(|l| l.iter().any(|p| p.case == Impact::None)),
        "multistable_omega_range": multi.first().zip(multi.last()).map(|(a, b)| [*a, *b]),
        "peak": peak.map(|p| serde_json::json!({"omega": p.omega, "qa": p.qa, "case": p.case.case()})),
    })
}

pub(crate) fn run(n: usize) -> Result<StudyOutput> {
    let omegas = super::grid(OMEGA.0, OMEGA.1, n)?;
    let branches = aft_branches(&omegas);
    let mut rows = Vec::new();
    let (mut qa_panels, mut qm_panels, mut summaries) = (Vec::new(), Vec::new(), Vec::new());
    for (k, &fh) in FORCE_RATIOS.iter().enumerate() {
        let r = force_ratio_output(fh, &omegas, [&branches[2 * k], &branches[2 * k + 1]])?;
        rows.extend(r.rows);
        qa_panels.push(r.qa);
        qm_panels.push(r.qm);
        summaries.push(r.summary);
    }
    let fig = |name: &str, what: &str, panels| Figure {
        name: name.to_string(),
        title: format!("{what}: STE (eq. 5) vs torque (eq. 4) excitation (Figs 24, 25)"),
        panels,
        cols: 2,
    };
    Ok(StudyOutput {
        name: "excitation".into(),
        figures: vec![
            fig("fig24-25-qa", "q_a", qa_panels),
            fig("fig24-25-qm", "q_m", qm_panels),
        ],
        rows,
        summary: serde_json::json!({
            "study": "excitation", "fm": FM, "zeta": ZETA, "harmonics": HARMONICS,
            "omega_range": [OMEGA.0, OMEGA.1], "points": n, "force_ratios": summaries,
        }),
    })
}

/// For each force ratio, internal (eq. 5) then external (eq. 4) excitation: the AFT branches
/// covering the range, and the distinct solutions on them at each of `omegas` (in parallel).
fn aft_branches(omegas: &[f64]) -> Vec<Result<Covered>> {
    let opts = AftOptions {
        harmonics: HARMONICS,
        ..AftOptions::default()
    };
    let jobs: Vec<(bool, f64)> = FORCE_RATIOS
        .iter()
        .flat_map(|&fh| [(true, fh), (false, fh)])
        .collect();
    jobs.par_iter()
        .map(|&(internal, fh)| {
            let m = model(internal, fh)?;
            let cont = ContinuationOptions::default();
            let bs = branches_covering(&m, OMEGA.0, OMEGA.1, &opts, &cont)?;
            let mut at: Vec<Vec<HbPoint>> = vec![Vec::new(); omegas.len()];
            for b in &bs {
                for (k, list) in branch_at(&m, b, omegas, &opts).into_iter().enumerate() {
                    for p in list {
                        if !at[k]
                            .iter()
                            .any(|o| (o.qa - p.qa).abs() <= 1e-7 * (1.0 + p.qa))
                        {
                            at[k].push(p);
                        }
                    }
                }
            }
            Ok((bs, at))
        })
        .collect()
}

/// What one force ratio adds to the study: its q_a and q_m panels, rows and summary.
struct RatioOutput {
    qa: XyPlot,
    qm: XyPlot,
    rows: Vec<StudyRow>,
    summary: serde_json::Value,
}

/// The panels, rows and summary of force ratio `fh`: the describing-function response of
/// eq. 5 as markers by impact case, and the AFT branches `branches` (internal, external) as
/// lines.
fn force_ratio_output(
    fh: f64,
    omegas: &[f64],
    branches: [&Result<Covered>; 2],
) -> Result<RatioOutput> {
    let fah = FM / fh;
    let df = df_response(FM, fah, ZETA, omegas, DfMethod::Exact)?;
    let caption = format!(
        "F_m = {FM}, zeta = {ZETA}, F_hat = {fh}: F_ah = F_aT = {fah}; AFT H = {HARMONICS} (stable solid, unstable dashed)"
    );
    let markers = |pick: fn(&DfSolution) -> f64| {
        case_markers(
            &df.iter()
                .map(|s| (s.omega, pick(s), s.case, s.stable))
                .collect::<Vec<_>>(),
            "eq. 5 df-exact ",
        )
    };
    let mut qa_series = markers(|s| s.qa);
    let mut qm_series = markers(|s| s.qm);
    let mut rows = Vec::new();
    let mut summary = serde_json::json!({"force_ratio": fh, "amplitude": fah});
    for (j, internal) in [true, false].into_iter().enumerate() {
        let (bs, at) = match branches[j] {
            Ok(v) => v,
            Err(e) => {
                return Err(crate::error::GearError::Numerical(format!(
                    "F_hat {fh}: {e}"
                )))
            }
        };
        let label = if internal {
            "eq. 5 STE (AFT)"
        } else {
            "eq. 4 torque (AFT)"
        };
        let series = format!("F_hat = {fh}, {label}");
        for (bi, branch) in bs.iter().enumerate() {
            let tri = |f: fn(&HbPoint) -> f64| -> Vec<(f64, f64, Option<bool>)> {
                branch.iter().map(|p| (p.omega, f(p), p.stable)).collect()
            };
            let name = if bi == 0 { label } else { "" };
            qa_series.extend(branch_series(&tri(|p| p.qa), name, 4 + j));
            qm_series.extend(branch_series(&tri(|p| p.qm), name, 4 + j));
            rows.extend(branch.iter().map(|p| StudyRow::from_hb(series.clone(), p)));
        }
        summary[if internal {
            "internal_eq5"
        } else {
            "external_eq4"
        }] = describe(at, omegas);
    }
    let df_series = format!("F_hat = {fh}, eq. 5 df-exact");
    rows.extend(df.iter().map(|s| StudyRow::from_df(df_series.clone(), s)));
    let title = format!("F_hat = {fh}");
    Ok(RatioOutput {
        qa: panel(title.clone(), caption.clone(), "q_a", qa_series),
        qm: panel(title, caption, "q_m", qm_series),
        rows,
        summary,
    })
}
