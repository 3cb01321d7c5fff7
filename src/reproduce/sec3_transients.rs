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

/// S3-07: non-periodic steady states over 1.0 <= Omega_h <= 1.5.
pub(crate) fn chaos_range_claim(maps: &[(f64, (&AttractorMap, &AttractorMap))]) -> Claim {
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
    let seen = maps
        .iter()
        .filter(|(_, (p, _))| dominant(p).is_some_and(|d| d.steady.period.is_none()))
        .count();
    let transient: Vec<f64> = maps
        .iter()
        .filter(|(_, (_, m))| chaotic(m).is_some_and(|c| c.kind == SetKind::ChaoticTransient))
        .map(|(w, _)| *w)
        .collect();
    let all_seen = seen == maps.len();
    let verdict = if all_seen && !transient.is_empty() {
        Verdict::BeyondPaper
    } else {
        agree_if(all_seen)
    };
    let mut expl = format!(
        "dominant set non-periodic after the default transient at {seen} of {} frequencies checked",
        maps.len()
    );
    if !transient.is_empty() {
        expl.push_str(&format!(
            "; followed, the chaos is a transient at Omega {transient:?} (the steady state there is periodic, row S3-06) and a chaotic attractor at the others"
        ));
    }
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
