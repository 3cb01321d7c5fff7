//! Fig. 28 (Sec. 8.2): the analytical frequency response to three STE harmonics by the principle
//! of superposition applied to the describing-function solutions of Sec. 4. Harmonic j alone is
//! eq. 5 at frequency j Omega with amplitude F_ahj; the superposed response is
//! q(t) = q_m + sum_j q_aj sin(j Omega t + phi_j) (phases included, as the paper's Fig. 27), whose
//! half range is q_a. Every combination of stable single-harmonic solutions gives a row, so the
//! jump region of the first harmonic yields two superposed values. The simultaneous response is
//! the AFT (H = 15) continuation of the three-harmonic model, for comparison.

use super::figures::{branch_series, panel, Figure};
use super::output::{StudyOutput, StudyRow};
use crate::error::Result;
use crate::hb::{
    continue_branch, df_solutions, AftOptions, ContinuationOptions, DfMethod, DfSolution, HbPoint,
};
use crate::model::{GearPair, Term};
use crate::plot::{Marker, Series};
use crate::progress::NoProgress;
use rayon::prelude::*;
use std::f64::consts::TAU;

const FM: f64 = 0.1;
const ZETA: f64 = 0.05;
const FAH: [f64; 3] = [0.05, 0.02, 0.01];
const OMEGA: (f64, f64) = (0.2, 1.6);
/// Phase samples for the half range of the superposed series.
const SAMPLES: usize = 720;

/// Per frequency: the stable solutions of each harmonic alone, and the superposed q_a values.
type PerOmega = (Vec<Vec<DfSolution>>, Vec<f64>);

/// Half range of sum_j q_aj sin(j theta + phi_j).
fn superposed_qa(parts: &[(usize, f64, f64)]) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..SAMPLES {
        let th = TAU * i as f64 / SAMPLES as f64;
        let q: f64 = parts
            .iter()
            .map(|&(j, a, p)| a * (j as f64 * th + p).sin())
            .sum();
        lo = lo.min(q);
        hi = hi.max(q);
    }
    0.5 * (hi - lo)
}

/// Stable describing-function solutions of harmonic j (1-based) alone at fundamental omega.
fn alone(j: usize, omega: f64) -> Result<Vec<DfSolution>> {
    Ok(
        df_solutions(FM, FAH[j - 1], ZETA, j as f64 * omega, DfMethod::Exact)?
            .into_iter()
            .filter(|s| s.stable != Some(false))
            .collect(),
    )
}

/// Run the study on `n` frequencies.
pub fn run(n: usize) -> Result<StudyOutput> {
    let omegas = super::grid(OMEGA.0, OMEGA.1, n)?;
    let per_omega = superposed(&omegas)?;
    let aft = simultaneous()?;
    let (rows, single_points, sup_points) = study_rows(&omegas, &per_omega, &aft);
    let diffs = single_valued_differences(&omegas, &per_omega, &aft);
    let rms = if diffs.is_empty() {
        f64::NAN
    } else {
        (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64).sqrt()
    };
    let multivalued: Vec<f64> = omegas
        .iter()
        .zip(&per_omega)
        .filter(|(_, (_, s))| s.len() > 1)
        .map(|(w, _)| *w)
        .collect();
    let summary = serde_json::json!({
        "study": "superposition-hb", "figure": 28, "fm": FM, "zeta": ZETA, "fah": FAH,
        "method": "df-exact per harmonic (eq. 5 at j Omega), superposed with phases; AFT H = 15 for the simultaneous response",
        "omega_range": [OMEGA.0, OMEGA.1], "points": n,
        "superposition_multivalued_omega": multivalued.first().zip(multivalued.last()).map(|(a, b)| [*a, *b]),
        "rms_superposition_minus_simultaneous_single_valued": rms,
        "single_valued_points_compared": diffs.len(),
        "aft_folds": aft.iter().filter(|p| p.fold).map(|p| p.omega).collect::<Vec<_>>(),
    });
    Ok(StudyOutput {
        name: "superposition-hb".into(),
        figures: vec![figure(n, sup_points, single_points, &aft)],
        rows,
        summary,
    })
}

/// At each frequency, in parallel: the stable solutions of each harmonic alone and the q_a of
/// every combination of them superposed.
fn superposed(omegas: &[f64]) -> Result<Vec<PerOmega>> {
    omegas
        .par_iter()
        .map(|&w| {
            let singles: Vec<Vec<DfSolution>> =
                (1..=3).map(|j| alone(j, w)).collect::<Result<_>>()?;
            let mut sup = Vec::new();
            for a in &singles[0] {
                for b in &singles[1] {
                    for c in &singles[2] {
                        sup.push(superposed_qa(&[
                            (1, a.qa, a.phase),
                            (2, b.qa, b.phase),
                            (3, c.qa, c.phase),
                        ]));
                    }
                }
            }
            Ok((singles, sup))
        })
        .collect()
}

/// The simultaneous response to the three harmonics: the AFT (H = 15) continuation.
fn simultaneous() -> Result<Vec<HbPoint>> {
    let model = GearPair {
        zeta: ZETA,
        mean_force: FM,
        omega: OMEGA.0,
        ste: (1..=3).map(|j| Term::new(j as u32, FAH[j - 1])).collect(),
        torque: Vec::new(),
        stiffness: Vec::new(),
    }
    .validated()?;
    continue_branch(
        &model,
        OMEGA.0,
        OMEGA.1,
        &AftOptions::default(),
        &ContinuationOptions::default(),
        &NoProgress,
    )
}

/// The study's rows (each harmonic alone, the superposed values, the AFT branch) and the
/// points of each harmonic alone and of the superposition for the figure.
#[allow(clippy::type_complexity)]
fn study_rows(
    omegas: &[f64],
    per_omega: &[PerOmega],
    aft: &[HbPoint],
) -> (Vec<StudyRow>, [Vec<(f64, f64)>; 3], Vec<(f64, f64)>) {
    let mut rows = Vec::new();
    let mut sup_points = Vec::new();
    let mut single_points: [Vec<(f64, f64)>; 3] = Default::default();
    for (&w, (singles, sup)) in omegas.iter().zip(per_omega) {
        for (j, sols) in singles.iter().enumerate() {
            for s in sols {
                single_points[j].push((w, s.qa));
                rows.push(StudyRow {
                    series: format!("df-exact, harmonic {} alone", j + 1),
                    omega: w,
                    qa: s.qa,
                    qm: Some(s.qm),
                    case: Some(s.case),
                    stable: s.stable,
                    period: Some(1),
                });
            }
        }
        for &q in sup {
            sup_points.push((w, q));
            rows.push(StudyRow {
                series: "superposition of df-exact solutions with phases".into(),
                omega: w,
                qa: q,
                qm: None,
                case: None,
                stable: None,
                period: None,
            });
        }
    }
    rows.extend(
        aft.iter()
            .map(|p| StudyRow::from_hb("AFT H = 15, three harmonics simultaneously", p)),
    );
    (rows, single_points, sup_points)
}

/// Where both are single-valued, the superposition less the simultaneous AFT branch
/// (interpolated along the continuation between neighbouring points on the same side).
fn single_valued_differences(omegas: &[f64], per_omega: &[PerOmega], aft: &[HbPoint]) -> Vec<f64> {
    let mut diffs = Vec::new();
    for (&w, (_, sup)) in omegas.iter().zip(per_omega) {
        let near: Vec<f64> = aft
            .windows(2)
            .filter(|s| (s[0].omega - w) * (s[1].omega - w) <= 0.0 && s[0].omega != s[1].omega)
            .map(|s| s[0].qa + (s[1].qa - s[0].qa) * (w - s[0].omega) / (s[1].omega - s[0].omega))
            .collect();
        if sup.len() == 1 && near.len() == 1 {
            diffs.push(sup[0] - near[0]);
        }
    }
    diffs
}

/// Fig. 28: the superposition, each harmonic alone and the simultaneous AFT branch.
fn figure(
    n: usize,
    sup_points: Vec<(f64, f64)>,
    single_points: [Vec<(f64, f64)>; 3],
    aft: &[HbPoint],
) -> Figure {
    let caption = format!(
        "F_m {FM}, zeta {ZETA}, F_ah1..3 = {}, {}, {}; {n} pts",
        FAH[0], FAH[1], FAH[2]
    );
    let mut series = vec![
        Series::markers("superposition of df-exact solutions", sup_points)
            .with_color(0)
            .with_marker(Marker::Dot),
    ];
    for (j, pts) in single_points.into_iter().enumerate() {
        series.push(
            Series::markers(format!("harmonic {} alone (df-exact)", j + 1), pts)
                .with_color(j + 1)
                .with_marker(Marker::Cross),
        );
    }
    let aft_pts: Vec<(f64, f64, Option<bool>)> =
        aft.iter().map(|p| (p.omega, p.qa, p.stable)).collect();
    series.extend(branch_series(
        &aft_pts,
        "AFT, three harmonics simultaneously",
        5,
    ));
    Figure {
        name: "fig28-superposition-hb".into(),
        title: "Fig. 28: superposed df-exact solutions, 3 STE harmonics".into(),
        panels: vec![panel("q_a".into(), caption, "q_a", series)],
        cols: 1,
    }
}
