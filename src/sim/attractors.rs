//! Every coexisting steady state (Sec. 3 and 5): the paper's point is that a single initial
//! condition, or a sweep that carries the last state, finds only one of them. A grid of initial
//! conditions is integrated to steady state, the steady states are deduplicated by Poincare orbit
//! (a period-p orbit counts once whatever its phase) and each gets its basin fraction.

use super::flow::{PeriodFlow, State};
use super::ic_grid::IcGrid;
use super::period::{distance, scale};
use super::steady::{steady_state, steady_state_watched, SteadyOptions, SteadyState, Watched};
use crate::error::Result;
use crate::model::Impact;
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// One steady state found from the grid, with the share of initial conditions that reach it.
#[derive(Clone, Debug, Serialize)]
pub struct Attractor {
    /// The steady state (from the first initial condition, in grid order, that reached it).
    pub steady: SteadyState,
    /// Number of grid initial conditions that reach it.
    pub basin_count: usize,
    /// basin_count / grid size.
    pub basin_fraction: f64,
    /// First initial condition (grid order) that reaches it.
    pub example_ic: State,
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
}

/// Initial conditions integrated in parallel before their results are merged.
const PHASE2_CHUNK: usize = 2048;
/// Seeds per axis integrated fully before the rest of the grid is matched against them.
const SEEDS_PER_AXIS: usize = 7;
/// Relative distance to a known periodic point below which a trajectory is tested for capture.
const CAPTURE_TOL: f64 = 1e-6;
/// Relative tolerance for two periodic orbits to be the same.
const SAME_ORBIT_TOL: f64 = 1e-6;
/// Neighbourhood, relative to the extent of a strange attractor's section, within which another
/// steady state's section points must fall to be the same attractor.
const SAME_CHAOS_TOL: f64 = 0.02;

/// Find every steady state reached from the grid of initial conditions.
pub fn find_attractors<F: PeriodFlow + ?Sized>(
    flow: &F,
    grid: &IcGrid,
    opts: &SteadyOptions,
    progress: &dyn Progress,
) -> Result<AttractorMap> {
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
    for (&i, r) in seeds.iter().zip(seeded) {
        labels[i] = merge(&mut found, r?, points[i]);
    }
    // Phase 2: the rest stop as soon as they are captured by a known periodic attractor.
    let known: Vec<SteadyState> = found.iter().map(|(s, _)| s.clone()).collect();
    let rest: Vec<usize> = (0..points.len()).filter(|&i| !is_seed[i]).collect();
    // In chunks, merged in grid order as they come: a steady state that is not captured keeps
    // its section cloud (32 kB for a chaotic one) only until it is merged, so memory stays
    // bounded by the chunk, not the grid.
    for chunk in rest.chunks(PHASE2_CHUNK) {
        let outcomes: Vec<Result<Watched<usize>>> = chunk
            .par_iter()
            .map(|&i| {
                let r = classify(flow, points[i], &known, opts);
                progress.advance(1);
                r
            })
            .collect();
        for (&i, r) in chunk.iter().zip(outcomes) {
            labels[i] = match r? {
                Watched::Stopped(k) => k,
                Watched::Steady(s) => merge(&mut found, s, points[i]),
            };
        }
    }
    progress.finish();
    Ok(order(grid, found, labels))
}

/// Integrate one initial condition, stopping when it is captured by a known periodic orbit:
/// within a relative 1e-6 of one of its section points and closer still p periods later.
fn classify<F: PeriodFlow + ?Sized>(
    flow: &F,
    x0: State,
    known: &[SteadyState],
    opts: &SteadyOptions,
) -> Result<Watched<usize>> {
    let targets: Vec<(usize, u32, State, f64)> = known
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_stable_periodic())
        .flat_map(|(k, s)| {
            let p = s.period.unwrap_or(1);
            let tol = CAPTURE_TOL * scale(&s.poincare);
            s.poincare.iter().map(move |&pt| (k, p, pt, tol))
        })
        .collect();
    steady_state_watched(flow, x0, opts, &mut |x| {
        for &(k, p, pt, tol) in &targets {
            let d = distance(x, pt);
            if d < tol {
                let mut y = x;
                for _ in 0..p {
                    y = flow.step(y, None)?;
                }
                if distance(y, pt) < d.max(1e-300) {
                    return Ok(Some(k));
                }
            }
        }
        Ok(None)
    })
}

/// Add a steady state to the list unless it is already there; return its index. A second
/// sample of a known non-periodic attractor widens its extremes (see [`widen`]).
fn merge(found: &mut Vec<(SteadyState, State)>, s: SteadyState, ic: State) -> usize {
    if let Some(k) = found.iter().position(|(f, _)| same_attractor(f, &s)) {
        if found[k].0.period.is_none() {
            widen(&mut found[k].0, &s);
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
/// [`widen`]), and two stretches of one strange attractor can disagree on it.
pub fn same_attractor(a: &SteadyState, b: &SteadyState) -> bool {
    // Motions that did not settle within their budget are not attractors yet: they are counted
    // together, as one entry whose basin is the share of initial conditions left unsettled.
    if !a.settled || !b.settled {
        return a.settled == b.settled;
    }
    match (a.period, b.period) {
        (Some(p), Some(r)) if p == r => {
            let tol = SAME_ORBIT_TOL * scale(&a.poincare).max(scale(&b.poincare));
            a.poincare
                .first()
                .is_some_and(|x| b.poincare.iter().any(|y| distance(*x, *y) <= tol))
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

/// Sort attractors deterministically and relabel the grid.
fn order(grid: &IcGrid, found: Vec<(SteadyState, State)>, labels: Vec<usize>) -> AttractorMap {
    let total = labels.len().max(1);
    let mut counts = vec![0usize; found.len()];
    for &l in &labels {
        counts[l] += 1;
    }
    let mut idx: Vec<usize> = (0..found.len()).collect();
    idx.sort_by(|&i, &j| {
        let (a, b) = (&found[i].0, &found[j].0);
        (!a.settled, a.period.unwrap_or(u32::MAX), a.impact)
            .cmp(&(!b.settled, b.period.unwrap_or(u32::MAX), b.impact))
            .then(a.qa.total_cmp(&b.qa))
    });
    let mut new_of_old = vec![0; found.len()];
    for (new, &old) in idx.iter().enumerate() {
        new_of_old[old] = new;
    }
    let attractors = idx
        .iter()
        .map(|&old| Attractor {
            steady: found[old].0.clone(),
            basin_count: counts[old],
            basin_fraction: counts[old] as f64 / total as f64,
            example_ic: found[old].1,
        })
        .collect();
    AttractorMap {
        grid: *grid,
        attractors,
        labels: labels.into_iter().map(|l| new_of_old[l]).collect(),
    }
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
            poincare: ring[..64].to_vec(),
            transient_periods: 100,
            settled: true,
            cloud: ring,
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
}
