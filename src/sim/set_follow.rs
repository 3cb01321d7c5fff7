//! Following the trajectories of non-periodic sets past the steady-state analysis (issue 23):
//! the chaotic set of Fig. 4 looks like an attractor after a few hundred periods, but its
//! trajectories keep leaving it for the period-2 orbit, one in about 18,000 periods. Every
//! trajectory an attractor search left on a non-periodic set is integrated further, in parallel
//! blocks, watched for capture by a stable periodic orbit (known, or found by shooting on the
//! way); each set's survival curve, escapes and destinations are recorded (see [`super::escape`]).

use super::attractors::{merge, Targets};
use super::escape::{escape_rate, EscapeBudget, EscapeRecord, SurvivalPoint};
use super::flow::{PeriodFlow, State};
use super::steady::{run_transient, steady_state, SteadyOptions, SteadyState};
use crate::error::Result;
use crate::progress::Progress;
use rayon::prelude::*;

/// A trajectory left on a non-periodic set by the steady-state analysis.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Member {
    /// Index of its initial condition in the grid.
    pub(crate) ic: usize,
    /// Section point where its analysis stopped.
    pub(crate) x: State,
    /// Forcing periods integrated from its initial condition to `x`.
    pub(crate) age: usize,
}

/// One followed trajectory.
struct Track {
    member: Member,
    /// The set it was on when followed (index into the found steady states).
    set: usize,
    /// Age at which it was captured by a periodic orbit, and that orbit's index.
    exit: Option<(usize, usize)>,
}

/// What one block of integration did to a trajectory.
enum Step {
    /// Still on the set, at this state and age.
    On(State, usize),
    /// Captured by the known orbit `k` at this age.
    Captured(usize, usize),
    /// Captured by an orbit not known yet (its steady state) at this age.
    NewOrbit(Box<SteadyState>, usize),
}

/// Follow every member of the non-periodic sets (labels in `labels`, indices into `found`) within
/// `opts.escape`; captured trajectories are relabelled to their orbit (added to `found` when new).
/// Returns, per followed set, its index and what was observed.
pub(crate) fn follow_sets<F: PeriodFlow + ?Sized>(
    flow: &F,
    found: &mut Vec<(SteadyState, State)>,
    labels: &mut [usize],
    members: Vec<Member>,
    opts: &SteadyOptions,
    progress: &dyn Progress,
) -> Result<Vec<(usize, EscapeRecord)>> {
    let budget = opts.escape;
    budget.validate()?;
    // The observation starts one block after the last analysis ended: trajectories that left
    // the set during their Lyapunov run are still approaching their orbit for up to a few
    // hundred periods, and would otherwise count as early escapes.
    let Some(start) = members.iter().map(|m| m.age + budget.block).max() else {
        return Ok(Vec::new());
    };
    if start >= budget.horizon {
        return Ok(Vec::new());
    }
    let mut tracks: Vec<Track> = members
        .into_iter()
        .map(|m| Track {
            set: labels[m.ic],
            member: m,
            exit: None,
        })
        .collect();
    let mut sets: Vec<usize> = tracks.iter().map(|t| t.set).collect();
    sets.sort_unstable();
    sets.dedup();
    let mut records: Vec<Record> = sets.iter().map(|&s| Record::new(s, start)).collect();
    let planned: f64 = records
        .iter()
        .map(|r| {
            let n = tracks.iter().filter(|t| t.set == r.set).count() as f64;
            budget.max_exposure.min(n * (budget.horizon - start) as f64)
        })
        .sum();
    progress.start(planned as u64, "periods followed on non-periodic sets");
    let mut checkpoint = start;
    loop {
        let active: Vec<usize> = records.iter().filter(|r| !r.done).map(|r| r.set).collect();
        advance_block(flow, found, labels, &mut tracks, &active, checkpoint, opts)?;
        for r in records.iter_mut().filter(|r| !r.done) {
            r.observe(&tracks, checkpoint, &budget, progress);
        }
        if records.iter().all(|r| r.done) {
            break;
        }
        checkpoint = (checkpoint + budget.block).min(budget.horizon);
    }
    progress.finish();
    Ok(records
        .into_iter()
        .map(|r| (r.set, r.finish(&tracks)))
        .collect())
}

/// Integrate every trajectory still on an `active` set up to age `checkpoint`.
fn advance_block<F: PeriodFlow + ?Sized>(
    flow: &F,
    found: &mut Vec<(SteadyState, State)>,
    labels: &mut [usize],
    tracks: &mut [Track],
    active: &[usize],
    checkpoint: usize,
    opts: &SteadyOptions,
) -> Result<()> {
    let targets = Targets::of(found);
    let steps: Vec<Result<Option<Step>>> = tracks
        .par_iter()
        .map(|t| {
            let running = t.exit.is_none() && active.contains(&t.set) && t.member.age <= checkpoint;
            if !running {
                return Ok(None);
            }
            step_track(flow, &t.member, checkpoint, &targets, opts).map(Some)
        })
        .collect();
    for (t, step) in tracks.iter_mut().zip(steps) {
        match step? {
            None => {}
            Some(Step::On(x, age)) => {
                t.member.x = x;
                t.member.age = age;
            }
            Some(Step::Captured(k, age)) => {
                t.exit = Some((age, k));
                t.member.age = age;
                labels[t.member.ic] = k;
            }
            Some(Step::NewOrbit(s, age)) => {
                let k = merge(found, *s, t.member.x);
                t.exit = Some((age, k));
                t.member.age = age;
                labels[t.member.ic] = k;
            }
        }
    }
    Ok(())
}

/// Integrate one trajectory to age `checkpoint`, stopping at capture by a known orbit or at a
/// stable orbit found by the transient's shooting. A trajectory already at `checkpoint` is only
/// tested for capture: one that left the set during its Lyapunov run is on its orbit when the
/// observation starts, and is not counted as an escape observed.
fn step_track<F: PeriodFlow + ?Sized>(
    flow: &F,
    m: &Member,
    checkpoint: usize,
    targets: &Targets,
    opts: &SteadyOptions,
) -> Result<Step> {
    if m.age == checkpoint {
        return Ok(match targets.capture(flow, m.x)? {
            Some(k) => Step::Captured(k, m.age),
            None => Step::On(m.x, m.age),
        });
    }
    let mut watch = |x: State| targets.capture(flow, x);
    match run_transient(flow, m.x, checkpoint - m.age, true, &mut watch)? {
        Err((k, used)) => Ok(Step::Captured(k, m.age + used)),
        Ok(end) => match end.orbit {
            Some(o) => {
                let s = steady_state(flow, o.points[0], opts)?;
                Ok(Step::NewOrbit(Box::new(s), m.age + end.used))
            }
            None => Ok(Step::On(end.x, m.age + end.used)),
        },
    }
}

/// Running observation of one set.
struct Record {
    set: usize,
    start: usize,
    entered: Option<usize>,
    survival: Vec<SurvivalPoint>,
    end: usize,
    done: bool,
    reported: f64,
}

impl Record {
    fn new(set: usize, start: usize) -> Self {
        Record {
            set,
            start,
            entered: None,
            survival: Vec::new(),
            end: start,
            done: false,
            reported: 0.0,
        }
    }

    /// Trajectories of this set on it at age `at`.
    fn alive_at(&self, tracks: &[Track], at: usize) -> usize {
        tracks
            .iter()
            .filter(|t| t.set == self.set && t.exit.is_none_or(|(age, _)| age > at))
            .count()
    }

    /// Escapes after the start and the exposure up to age `end`.
    fn escapes_exposure(&self, tracks: &[Track], end: usize) -> (usize, f64) {
        let mut escapes = 0;
        let mut exposure = 0.0;
        for t in tracks.iter().filter(|t| t.set == self.set) {
            match t.exit {
                Some((age, _)) if age <= self.start => {}
                Some((age, _)) => {
                    escapes += 1;
                    exposure += (age.min(end) - self.start) as f64;
                }
                None => exposure += (end - self.start) as f64,
            }
        }
        (escapes, exposure)
    }

    /// Record the checkpoint and decide whether the set has been followed long enough.
    fn observe(
        &mut self,
        tracks: &[Track],
        checkpoint: usize,
        budget: &EscapeBudget,
        progress: &dyn Progress,
    ) {
        let alive = self.alive_at(tracks, checkpoint);
        if self.entered.is_none() {
            self.entered = Some(alive);
        }
        self.survival.push(SurvivalPoint {
            periods: checkpoint,
            alive,
        });
        self.end = checkpoint;
        let (escapes, exposure) = self.escapes_exposure(tracks, checkpoint);
        progress.advance((exposure - self.reported).max(0.0) as u64);
        self.reported = exposure;
        self.done = alive == 0
            || escapes >= budget.target_escapes
            || exposure >= budget.max_exposure
            || checkpoint >= budget.horizon;
    }

    fn finish(self, tracks: &[Track]) -> EscapeRecord {
        let (escapes, exposure) = self.escapes_exposure(tracks, self.end);
        let (rate, rate_ci95) = escape_rate(escapes, exposure);
        let mut destinations: Vec<(usize, usize)> = Vec::new();
        for t in tracks.iter().filter(|t| t.set == self.set) {
            if let Some((age, k)) = t.exit {
                // The same rule as the escape count (a capture found by following a shot orbit
                // may end a few periods past the last checkpoint).
                if age > self.start {
                    match destinations.iter_mut().find(|(d, _)| *d == k) {
                        Some((_, n)) => *n += 1,
                        None => destinations.push((k, 1)),
                    }
                }
            }
        }
        EscapeRecord {
            entered: self.entered.unwrap_or(0),
            start_periods: self.start,
            end_periods: self.end,
            survival: self.survival,
            escapes,
            exposure,
            rate,
            rate_ci95,
            destinations,
        }
    }
}
