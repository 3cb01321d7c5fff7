//! Sec. 3's chaos followed past the paper's time scale (issue 23): the paper integrated a few
//! hundred forcing periods, after which the chaotic set of Fig. 4 looks like a strange
//! attractor; followed for up to 40,000 periods its trajectories keep leaving it for the
//! period-2 orbit at a constant rate, so it is a chaotic transient. Every Sec. 3 point is searched
//! both ways and the differences are tabulated; the chaos claims S3-06 and S3-07 say which they
//! are.

use super::attractor_set::{describe, describe_all, dominant, escape_text, impact_name, Point};
use super::claims::{agree_if, Claim, ReportTable, Verdict};
use super::sec3::{extra_verdict, light, Confirmations};
use crate::sim::{Attractor, AttractorMap, BasinTime, EscapeBudget, Motion, SetKind};

/// Relative q_a agreement for a periodic orbit to be the same in two searches.
const SAME_QA: f64 = 1e-6;

/// The chaotic set of a map, if any.
fn chaotic(m: &AttractorMap) -> Option<&Attractor> {
    m.attractors
        .iter()
        .find(|a| a.steady.motion == Motion::Chaotic)
}

/// The escape of the chaotic transient of the DOP853 map, in words.
fn dop853_text(rk: Option<&AttractorMap>) -> String {
    match rk.and_then(|m| {
        m.attractors
            .iter()
            .find(|a| a.kind == SetKind::ChaoticTransient)
            .and_then(|a| a.escape.as_ref())
    }) {
        Some(r) => format!(
            "the DOP853 flow (rtol 1e-11) on the same grid measures {:.2e} per period (95% {:.2e} .. {:.2e}, {} escapes)",
            r.rate, r.rate_ci95.0, r.rate_ci95.1, r.escapes
        ),
        None => "the DOP853 flow (rtol 1e-11) does not find the set to be a transient".into(),
    }
}

/// S3-06: Fig. 4's chaos, at the paper's time scale and followed.
pub(crate) fn chaos_claim(
    (paper, m): (&AttractorMap, &AttractorMap),
    conf: &Confirmations,
) -> Claim {
    let pt = light(1.0);
    let seen = dominant(paper).filter(|d| d.steady.motion == Motion::Chaotic);
    let lyap = |a: &Attractor| a.steady.lyapunov.unwrap_or(f64::NAN);
    let (verdict, expl) = match (seen, chaotic(m)) {
        (None, _) | (_, None) => (
            Verdict::Differ,
            "the dominant set is not chaotic".to_string(),
        ),
        (Some(d), Some(c)) if c.kind == SetKind::ChaoticTransient => {
            let attractors: Vec<String> = m
                .attractors
                .iter()
                .filter(|a| a.kind == SetKind::Attractor)
                .map(|a| {
                    format!(
                        "{} (asymptotic basin {})",
                        describe(a),
                        a.basin_fraction_asymptotic
                            .map_or("unknown".into(), |f| format!("{:.1}%", 100.0 * f))
                    )
                })
                .collect();
            (
                Verdict::BeyondPaper,
                format!(
                    "after the default transient ({} periods, the paper's time scale) the dominant set is chaotic (Lyapunov {:+.4}, {:.1}% of the initial conditions); followed, it is a chaotic transient, not a strange attractor: {}; the attractors are {}; {}",
                    d.steady.transient_periods,
                    lyap(d),
                    100.0 * d.basin_fraction,
                    escape_text(m, c).unwrap_or_default(),
                    attractors.join("; "),
                    dop853_text(conf.get(pt))
                ),
            )
        }
        (Some(_), Some(c)) => {
            let extra: Vec<usize> = (0..m.attractors.len())
                .filter(|&i| m.attractors[i].steady.motion != Motion::Chaotic)
                .collect();
            if extra.is_empty() {
                (
                    Verdict::Agree,
                    format!(
                        "chaotic attractor with largest Lyapunov exponent {:+.4} > 0",
                        lyap(c)
                    ),
                )
            } else {
                let (v, e) = extra_verdict(pt, m, &extra, conf);
                (
                    v,
                    format!("chaotic with Lyapunov exponent {:+.4} > 0; {e}", lyap(c)),
                )
            }
        }
    };
    Claim::new(
        "S3-06",
        "3",
        "Fig. 4",
        "F_hat 0.5, zeta 0.02, Omega_h 1.0: chaotic response, strange attractor in the Poincare map",
        describe_all(m),
        verdict,
        expl,
    )
}

/// The frequencies of S3-07's scan: 1.0 to 1.5 (or just below) in steps of `step`.
pub(crate) fn window_omegas(step: f64) -> Vec<f64> {
    let n = (0.5 / step + 1e-9).floor() as usize;
    (0..=n)
        .map(|i| crate::numeric::to_significant(1.0 + i as f64 * step, 6))
        .collect()
}

/// What the search at one frequency of the scan found.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Steady {
    /// Only non-periodic sets.
    NonPeriodic,
    /// Periodic attractors beside a non-periodic set.
    Both,
    /// Only periodic attractors: the paper's "non-periodic" fails here.
    Periodic,
}

/// The attractors of a followed search (its transient sets left out).
fn attractors_of(m: &AttractorMap) -> impl Iterator<Item = &Attractor> {
    m.attractors.iter().filter(|a| a.kind == SetKind::Attractor)
}

/// The class of a followed search: its attractors by periodicity.
fn steady_of(m: &AttractorMap) -> Steady {
    let periodic = attractors_of(m).any(|a| a.steady.period.is_some());
    let other = attractors_of(m).any(|a| a.steady.period.is_none());
    match (periodic, other) {
        (true, true) => Steady::Both,
        (true, false) => Steady::Periodic,
        _ => Steady::NonPeriodic,
    }
}

/// The periodic orbits at the scan frequencies of class `class`, each kind with the runs of
/// consecutive frequencies it was found at: "period-3 double-sided at 1.36-1.45, 1.47-1.49".
fn windows_of(scan: &[(f64, AttractorMap)], class: Steady) -> Vec<String> {
    let mut kinds: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, (_, m)) in scan.iter().enumerate() {
        if steady_of(m) != class {
            continue;
        }
        for a in attractors_of(m).filter(|a| a.steady.period.is_some()) {
            let k = format!(
                "period-{} {}",
                a.steady.period.unwrap_or(0),
                impact_name(a.steady.impact)
            );
            match kinds.iter_mut().find(|(name, _)| *name == k) {
                Some((_, at)) if at.last() != Some(&i) => at.push(i),
                Some(_) => {}
                None => kinds.push((k, vec![i])),
            }
        }
    }
    kinds
        .iter()
        .map(|(k, at)| {
            let mut runs: Vec<(usize, usize)> = Vec::new();
            for &i in at {
                match runs.last_mut() {
                    Some((_, b)) if *b + 1 == i => *b = i,
                    _ => runs.push((i, i)),
                }
            }
            let text: Vec<String> = runs
                .iter()
                .map(|&(a, b)| match a == b {
                    true => format!("{:.2}", scan[a].0),
                    false => format!("{:.2}-{:.2}", scan[a].0, scan[b].0),
                })
                .collect();
            format!("{k} at {}", text.join(", "))
        })
        .collect()
}

/// S3-07: non-periodic steady states throughout 1.0 <= Omega_h <= 1.5. `maps` are the three
/// frequencies searched at the paper's time scale and followed; `scan` the whole range on a
/// grid of `Resolution::window_step`, its non-periodic sets followed: a frequency whose only attractors are
/// periodic contradicts "throughout" (a chaotic transient there is not a steady state).
pub(crate) fn chaos_range_claim(
    maps: &[(f64, (&AttractorMap, &AttractorMap))],
    scan: &[(f64, AttractorMap)],
) -> Claim {
    let parts: Vec<String> = maps
        .iter()
        .map(|(w, (paper, m))| {
            let followed = chaotic(m).map_or("no chaotic set".into(), describe);
            format!(
                "Omega {w}: {} after the default transient; followed: {followed}",
                dominant(paper).map_or("nothing".into(), describe),
            )
        })
        .collect();
    let count = |c: Steady| scan.iter().filter(|(_, m)| steady_of(m) == c).count();
    let step = match scan {
        [a, b, ..] => crate::numeric::to_significant(b.0 - a.0, 3),
        _ => 0.0,
    };
    let (periodic, both) = (
        windows_of(scan, Steady::Periodic),
        windows_of(scan, Steady::Both),
    );
    let transient: Vec<String> = scan
        .iter()
        .filter(|(_, m)| chaotic(m).is_some_and(|c| c.kind == SetKind::ChaoticTransient))
        .map(|(w, _)| format!("{w:.2}"))
        .collect();
    let mut expl = format!(
        "on an Omega grid of step {step} ({} frequencies, each non-periodic set followed to its \
         escape) the attractors are non-periodic only at {}, periodic beside a chaotic \
         attractor at {}, and periodic only at {}",
        scan.len(),
        count(Steady::NonPeriodic),
        count(Steady::Both),
        count(Steady::Periodic)
    );
    if !periodic.is_empty() {
        expl.push_str(&format!(
            "; the paper's \"throughout\" fails in the periodic windows, where the only \
             attractors are {}",
            periodic.join("; ")
        ));
    }
    if !both.is_empty() {
        expl.push_str(&format!(
            "; beside a chaotic attractor the search finds {}",
            both.join("; ")
        ));
    }
    if !transient.is_empty() {
        expl.push_str(&format!(
            "; the chaos seen at the paper's time scale is a transient at Omega {} (row S3-06 at \
             1.0)",
            transient.join(", ")
        ));
    }
    let verdict = if !periodic.is_empty() {
        Verdict::Differ
    } else if !transient.is_empty() {
        Verdict::BeyondPaper
    } else {
        agree_if(count(Steady::NonPeriodic) + count(Steady::Both) == scan.len())
    };
    Claim::new(
        "S3-07",
        "3",
        "Sec. 3 text",
        "F_hat 0.5: non-periodic (chaotic) steady state within 1.0 <= Omega_h <= 1.5",
        parts.join("; "),
        verdict,
        expl,
    )
}

/// True when `a` (periodic) has the same orbit as an entry of `m`: period, impact and q_a.
fn has_orbit(m: &AttractorMap, a: &Attractor) -> bool {
    m.attractors.iter().any(|b| {
        b.steady.period == a.steady.period
            && b.steady.impact == a.steady.impact
            && (b.steady.qa - a.steady.qa).abs() <= SAME_QA * (1.0 + a.steady.qa.abs())
    })
}

/// What following the non-periodic sets changed at one point.
fn changes(paper: &AttractorMap, m: &AttractorMap) -> String {
    let mut out = Vec::new();
    for a in &m.attractors {
        match (&a.escape, a.kind) {
            (Some(_), SetKind::ChaoticTransient | SetKind::Transient) => out.push(format!(
                "the {} {} set is a {}: {}",
                if a.steady.motion == Motion::Chaotic {
                    "chaotic"
                } else {
                    "non-periodic"
                },
                impact_name(a.steady.impact),
                if a.kind == SetKind::ChaoticTransient {
                    "chaotic transient"
                } else {
                    "transient"
                },
                escape_text(m, a).unwrap_or_default()
            )),
            (Some(r), SetKind::Attractor) => out.push(format!(
                "the {} set is an attractor as far as followed: {} of {} trajectories left it in {:.1e} trajectory-periods (rate < {:.1e} per period at 95%)",
                impact_name(a.steady.impact),
                r.escapes,
                r.entered,
                r.exposure,
                r.rate_ci95.1
            )),
            (None, _) if a.steady.period.is_some() && !has_orbit(paper, a) => {
                out.push(format!("found only when followed: {}", describe(a)))
            }
            _ => {}
        }
    }
    for a in paper.attractors.iter() {
        if a.steady.period.is_some() && !has_orbit(m, a) {
            out.push(format!("not found when followed: {}", describe(a)));
        }
    }
    if m.basin_time == BasinTime::FiniteTime {
        let shares: Vec<String> = m
            .attractors
            .iter()
            .filter(|a| a.kind == SetKind::Attractor)
            .map(|a| {
                format!(
                    "{} {:.1}% at {} periods, {} asymptotically",
                    super::attractor_set::name(a),
                    100.0 * a.basin_fraction,
                    m.horizon,
                    a.basin_fraction_asymptotic
                        .map_or("unknown".into(), |f| format!("{:.1}%", 100.0 * f))
                )
            })
            .collect();
        out.push(format!("basins: {}", shares.join("; ")));
    }
    if out.is_empty() {
        "none".into()
    } else {
        out.join("; ")
    }
}

/// The DOP853 re-search of a point, when made: how many of the sets it finds again.
fn dop853_check(pt: Point, m: &AttractorMap, conf: &Confirmations) -> String {
    let Some(rk) = conf.get(pt) else {
        return "-".into();
    };
    let n = m.attractors.len();
    let same = (0..n)
        .filter(|&i| super::attractor_set::confirmed(m, i, rk))
        .count();
    let mut t = format!("{same} of {n} sets found again");
    if let Some(r) = rk
        .attractors
        .iter()
        .find_map(|a| a.escape.as_ref().filter(|r| r.escapes > 0))
    {
        t.push_str(&format!(
            "; escape rate {:.2e} (95% {:.2e} .. {:.2e})",
            r.rate, r.rate_ci95.0, r.rate_ci95.1
        ));
    }
    t
}

/// The table of every Sec. 3 point searched at the paper's time scale and followed.
pub(crate) fn sets_table(
    points: &[(Point, &AttractorMap, &AttractorMap)],
    conf: &Confirmations,
) -> ReportTable {
    let budget = EscapeBudget::default();
    let rows = points
        .iter()
        .map(|(pt, paper, m)| {
            vec![
                pt.caption(),
                describe_all(paper),
                describe_all(m),
                changes(paper, m),
                dop853_check(*pt, m, conf),
            ]
        })
        .collect();
    ReportTable {
        heading: "Sec. 3 attractor sets at the paper's time scale and followed".into(),
        intro: format!(
            "Every Sec. 3 point searched twice on the claim grid: after the default transient (a few hundred forcing periods, the time scale the paper integrated), and with every non-periodic set followed further, trajectory by trajectory, until {} of them left it, {:.0e} trajectory-periods were spent on it, or {} periods from the initial conditions. A trajectory leaves a set when a stable periodic orbit captures it (within 1e-6, contracting). Periodic orbits are identified by Newton shooting with the exact monodromy and counted once by orbit identity (a period-2p solution that is a period-p orbit twice is the period-p orbit). Escape rates are escapes / trajectory-periods with the exact Poisson 95% interval; a set without escapes gets the upper bound. DOP853 column: the independent integrator's search of the same points (where the claims needed it), followed the same way.",
            budget.target_escapes, budget.max_exposure, budget.horizon
        ),
        header: vec![
            "point".into(),
            "after the default transient".into(),
            "followed".into(),
            "change".into(),
            "DOP853 check".into(),
        ],
        rows,
    }
}
