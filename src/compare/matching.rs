//! Gap detection between harmonic balance and simulation on a common frequency grid.

use super::{ComparePoint, Source};
use crate::model::Impact;
use crate::sim::Motion;
use serde::Serialize;

/// A steady state one method finds and the other does not.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Gap {
    /// Excitation frequency.
    pub omega: f64,
    /// Half range of q.
    pub qa: f64,
    /// Mid range of q.
    pub qm: f64,
    /// Impact regime.
    pub case: Impact,
    /// Period in forcing periods (`None`: non-periodic).
    pub period: Option<u32>,
    /// Kind of simulated motion (`None` for harmonic balance).
    pub motion: Option<Motion>,
    /// Every source that found this steady state.
    pub sources: Vec<Source>,
    /// Relative q_a distance to the nearest point of the other method at this Omega (`None`
    /// when the other method has no point there).
    pub nearest_rel: Option<f64>,
}

/// A stable AFT point reached by a simulation attractor.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Match {
    /// Excitation frequency.
    pub omega: f64,
    /// q_a of the AFT point.
    pub aft_qa: f64,
    /// q_a of the nearest period-1 simulation steady state.
    pub sim_qa: f64,
    /// |aft_qa - sim_qa| / sim_qa.
    pub rel: f64,
    /// Impact regime of the AFT point.
    pub case: Impact,
}

/// Where harmonic balance (AFT, period 1) and simulation disagree.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Gaps {
    /// Relative q_a tolerance of a match.
    pub tolerance: f64,
    /// Stable AFT points with a period-1 simulation steady state within the tolerance.
    pub matched: Vec<Match>,
    /// Period-1 simulation steady states with no AFT point (stable or not) within the tolerance.
    pub sim_unmatched: Vec<Gap>,
    /// Stable AFT points that no simulation steady state reaches within the tolerance (e.g. an
    /// attractor whose basin misses the initial-condition grid, Sec. 5(b) case III).
    pub aft_unreached: Vec<Gap>,
    /// Subharmonic, chaotic or aperiodic simulation steady states, which a period-1 harmonic
    /// balance cannot represent.
    pub non_period1: Vec<Gap>,
}

fn same_omega(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs())
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// Distinct simulation steady states (same Omega, period and q_a, q_m within 1e-6), each with
/// every source that found it.
fn distinct_sim(points: &[ComparePoint]) -> Vec<Gap> {
    let mut out: Vec<Gap> = Vec::new();
    for p in points.iter().filter(|p| p.source.is_simulation()) {
        let same = out.iter_mut().find(|g| {
            same_omega(g.omega, p.omega)
                && g.period == p.period
                && (g.qa - p.qa).abs() <= 1e-6 * (1.0 + p.qa)
                && (g.qm - p.qm).abs() <= 1e-6 * (1.0 + p.qm.abs())
        });
        match same {
            Some(g) => {
                if !g.sources.contains(&p.source) {
                    g.sources.push(p.source);
                }
            }
            None => out.push(Gap {
                omega: p.omega,
                qa: p.qa,
                qm: p.qm,
                case: p.case,
                period: p.period,
                motion: p.motion,
                sources: vec![p.source],
                nearest_rel: None,
            }),
        }
    }
    out
}

/// Nearest relative q_a distance from `qa` to the `candidates` at `omega`.
fn nearest<'a>(
    omega: f64,
    qa: f64,
    candidates: impl Iterator<Item = &'a ComparePoint>,
) -> Option<(f64, f64)> {
    candidates
        .filter(|c| same_omega(c.omega, omega))
        .map(|c| (rel(c.qa, qa), c.qa))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// Compare the period-1 AFT points solved on the frequency grid ([`Source::AftGrid`]) with the
/// simulation points of every source, at equal Omega, by relative q_a distance `tolerance`
/// (e.g. 0.01 for 1%).
pub fn gaps(points: &[ComparePoint], tolerance: f64) -> Gaps {
    let sims = distinct_sim(points);
    let aft = || points.iter().filter(|p| p.source == Source::AftGrid);
    let period1_sim: Vec<&Gap> = sims.iter().filter(|g| g.period == Some(1)).collect();
    let mut out = Gaps {
        tolerance,
        matched: Vec::new(),
        sim_unmatched: Vec::new(),
        aft_unreached: Vec::new(),
        non_period1: Vec::new(),
    };
    for g in &sims {
        if g.period != Some(1) {
            out.non_period1.push(g.clone());
            continue;
        }
        let near = nearest(g.omega, g.qa, aft());
        if near.is_none_or(|(r, _)| r > tolerance) {
            out.sim_unmatched.push(Gap {
                nearest_rel: near.map(|n| n.0),
                ..g.clone()
            });
        }
    }
    for a in aft().filter(|a| a.stable != Some(false)) {
        let near = period1_sim
            .iter()
            .filter(|g| same_omega(g.omega, a.omega))
            .map(|g| (rel(a.qa, g.qa), g.qa))
            .min_by(|x, y| x.0.total_cmp(&y.0));
        match near {
            Some((r, sim_qa)) if r <= tolerance => out.matched.push(Match {
                omega: a.omega,
                aft_qa: a.qa,
                sim_qa,
                rel: r,
                case: a.case,
            }),
            _ => out.aft_unreached.push(Gap {
                omega: a.omega,
                qa: a.qa,
                qm: a.qm,
                case: a.case,
                period: Some(1),
                motion: None,
                sources: vec![Source::AftGrid],
                nearest_rel: near.map(|n| n.0),
            }),
        }
    }
    out
}

impl Gaps {
    /// One line per kind of disagreement, with the Omega values concerned (for a summary).
    pub fn summary_lines(&self) -> Vec<String> {
        self.summary_lines_at(None)
    }

    /// The same, each Omega also given as the pinion speed `rpm(Omega)` where the operating
    /// point is known (`compare --rig`).
    pub fn summary_lines_at(&self, rpm: Option<&dyn Fn(f64) -> f64>) -> Vec<String> {
        let list = |gs: &[Gap]| -> String {
            let mut ws: Vec<f64> = gs.iter().map(|g| g.omega).collect();
            ws.sort_by(f64::total_cmp);
            ws.dedup_by(|a, b| same_omega(*a, *b));
            ws.iter()
                .map(|w| match rpm {
                    Some(f) => format!("{w:.3} ({:.0} rpm)", f(*w)),
                    None => format!("{w:.3}"),
                })
                .collect::<Vec<_>>()
                .join(" ")
        };
        let pct = 100.0 * self.tolerance;
        let mut lines = vec![format!(
            "{} stable AFT points matched by simulation within {pct}% in q_a",
            self.matched.len()
        )];
        lines.push(format!(
            "{} period-1 simulation steady states with no AFT point within {pct}%{}{}",
            self.sim_unmatched.len(),
            if self.sim_unmatched.is_empty() {
                ""
            } else {
                " at Omega "
            },
            list(&self.sim_unmatched)
        ));
        lines.push(format!(
            "{} stable AFT points reached by no simulation steady state{}{}",
            self.aft_unreached.len(),
            if self.aft_unreached.is_empty() {
                ""
            } else {
                " at Omega "
            },
            list(&self.aft_unreached)
        ));
        lines.push(format!(
            "{} non-period-1 simulation steady states (not representable by period-1 HB){}{}",
            self.non_period1.len(),
            if self.non_period1.is_empty() {
                ""
            } else {
                " at Omega "
            },
            list(&self.non_period1)
        ));
        lines
    }
}
