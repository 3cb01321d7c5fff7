//! Parametric studies by the describing-function solution with exact g, h (eq. 8-10; Sec. 6):
//! force ratio through F_ah (Figs 15, 16), through F_m (Fig. 17) and damping (Fig. 18).

use super::figures::{case_markers, panel, Figure};
use super::output::{StudyOutput, StudyRow};
use crate::error::Result;
use crate::hb::{df_response, response_ranges, transition_frequencies, DfMethod, DfSolution};
use crate::model::Impact;

/// Frequency range of Figs 15-18.
const OMEGA: (f64, f64) = (0.2, 1.6);

/// One curve: F_m, F_ah, zeta.
#[derive(Clone, Copy, Debug)]
struct Case {
    fm: f64,
    fah: f64,
    zeta: f64,
}

impl Case {
    fn label(&self) -> String {
        format!(
            "F_m = {}, F_ah = {}, F_hat = {}, zeta = {}",
            self.fm,
            round(self.fah),
            round(self.fm / self.fah),
            self.zeta
        )
    }
}

fn round(v: f64) -> f64 {
    (v * 1e9).round() / 1e9
}

/// Linear (contact-only) amplitude of eq. 13: q_a = Omega^2 F_ah / sqrt((1 - Omega^2)^2 +
/// (2 zeta Omega)^2).
pub(crate) fn eq13(fah: f64, zeta: f64, omega: f64) -> f64 {
    let w2 = omega * omega;
    w2 * fah / ((1.0 - w2).powi(2) + (2.0 * zeta * omega).powi(2)).sqrt()
}

/// Figs 15, 16: F_m 0.1, zeta 0.05, F_hat 10, 2, 1, 0.5 (F_ah = F_m / F_hat).
pub(crate) fn load(n: usize) -> Result<StudyOutput> {
    let cases = [10.0, 2.0, 1.0, 0.5].map(|fh| Case {
        fm: 0.1,
        fah: 0.1 / fh,
        zeta: 0.05,
    });
    family(
        "parametric-load",
        ["fig15-qa", "fig16-qm"],
        "force ratio through F_ah (Figs 15, 16)",
        &cases,
        n,
    )
}

/// Fig. 17: F_ah 0.05, zeta 0.05, F_hat 10, 4, 2, 1 (F_m = F_hat F_ah).
pub(crate) fn mean(n: usize) -> Result<StudyOutput> {
    let cases = [10.0, 4.0, 2.0, 1.0].map(|fh| Case {
        fm: round(0.05 * fh),
        fah: 0.05,
        zeta: 0.05,
    });
    family(
        "parametric-mean",
        ["fig17-qa", "fig17-qm"],
        "force ratio through F_m (Fig. 17)",
        &cases,
        n,
    )
}

/// Fig. 18: F_m 0.1, F_hat 2, zeta 0.025, 0.05, 0.075, 0.1.
pub(crate) fn damping(n: usize) -> Result<StudyOutput> {
    let cases = [0.025, 0.05, 0.075, 0.1].map(|zeta| Case {
        fm: 0.1,
        fah: 0.05,
        zeta,
    });
    family(
        "damping",
        ["fig18-qa", "fig18-qm"],
        "damping ratio (Fig. 18)",
        &cases,
        n,
    )
}

/// Summary of one curve: solution counts, impact regimes, eq. 14 transitions, agreement of the
/// case I solutions with eq. 13.
fn summarize(c: &Case, sols: &[DfSolution], omegas: &[f64]) -> Result<serde_json::Value> {
    let (t1, t2) = transition_frequencies(c.fm, c.fah, c.zeta)?;
    let r = response_ranges(sols, omegas);
    let pair = |x: Option<(f64, f64)>| x.map(|(a, b)| [a, b]);
    let eq13_err = sols
        .iter()
        .filter(|s| s.case == Impact::None)
        .map(|s| (s.qa - eq13(c.fah, c.zeta, s.omega)).abs())
        .fold(0.0, f64::max);
    let peak = sols
        .iter()
        .filter(|s| s.stable != Some(false))
        .max_by(|a, b| a.qa.total_cmp(&b.qa));
    Ok(serde_json::json!({
        "fm": c.fm, "fah": c.fah, "zeta": c.zeta, "force_ratio": c.fm / c.fah,
        "eq14_transitions": [t1, t2],
        "max_solutions_per_omega": r.max_solutions,
        "multivalued_omega_range": pair(r.multivalued),
        "case_i_omega_range": pair(r.case_i),
        "case_ii_omega_range": pair(r.case_ii),
        "case_iii_omega_range": pair(r.case_iii),
        "case_i_max_abs_diff_from_eq13": eq13_err,
        "peak": peak.map(|p| serde_json::json!({"omega": p.omega, "qa": p.qa, "case": p.case.case()})),
    }))
}

fn family(
    name: &str,
    stems: [&str; 2],
    what: &str,
    cases: &[Case],
    n: usize,
) -> Result<StudyOutput> {
    let omegas = super::grid(OMEGA.0, OMEGA.1, n)?;
    let mut rows = Vec::new();
    let mut qa_panels = Vec::new();
    let mut qm_panels = Vec::new();
    let mut summaries = Vec::new();
    for c in cases {
        let sols = df_response(c.fm, c.fah, c.zeta, &omegas, DfMethod::Exact)?;
        let label = c.label();
        let caption = format!("{label}; df-exact (eq. 8-10), {n} frequencies");
        let pick = |f: fn(&DfSolution) -> f64| -> Vec<(f64, f64, Impact, Option<bool>)> {
            sols.iter()
                .map(|s| (s.omega, f(s), s.case, s.stable))
                .collect()
        };
        let title = format!("F_hat = {}, zeta = {}", round(c.fm / c.fah), c.zeta);
        qa_panels.push(panel(
            title.clone(),
            caption.clone(),
            "q_a",
            case_markers(&pick(|s| s.qa), ""),
        ));
        qm_panels.push(panel(
            title,
            caption,
            "q_m",
            case_markers(&pick(|s| s.qm), ""),
        ));
        rows.extend(sols.iter().map(|s| StudyRow::from_df(label.clone(), s)));
        summaries.push(summarize(c, &sols, &omegas)?);
    }
    let figures = vec![
        Figure {
            name: stems[0].to_string(),
            title: format!("q_a versus Omega: {what}"),
            panels: qa_panels,
            cols: 2,
        },
        Figure {
            name: stems[1].to_string(),
            title: format!("q_m versus Omega: {what}"),
            panels: qm_panels,
            cols: 2,
        },
    ];
    Ok(StudyOutput {
        name: name.to_string(),
        figures,
        rows,
        summary: serde_json::json!({
            "study": name, "method": "df-exact (eq. 8-10)", "omega_range": [OMEGA.0, OMEGA.1],
            "points": n, "curves": summaries,
        }),
    })
}
