//! Every coexisting steady state (Sec. 3 and 5): the paper's point is that a single initial
//! condition, or a sweep that carries the last state, finds only one of them. A grid of initial
//! conditions is integrated to steady state, the steady states are deduplicated by Poincare orbit
//! (a period-p orbit counts once whatever its phase) and each gets its basin fraction.

use super::flow::{PeriodFlow, State};
use super::ic_grid::IcGrid;
use super::period::{distance, scale};
use super::steady::{steady_state, steady_state_watched, SteadyOptions, SteadyState, Watched};
use crate::error::Result;
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
    /// Distinct steady states, ordered by period (non-periodic last), impact regime and q_a.
    pub attractors: Vec<Attractor>,
    /// Attractor index of each grid point, in [`IcGrid::points`] order.
    pub labels: Vec<usize>,
}

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
    let outcomes: Vec<Result<Watched<usize>>> = rest
        .par_iter()
        .map(|&i| {
            let r = classify(flow, points[i], &known, opts);
            progress.advance(1);
            r
        })
        .collect();
    for (&i, r) in rest.iter().zip(outcomes) {
        labels[i] = match r? {
            Watched::Stopped(k) => k,
            Watched::Steady(s) => merge(&mut found, s, points[i]),
        };
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

/// Add a steady state to the list unless it is already there; return its index.
fn merge(found: &mut Vec<(SteadyState, State)>, s: SteadyState, ic: State) -> usize {
    if let Some(k) = found.iter().position(|(f, _)| same_attractor(f, &s)) {
        return k;
    }
    found.push((s, ic));
    found.len() - 1
}

/// Two steady states are the same attractor when they are the same periodic orbit (up to phase)
/// or both non-periodic with the same impact regime and section points on each other's cloud.
pub fn same_attractor(a: &SteadyState, b: &SteadyState) -> bool {
    match (a.period, b.period) {
        (Some(p), Some(r)) if p == r => {
            let tol = SAME_ORBIT_TOL * scale(&a.poincare).max(scale(&b.poincare));
            a.poincare
                .first()
                .is_some_and(|x| b.poincare.iter().any(|y| distance(*x, *y) <= tol))
        }
        (None, None) => a.impact == b.impact && clouds_overlap(a, b) && clouds_overlap(b, a),
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
        (a.period.unwrap_or(u32::MAX), a.impact)
            .cmp(&(b.period.unwrap_or(u32::MAX), b.impact))
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
