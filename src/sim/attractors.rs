//! Every coexisting steady state (Sec. 3 and 5): the paper's point is that a single initial
//! condition, or a sweep that carries the last state, finds only one of them. A grid of initial
//! conditions is integrated to steady state, the steady states are deduplicated by Poincare orbit
//! (a period-p orbit counts once whatever its phase) and each gets its basin fraction.

use super::escape::EscapeRecord;
use super::flow::{PeriodFlow, State};
use super::ic_grid::IcGrid;
use super::period::{distance, scale};
use super::set_follow::{follow_sets, Member};
use super::shooting::{captured, CAPTURE_TOL};
use super::steady::{
    steady_state, steady_state_watched, Motion, SteadyOptions, SteadyState, Watched,
};
use crate::error::Result;
use crate::model::Impact;
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// What a steady state found from the grid is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SetKind {
    /// An attractor: a stable periodic orbit, or a non-periodic set from which no trajectory
    /// (fewer than [`super::MIN_ESCAPES`]) escaped while it was followed.
    Attractor,
    /// A chaotic set (positive Lyapunov exponent) that trajectories leave for periodic orbits:
    /// transient chaos, with an escape rate.
    ChaoticTransient,
    /// A non-chaotic, non-periodic set that trajectories leave (a slow approach to an orbit
    /// that was not identified within the budget).
    Transient,
}

impl SetKind {
    /// The name used in JSON and CSV: "attractor", "chaotic_transient", "transient".
    pub fn name(self) -> &'static str {
        match self {
            SetKind::Attractor => "attractor",
            SetKind::ChaoticTransient => "chaotic_transient",
            SetKind::Transient => "transient",
        }
    }
}

/// Whether basin fractions are final.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BasinTime {
    /// Every initial condition ended on an attractor: the fractions are the basins' shares.
    Asymptotic,
    /// Some initial conditions were still on a transient set at the horizon: the fractions are
    /// the shares at that time, and the periodic attractors' shares grow beyond it.
    FiniteTime,
}

/// One steady state found from the grid, with the share of initial conditions that reach it.
#[derive(Clone, Debug, Serialize)]
pub struct Attractor {
    /// The steady state (from the first initial condition, in grid order, that reached it).
    pub steady: SteadyState,
    /// Attractor or transient set.
    pub kind: SetKind,
    /// Number of grid initial conditions on it at the end of the search.
    pub basin_count: usize,
    /// basin_count / grid size (at [`AttractorMap::horizon`] when [`AttractorMap::basin_time`]
    /// is finite-time).
    pub basin_fraction: f64,
    /// Expected share once every transient has ended: basin_count plus the trajectories left on
    /// transient sets, shared among the attractors in proportion to the escapes each received.
    /// `None` when some transient set had survivors but no escape to share them by.
    pub basin_fraction_asymptotic: Option<f64>,
    /// First initial condition (grid order) that reaches it.
    pub example_ic: State,
    /// Survival and escape rate of a followed non-periodic set.
    pub escape: Option<EscapeRecord>,
}

/// All attractors found from a grid, with the attractor index of every initial condition.
#[derive(Clone, Debug, Serialize)]
pub struct AttractorMap {
    /// The grid searched.
    pub grid: IcGrid,
    /// Distinct steady states, ordered by period (non-periodic last, unsettled after them),
    /// impact regime and q_a.
    pub attractors: Vec<Attractor>,
    /// Attractor index of each grid point, in [`IcGrid::points`] order.
    pub labels: Vec<usize>,
    /// Largest age (forcing periods from the initial conditions) to which non-periodic sets were
    /// followed; 0 when none was.
    pub horizon: usize,
    /// Whether the basin fractions are final or at the horizon.
    pub basin_time: BasinTime,
}

/// Relative agreement for a negative Lyapunov exponent to be read as a Floquet rate.
const FLOQUET_MATCH: f64 = 0.1;

impl AttractorMap {
    /// For a non-periodic entry `i` with a negative largest Lyapunov exponent, the stable
    /// periodic orbit whose Floquet rate it equals (within 10%): the entry is then a slow
    /// approach to that orbit, and its "Lyapunov exponent" is the orbit's Floquet rate.
    pub fn floquet_match(&self, i: usize) -> Option<usize> {
        let a = self.attractors.get(i)?;
        let l = a
            .steady
            .lyapunov
            .filter(|l| *l < 0.0 && a.steady.period.is_none())?;
        self.attractors.iter().position(|b| {
            b.steady.is_stable_periodic()
                && b.steady
                    .floquet_rate
                    .is_some_and(|r| (r - l).abs() <= FLOQUET_MATCH * r.abs())
        })
    }
}

/// Initial conditions integrated in parallel before their results are merged.
const PHASE2_CHUNK: usize = 2048;
/// Seeds per axis integrated fully before the rest of the grid is matched against them.
const SEEDS_PER_AXIS: usize = 7;
/// Relative tolerance for two periodic orbits to be the same.
const SAME_ORBIT_TOL: f64 = 1e-6;
/// Neighbourhood, relative to the extent of a strange attractor's section, within which another
/// steady state's section points must fall to be the same attractor.
const SAME_CHAOS_TOL: f64 = 0.02;

/// Find every steady state reached from the grid of initial conditions; the non-periodic ones
/// are then followed within `opts.escape` to tell attractors from transients.
pub fn find_attractors<F: PeriodFlow + ?Sized>(
    flow: &F,
    grid: &IcGrid,
    opts: &SteadyOptions,
    progress: &dyn Progress,
) -> Result<AttractorMap> {
    opts.escape.validate()?;
    let points = grid.points();
    progress.start(points.len() as u64, "initial conditions");
    let seeds = grid.coarse_indices(SEEDS_PER_AXIS);
    let mut is_seed = vec![false; points.len()];
    for &i in &seeds {
        is_seed[i] = true;
    }
    // Phase 1: a coarse sub-grid integrated fully finds the attractors with large basins.
    let seeded: Vec<Result<SteadyState>> = seeds
        .par_iter()
        .map(|&i| {
            let r = steady_state(flow, points[i], opts);
            progress.advance(1);
            r
        })
        .collect();
    let mut found: Vec<(SteadyState, State)> = Vec::new();
    let mut labels = vec![usize::MAX; points.len()];
    let mut members = Vec::new();
    for (&i, r) in seeds.iter().zip(seeded) {
        let s = r?;
        members.extend(member(i, &s));
        labels[i] = merge(&mut found, s, points[i]);
    }
    // Phase 2: the rest stop as soon as they are captured by a known periodic attractor.
    let targets = Targets::of(&found);
    let rest: Vec<usize> = (0..points.len()).filter(|&i| !is_seed[i]).collect();
    // In chunks, merged in grid order as they come: a steady state that is not captured keeps
    // its section cloud (32 kB for a chaotic one) only until it is merged, so memory stays
    // bounded by the chunk, not the grid.
    for chunk in rest.chunks(PHASE2_CHUNK) {
        let outcomes: Vec<Result<Watched<usize>>> = chunk
            .par_iter()
            .map(|&i| {
                let r =
                    steady_state_watched(flow, points[i], opts, &mut |x| targets.capture(flow, x));
                progress.advance(1);
                r
            })
            .collect();
        for (&i, r) in chunk.iter().zip(outcomes) {
            labels[i] = match r? {
                Watched::Stopped(k) => k,
                Watched::Steady(s) => {
                    members.extend(member(i, &s));
                    merge(&mut found, *s, points[i])
                }
            };
        }
    }
    progress.finish();
    // Phase 3: the trajectories on non-periodic sets are followed to measure their escape.
    let records = if opts.escape.horizon > 0 {
        follow_sets(flow, &mut found, &mut labels, members, opts, progress)?
    } else {
        Vec::new()
    };
    Ok(order(grid, found, labels, records))
}

/// The trajectory of initial condition `ic` as a member of a non-periodic set, if it is one.
fn member(ic: usize, s: &SteadyState) -> Option<Member> {
    (s.settled && s.period.is_none()).then_some(Member {
        ic,
        x: s.end,
        age: s.age,
    })
}

/// Stable periodic orbits a trajectory can be captured by: index, section points, tolerance.
pub(crate) struct Targets(Vec<(usize, Vec<State>, f64)>);

impl Targets {
    /// The stable periodic orbits among `found`.
    pub(crate) fn of(found: &[(SteadyState, State)]) -> Self {
        Targets(
            found
                .iter()
                .enumerate()
                .filter(|(_, (s, _))| s.is_stable_periodic())
                .map(|(k, (s, _))| (k, s.poincare.clone(), CAPTURE_TOL * scale(&s.poincare)))
                .collect(),
        )
    }

    /// The orbit that captures section point `x` (see [`captured`]), if any.
    pub(crate) fn capture<F: PeriodFlow + ?Sized>(
        &self,
        flow: &F,
        x: State,
    ) -> Result<Option<usize>> {
        for (k, points, tol) in &self.0 {
            if captured(flow, x, points, *tol)? {
                return Ok(Some(*k));
            }
        }
        Ok(None)
    }
}

/// Add a steady state to the list unless it is already there; return its index. A second
/// sample of a known non-periodic attractor widens its extremes (see [`widen`]).
pub(crate) fn merge(found: &mut Vec<(SteadyState, State)>, s: SteadyState, ic: State) -> usize {
    if let Some(k) = found.iter().position(|(f, _)| same_attractor(f, &s)) {
        match (found[k].0.period, s.period) {
            (None, _) => widen(&mut found[k].0, &s),
            // The same orbit under a longer period label (unrefined repetition): keep the least.
            (Some(p), Some(r)) if r < p => found[k].0 = s,
            _ => {}
        }
        return k;
    }
    found.push((s, ic));
    found.len() - 1
}

/// Each trajectory on a strange attractor analyses a finite stretch of it, so its extremes
/// (q range, pp DTE, peak mesh force) are lower bounds of the attractor's; the union over every
/// sample is the better estimate, and the impact regime follows from it (a rare back-flank
/// contact is seen by one stretch and missed by another). The pp DTE of the union is at least
/// the larger of the two samples'; that bound is what is kept.
fn widen(known: &mut SteadyState, other: &SteadyState) {
    known.q_min = known.q_min.min(other.q_min);
    known.q_max = known.q_max.max(other.q_max);
    known.qa = 0.5 * (known.q_max - known.q_min);
    known.qm = 0.5 * (known.q_max + known.q_min);
    known.impact = Impact::from_range(known.q_min);
    known.dte_pp = known.dte_pp.max(other.dte_pp);
    known.dl_max = match (known.dl_max, other.dl_max) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    };
}

/// Two steady states are the same attractor when they are the same periodic orbit (up to phase)
/// or both non-periodic with section points on each other's cloud; every unsettled motion is
/// one entry. The impact regime of a
/// non-periodic sample is not compared: it comes from a finite stretch of the motion (see
/// `widen`), and two stretches of one strange attractor can disagree on it.
pub fn same_attractor(a: &SteadyState, b: &SteadyState) -> bool {
    // Motions that did not settle within their budget are not attractors yet: they are counted
    // together, as one entry whose basin is the share of initial conditions left unsettled.
    if !a.settled || !b.settled {
        return a.settled == b.settled;
    }
    match (a.period, b.period) {
        // Orbit identity: the same set of section points, whatever the phase or the period
        // label (a period-2p orbit that is a period-p orbit run twice is that orbit).
        (Some(_), Some(_)) => {
            let tol = SAME_ORBIT_TOL * scale(&a.poincare).max(scale(&b.poincare));
            let within = |x: &[State], y: &[State]| {
                x.iter().all(|p| y.iter().any(|q| distance(*p, *q) <= tol))
            };
            within(&a.poincare, &b.poincare) && within(&b.poincare, &a.poincare)
        }
        (None, None) => clouds_overlap(a, b) && clouds_overlap(b, a),
        _ => false,
    }
}

/// True when the section points of `a` lie on the strange attractor sampled by `b`: at least 90%
/// of them within 2% of b's extent from one of b's points. Distinct coexisting attractors are
/// separated in the section, so their points are not near each other.
fn clouds_overlap(a: &SteadyState, b: &SteadyState) -> bool {
    let pa = if a.cloud.is_empty() {
        &a.poincare
    } else {
        &a.cloud
    };
    let pb = if b.cloud.is_empty() {
        &b.poincare
    } else {
        &b.cloud
    };
    if pa.is_empty() || pb.is_empty() {
        return false;
    }
    let (lo, hi) = pb.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    let tol = SAME_CHAOS_TOL * distance(lo, hi).max(1e-12);
    let sample: Vec<State> = pa
        .iter()
        .copied()
        .step_by((pa.len() / 200).max(1))
        .collect();
    let near = sample
        .iter()
        .filter(|x| pb.iter().any(|y| distance(**x, *y) <= tol))
        .count();
    near as f64 >= 0.9 * sample.len() as f64
}

/// What a followed set is, from its escapes: a set that trajectories leave is a transient
/// (chaotic when its Lyapunov exponent is positive), otherwise an attractor.
fn kind_of(s: &SteadyState, escape: Option<&EscapeRecord>) -> SetKind {
    let leaks = escape.is_some_and(|r| {
        r.is_transient() || (r.escapes > 0 && r.survival.last().is_some_and(|p| p.alive == 0))
    });
    match (leaks, s.motion) {
        (false, _) => SetKind::Attractor,
        (true, Motion::Chaotic) => SetKind::ChaoticTransient,
        (true, _) => SetKind::Transient,
    }
}

/// Sort the steady states deterministically, classify them, and relabel the grid. A followed
/// non-chaotic set that every trajectory left is dropped: it was a slow approach to the orbits
/// they reached, not a set of its own. A chaotic transient stays listed, with its escape rate,
/// even when no trajectory is left on it.
fn order(
    grid: &IcGrid,
    found: Vec<(SteadyState, State)>,
    labels: Vec<usize>,
    records: Vec<(usize, EscapeRecord)>,
) -> AttractorMap {
    let total = labels.len().max(1);
    let mut counts = vec![0usize; found.len()];
    for &l in &labels {
        counts[l] += 1;
    }
    let horizon = records
        .iter()
        .map(|(_, r)| r.end_periods)
        .max()
        .unwrap_or(0);
    let mut escape: Vec<Option<EscapeRecord>> = vec![None; found.len()];
    for (k, r) in records {
        escape[k] = Some(r);
    }
    let kinds: Vec<SetKind> = found
        .iter()
        .zip(&escape)
        .map(|((s, _), e)| kind_of(s, e.as_ref()))
        .collect();
    let mut idx: Vec<usize> = (0..found.len())
        .filter(|&k| counts[k] > 0 || kinds[k] == SetKind::ChaoticTransient)
        .collect();
    idx.sort_by(|&i, &j| {
        let (a, b) = (&found[i].0, &found[j].0);
        (!a.settled, a.period.unwrap_or(u32::MAX), a.impact)
            .cmp(&(!b.settled, b.period.unwrap_or(u32::MAX), b.impact))
            .then(a.qa.total_cmp(&b.qa))
    });
    let mut new_of_old = vec![usize::MAX; found.len()];
    for (new, &old) in idx.iter().enumerate() {
        new_of_old[old] = new;
    }
    let asymptotic = asymptotic_counts(&found, &counts, &kinds, &escape);
    let unsettled = idx.iter().any(|&k| !found[k].0.settled);
    let on_transients = idx
        .iter()
        .any(|&k| kinds[k] != SetKind::Attractor && counts[k] > 0);
    let attractors = idx
        .iter()
        .map(|&old| Attractor {
            steady: found[old].0.clone(),
            kind: kinds[old],
            basin_count: counts[old],
            basin_fraction: counts[old] as f64 / total as f64,
            basin_fraction_asymptotic: asymptotic.as_ref().map(|a| a[old] / total as f64),
            example_ic: found[old].1,
            escape: escape[old].clone().map(|mut r| {
                for d in &mut r.destinations {
                    d.0 = new_of_old[d.0];
                }
                r
            }),
        })
        .collect();
    AttractorMap {
        grid: *grid,
        attractors,
        labels: labels.into_iter().map(|l| new_of_old[l]).collect(),
        horizon,
        basin_time: if unsettled || on_transients {
            BasinTime::FiniteTime
        } else {
            BasinTime::Asymptotic
        },
    }
}

/// Expected basin counts once every transient has ended: each attractor's count plus the
/// trajectories still on transient sets, shared in proportion to the escapes it received from
/// them. `None` when that cannot be estimated (unsettled motion, or survivors on a transient
/// without escapes to share them by).
fn asymptotic_counts(
    found: &[(SteadyState, State)],
    counts: &[usize],
    kinds: &[SetKind],
    escape: &[Option<EscapeRecord>],
) -> Option<Vec<f64>> {
    let mut out: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
    for k in 0..found.len() {
        if !found[k].0.settled && counts[k] > 0 {
            return None;
        }
        if kinds[k] == SetKind::Attractor || counts[k] == 0 {
            continue;
        }
        let r = escape[k].as_ref()?;
        if r.escapes == 0 {
            return None;
        }
        for &(to, n) in &r.destinations {
            out[to] += counts[k] as f64 * n as f64 / r.escapes as f64;
        }
        out[k] = 0.0;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Motion;

    /// A non-periodic sample whose section cloud is a ring (the same for every sample) and whose
    /// analysed stretch reached down to `q_min`.
    fn sample(q_min: f64, dte_pp: f64) -> SteadyState {
        let ring: Vec<State> = (0..400)
            .map(|k| {
                let t = k as f64 * 0.0157;
                [0.3 * t.cos(), 0.5 * t.sin()]
            })
            .collect();
        SteadyState {
            period: None,
            motion: Motion::Chaotic,
            impact: Impact::from_range(q_min),
            qa: 0.5 * (1.6 - q_min),
            qm: 0.5 * (1.6 + q_min),
            q_min,
            q_max: 1.6,
            dte_pp,
            dl_max: Some(3.0 + dte_pp),
            lyapunov: Some(0.05),
            floquet: None,
            floquet_rate: None,
            poincare: ring[..64].to_vec(),
            transient_periods: 100,
            settled: true,
            cloud: ring,
            end: [0.0, 0.0],
            age: 2184,
        }
    }

    #[test]
    fn two_stretches_of_one_strange_attractor_merge_into_their_union() {
        let single = sample(-0.8, 2.4);
        let double = sample(-1.1, 2.7);
        assert_ne!(single.impact, double.impact);
        assert!(same_attractor(&single, &double));
        let mut found = Vec::new();
        assert_eq!(merge(&mut found, single, [0.0, 0.0]), 0);
        assert_eq!(merge(&mut found, double, [1.0, 0.0]), 0);
        assert_eq!(found.len(), 1);
        let s = &found[0].0;
        assert_eq!((s.q_min, s.q_max, s.impact), (-1.1, 1.6, Impact::Double));
        assert!((s.qa - 1.35).abs() < 1e-15 && (s.qm - 0.25).abs() < 1e-15);
        assert_eq!((s.dte_pp, s.dl_max), (2.7, Some(5.7)));
        // A cloud elsewhere in the section is another attractor.
        let mut apart = sample(-0.8, 2.4);
        for p in apart.cloud.iter_mut().chain(apart.poincare.iter_mut()) {
            p[0] += 5.0;
        }
        assert_eq!(merge(&mut found, apart, [2.0, 0.0]), 1);
    }

    /// A periodic orbit as a steady state: `points` its section points, `rho` its multiplier.
    fn orbit(points: Vec<State>, rho: f64) -> SteadyState {
        SteadyState {
            period: Some(points.len() as u32),
            motion: Motion::Periodic,
            floquet: Some([(rho, 0.0), (0.1, 0.0)]),
            floquet_rate: Some(rho.abs().ln() / (points.len() as f64 * std::f64::consts::TAU)),
            poincare: points,
            lyapunov: None,
            cloud: Vec::new(),
            ..sample(0.2, 1.0)
        }
    }

    fn record(entered: usize, escapes: usize, alive: usize, to: usize) -> EscapeRecord {
        EscapeRecord {
            entered,
            start_periods: 1000,
            end_periods: 5000,
            survival: vec![
                crate::sim::SurvivalPoint {
                    periods: 1000,
                    alive: entered,
                },
                crate::sim::SurvivalPoint {
                    periods: 5000,
                    alive,
                },
            ],
            escapes,
            exposure: 1e5,
            rate: escapes as f64 / 1e5,
            rate_ci95: (0.0, 1.0),
            destinations: vec![(to, escapes)],
        }
    }

    /// Orbit identity: a period-4 label on the points of a period-2 orbit run twice is that
    /// orbit, and the least period is kept.
    #[test]
    fn an_orbit_counts_once_under_any_period_label() {
        let p2 = orbit(vec![[1.0, 0.5], [0.2, -0.3]], 0.5);
        let p4 = orbit(vec![[0.2, -0.3], [1.0, 0.5], [0.2, -0.3], [1.0, 0.5]], 0.25);
        assert!(same_attractor(&p2, &p4));
        let mut found = Vec::new();
        merge(&mut found, p4, [0.0, 0.0]);
        merge(&mut found, p2, [1.0, 0.0]);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].0.period, Some(2));
        let other = orbit(vec![[1.0, 0.5 + 1e-3], [0.2, -0.3]], 0.5);
        assert!(!same_attractor(&found[0].0, &other));
    }

    /// A chaotic set that loses trajectories is a chaotic transient, listed even when empty; a
    /// non-chaotic set every trajectory left is dropped (a slow approach, not a set); the
    /// asymptotic basins share the survivors by the observed destinations.
    #[test]
    fn followed_sets_are_classified_and_basins_projected() {
        let grid = IcGrid::new(-1.0, 1.0, 2).unwrap();
        let p2 = orbit(vec![[1.0, 0.5], [0.2, -0.3]], 0.5);
        let chaos = sample(-1.1, 2.7);
        let mut slow = sample(-0.5, 1.0);
        slow.motion = Motion::Converging;
        slow.lyapunov = Some(-0.01);
        let found = vec![(p2.clone(), [0.0; 2]), (chaos, [0.0; 2]), (slow, [0.0; 2])];
        // Two ICs on the orbit, two still on the chaotic set; the slow set emptied.
        let labels = vec![0, 0, 1, 1];
        let records = vec![(1, record(3, 1, 2, 0)), (2, record(1, 1, 0, 0))];
        let m = order(&grid, found.clone(), labels.clone(), records.clone());
        assert_eq!(m.attractors.len(), 2);
        assert_eq!(m.attractors[0].kind, SetKind::Attractor);
        assert_eq!(
            m.attractors[1].kind,
            SetKind::Attractor,
            "one escape: not yet a transient"
        );
        let records = vec![(1, record(6, 4, 2, 0)), (2, record(1, 1, 0, 0))];
        let m = order(&grid, found, labels, records);
        assert_eq!(m.attractors[1].kind, SetKind::ChaoticTransient);
        assert_eq!(m.basin_time, BasinTime::FiniteTime);
        assert_eq!(m.horizon, 5000);
        assert_eq!(m.attractors[0].basin_fraction, 0.5);
        assert_eq!(m.attractors[0].basin_fraction_asymptotic, Some(1.0));
        assert_eq!(m.attractors[1].basin_fraction_asymptotic, Some(0.0));
        assert_eq!(
            m.attractors[1].escape.as_ref().unwrap().destinations,
            vec![(0, 4)]
        );
    }

    /// A negative exponent equal to an orbit's Floquet rate names that orbit.
    #[test]
    fn negative_exponent_is_matched_to_a_floquet_rate() {
        let grid = IcGrid::new(-1.0, 1.0, 2).unwrap();
        let p2 = orbit(vec![[1.0, 0.5], [0.2, -0.3]], 0.9);
        let rate = p2.floquet_rate.unwrap();
        let mut slow = sample(-0.5, 1.0);
        slow.motion = Motion::Converging;
        slow.lyapunov = Some(1.05 * rate);
        let m = order(
            &grid,
            vec![(p2, [0.0; 2]), (slow, [0.0; 2])],
            vec![0, 0, 1, 1],
            vec![],
        );
        assert_eq!(m.floquet_match(1), Some(0));
        assert_eq!(m.floquet_match(0), None);
    }
}
