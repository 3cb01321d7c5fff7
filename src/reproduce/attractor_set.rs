//! Coexisting steady states of one parameter set (Sec. 3): computed from a grid of initial
//! conditions with the exact flow, described in words, matched against what the paper lists, and
//! re-computed with the independent DOP853 flow before an additional orbit is reported.

use crate::error::Result;
use crate::model::{GearPair, Impact};
use crate::progress::NoProgress;
use crate::sim::{
    find_attractors, Attractor, AttractorMap, EscapeBudget, ExactFlow, IcGrid, Motion, PeriodFlow,
    RkFlow, SetKind, SteadyOptions,
};

/// Relative tolerance of DOP853 in the confirmation runs (Poincare points to ~1e-10).
pub const CONFIRM_RTOL: f64 = 1e-11;
/// Relative q_a agreement required between the two integrators for the same orbit.
pub const CONFIRM_QA_TOL: f64 = 1e-6;

/// Parameters of one attractor search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Mean load F_m.
    pub fm: f64,
    /// STE amplitude F_ah.
    pub fah: f64,
    /// Damping ratio.
    pub zeta: f64,
    /// Mesh frequency Omega_h.
    pub omega: f64,
}

impl Point {
    /// The paper's model at this point.
    pub fn model(&self) -> Result<GearPair> {
        GearPair::paper(self.fm, self.fah, self.zeta, self.omega)
    }

    /// "F_m = .., F_ah = .. (F_hat = ..), zeta = .., Omega_h = .."
    pub fn caption(&self) -> String {
        format!(
            "F_m = {}, F_ah = {} (F_hat = {}), zeta = {}, Omega_h = {}",
            self.fm,
            self.fah,
            round3(self.fm / self.fah),
            self.zeta,
            self.omega
        )
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// How long a search looks at the steady states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Horizon {
    /// The default transient and analysis only: the few hundred periods the paper integrated.
    Paper,
    /// Non-periodic sets followed to measure their escape (the default budget).
    Followed,
}

/// Attractors from an IC grid with the chosen integrator (exact unless `dop853`).
pub fn search(p: &Point, grid: &IcGrid, dop853: bool, horizon: Horizon) -> Result<AttractorMap> {
    let model = p.model()?;
    let flow: Box<dyn PeriodFlow> = if dop853 {
        Box::new(RkFlow::new(&model, CONFIRM_RTOL)?)
    } else {
        Box::new(ExactFlow::new(&model)?)
    };
    let opts = SteadyOptions {
        escape: match horizon {
            Horizon::Paper => EscapeBudget::none(),
            Horizon::Followed => EscapeBudget::default(),
        },
        ..SteadyOptions::default()
    };
    find_attractors(flow.as_ref(), grid, &opts, &NoProgress)
}

/// Kind of an attractor as the paper names it: a period (None for non-periodic) and an impact
/// regime.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Kind {
    /// Period p, `None` for non-periodic motion.
    pub period: Option<u32>,
    /// Impact regime.
    pub impact: Impact,
}

/// Kind of one attractor.
pub fn kind(a: &Attractor) -> Kind {
    Kind {
        period: a.steady.period,
        impact: a.steady.impact,
    }
}

/// "period-2", "chaotic", "chaotic transient", "aperiodic", "converging" or "transient".
pub fn motion_name(a: &Attractor) -> String {
    match (a.steady.period, a.kind, a.steady.motion) {
        (Some(p), _, _) => format!("period-{p}"),
        (None, SetKind::ChaoticTransient, _) => "chaotic transient".to_string(),
        (None, SetKind::Transient, _) => "transient".to_string(),
        (None, _, Motion::Chaotic) => "chaotic".to_string(),
        (None, _, Motion::Converging) => "converging".to_string(),
        (None, _, _) => "aperiodic".to_string(),
    }
}

/// The name of an attractor or transient set: "period-2 single-sided", "chaotic transient
/// double-sided" (its motion and impact regime; the one naming used by reports, maps and the
/// command line).
pub fn name(a: &Attractor) -> String {
    format!("{} {}", motion_name(a), impact_name(a.steady.impact))
}

/// One attractor in words: "period-1 single-sided (q_a 0.512, basin 31.3%)"; a followed
/// non-periodic set adds its escape rate, or the bound on it when none escaped.
pub fn describe(a: &Attractor) -> String {
    let lyap = match (a.steady.period, a.steady.lyapunov) {
        (None, Some(l)) => format!(", Lyapunov {l:+.4}"),
        _ => String::new(),
    };
    let escape = match &a.escape {
        Some(r) if r.escapes > 0 => format!(
            ", escape rate {:.2e}/period (95% {:.2e} .. {:.2e})",
            r.rate, r.rate_ci95.0, r.rate_ci95.1
        ),
        Some(r) => format!(
            ", no escape in {:.1e} trajectory-periods (rate < {:.1e})",
            r.exposure, r.rate_ci95.1
        ),
        None => String::new(),
    };
    format!(
        "{} (q_a {:.3}, basin {:.1}%{lyap}{escape})",
        name(a),
        a.steady.qa,
        100.0 * a.basin_fraction
    )
}

/// "103 of 403 trajectories followed from period 2259 to 7759 left it for the period-2
/// single-sided orbit (q_a 0.573): escape rate 5.50e-5 per period (95% 4.49e-5-6.67e-5), mean
/// lifetime 18187 periods", for a followed set of `m` with escapes.
pub fn escape_text(m: &AttractorMap, a: &Attractor) -> Option<String> {
    let r = a.escape.as_ref().filter(|r| r.escapes > 0)?;
    let dest: Vec<String> = r
        .destinations
        .iter()
        .map(|&(k, n)| {
            let d = &m.attractors[k];
            format!(
                "{n} to the period-{} {} orbit (q_a {:.3})",
                d.steady.period.unwrap_or(0),
                impact_name(d.steady.impact),
                d.steady.qa
            )
        })
        .collect();
    Some(format!(
        "{} of {} trajectories followed from period {} to {} left it ({}): escape rate {:.2e} per period (95% {:.2e} .. {:.2e}), mean lifetime {:.0} periods",
        r.escapes,
        r.entered,
        r.start_periods,
        r.end_periods,
        dest.join(", "),
        r.rate,
        r.rate_ci95.0,
        r.rate_ci95.1,
        1.0 / r.rate
    ))
}

/// "no-impact", "single-sided", "double-sided".
pub fn impact_name(i: Impact) -> &'static str {
    match i {
        Impact::None => "no-impact",
        Impact::Single => "single-sided",
        Impact::Double => "double-sided",
    }
}

/// All attractors of a map in words, separated by "; ".
pub fn describe_all(m: &AttractorMap) -> String {
    m.attractors
        .iter()
        .map(describe)
        .collect::<Vec<_>>()
        .join("; ")
}

/// The attractor with the largest basin (first in order on ties).
pub fn dominant(m: &AttractorMap) -> Option<&Attractor> {
    m.attractors
        .iter()
        .fold(None, |best: Option<&Attractor>, a| match best {
            Some(b) if b.basin_count >= a.basin_count => Some(b),
            _ => Some(a),
        })
}

/// What the paper lists at one point: a period (`None` = non-periodic) and, when the paper
/// names it, an impact regime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Expected {
    /// Period, `None` for chaos / non-periodic.
    pub period: Option<u32>,
    /// Impact regime when stated.
    pub impact: Option<Impact>,
}

/// Result of matching the found attractors against the paper's list.
#[derive(Clone, Debug, Default)]
pub struct Matching {
    /// Indices of the paper's attractors that were not found.
    pub missing: Vec<usize>,
    /// Indices (into the map) of attractors beyond the paper's list.
    pub extra: Vec<usize>,
}

/// Assign each expected attractor to a distinct found one of that kind (first in map order).
pub fn match_expected(m: &AttractorMap, expected: &[Expected]) -> Matching {
    let mut used = vec![false; m.attractors.len()];
    let mut missing = Vec::new();
    for (e_idx, e) in expected.iter().enumerate() {
        let hit = m.attractors.iter().enumerate().position(|(i, a)| {
            !used[i]
                && a.steady.period == e.period
                && e.impact.is_none_or(|imp| imp == a.steady.impact)
        });
        match hit {
            Some(i) => used[i] = true,
            None => missing.push(e_idx),
        }
    }
    let extra = (0..m.attractors.len()).filter(|&i| !used[i]).collect();
    Matching { missing, extra }
}

/// True when attractor `i` of `exact` is found again by the DOP853 map: a periodic orbit with
/// the same period and impact regime and q_a within [`CONFIRM_QA_TOL`]; a non-periodic set with
/// the same impact regime, kind of motion (chaotic or not) and kind (attractor or transient),
/// the DOP853 map holding at
/// least as many such attractors as the exact one (so that one DOP853 attractor cannot confirm
/// two exact ones).
pub fn confirmed(exact: &AttractorMap, i: usize, rk: &AttractorMap) -> bool {
    let same = |a: &Attractor, b: &Attractor| {
        kind(a) == kind(b)
            && a.kind == b.kind
            && a.steady.motion == b.steady.motion
            && (a.steady.period.is_none()
                || (a.steady.qa - b.steady.qa).abs() <= CONFIRM_QA_TOL * (1.0 + a.steady.qa.abs()))
    };
    exact.attractors.get(i).is_some_and(|a| {
        let in_exact = exact.attractors.iter().filter(|b| same(a, b)).count();
        let in_rk = rk.attractors.iter().filter(|b| same(a, b)).count();
        in_rk >= in_exact.max(1)
    })
}
