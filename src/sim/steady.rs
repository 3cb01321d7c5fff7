//! Steady-state response from one initial condition (Sec. 3): transient skipping, stroboscopic
//! Poincare section, period detection up to 32 forcing periods, refinement of periodic orbits,
//! chaos flagged by the largest Lyapunov exponent, and the response measures of design.md 1.

use super::escape::EscapeBudget;
use super::extrema::extremes_over;
use super::flow::{PeriodFlow, State};
use super::lyapunov::largest_lyapunov;
use super::period::{detect_period, distance, refine_orbit, scale, PeriodicOrbit, MAX_PERIOD};
use super::shooting::{follow, shoot};
use crate::error::{GearError, Result};
use crate::model::Impact;
use serde::Serialize;

/// Options of a steady-state computation.
#[derive(Clone, Debug)]
pub struct SteadyOptions {
    /// Forcing periods skipped as transient; `None` chooses from zeta ([`default_transient`]).
    /// The transient ends earlier when the section points provably repeat (see `settle`).
    pub transient: Option<usize>,
    /// Forcing periods analysed after the transient (default 64).
    pub keep: usize,
    /// End the transient as soon as the section points repeat and Newton refines the orbit.
    pub settle: bool,
    /// Compute the largest Lyapunov exponent also for periodic motion (from its multipliers).
    pub lyapunov: bool,
    /// Forcing periods averaged for the Lyapunov exponent of non-periodic motion.
    pub lyapunov_periods: usize,
    /// Classify settled non-periodic motion (chaotic, converging or aperiodic) by its largest
    /// Lyapunov exponent, at `lyapunov_periods` periods a point. Without it such motion is
    /// `Aperiodic`, with no exponent and no cloud: a fit that only reads the pp of the
    /// analysed window and whether the motion is periodic skips the cost (most of a
    /// non-periodic point's).
    pub classify_aperiodic: bool,
    /// How long attractor searches follow non-periodic sets to measure their escape (used by
    /// [`super::find_attractors`], not by a single steady state).
    pub escape: EscapeBudget,
}

impl Default for SteadyOptions {
    fn default() -> Self {
        SteadyOptions {
            transient: None,
            keep: 64,
            settle: true,
            lyapunov: false,
            lyapunov_periods: 2000,
            classify_aperiodic: true,
            escape: EscapeBudget::default(),
        }
    }
}

/// Largest transient accepted, in forcing periods (`--periods`): bounds the time of one steady
/// state (about 5 us a period with the exact solver).
pub const MAX_TRANSIENT: usize = 1_000_000;
/// Largest number of analysed periods (`--keep`): bounds memory (16 bytes a kept period, more
/// with the figures of `simulate --out`).
pub const MAX_KEEP: usize = 100_000;
/// Decay exponent zeta x (transient time) below which a motion without a periodic orbit is not
/// settled: the free decay e^{-zeta t} of the initial condition is then above e^-20 = 2e-9.
pub const SETTLED_DECAY: f64 = 20.0;

impl SteadyOptions {
    /// Check the budgets against [`MAX_TRANSIENT`] and [`MAX_KEEP`].
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = self.transient {
            if t > MAX_TRANSIENT {
                return Err(GearError::param(
                    "periods",
                    t as f64,
                    "at most 1000000 transient periods",
                ));
            }
        }
        if self.keep == 0 || self.keep > MAX_KEEP {
            return Err(GearError::param(
                "keep",
                self.keep as f64,
                "the analysed periods must be between 1 and 100000",
            ));
        }
        if self.lyapunov_periods > MAX_TRANSIENT {
            return Err(GearError::param(
                "lyapunov_periods",
                self.lyapunov_periods as f64,
                "at most 1000000 periods",
            ));
        }
        Ok(())
    }
}

/// Default transient length: enough forcing periods for a decay e^{-zeta t} of 1e-13 (the slowest
/// free decay of eq. 3a in contact), at least 100 and at most 20000 periods.
pub fn default_transient(zeta: f64, period: f64) -> usize {
    let n = (30.0 / (zeta * period)).ceil();
    n.clamp(100.0, 20000.0) as usize
}

/// Kind of steady motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Motion {
    /// A period-p orbit (p <= 32).
    Periodic,
    /// No period up to 32 and a positive largest Lyapunov exponent.
    Chaotic,
    /// No period up to 32 and an exponent indistinguishable from zero (quasi-periodic motion).
    Aperiodic,
    /// No periodic orbit identified within the budget, but a negative largest Lyapunov exponent:
    /// the motion is still contracting onto a stable orbit (of period above 32, or approached
    /// too slowly); its exponent is that orbit's Floquet rate.
    Converging,
    /// No periodic orbit found and the transient budget too short for the free decay to have
    /// died out: the motion is still converging, so it is neither classified as aperiodic nor
    /// as chaotic ([`SteadyState::settled`] is false).
    Unsettled,
}

impl Motion {
    /// Name used in text, JSON and CSV outputs ("periodic", "chaotic", "aperiodic",
    /// "converging", "unsettled"; the serde name).
    pub fn name(self) -> &'static str {
        match self {
            Motion::Periodic => "periodic",
            Motion::Chaotic => "chaotic",
            Motion::Aperiodic => "aperiodic",
            Motion::Converging => "converging",
            Motion::Unsettled => "unsettled",
        }
    }
}

/// The steady state reached from one initial condition.
#[derive(Clone, Debug, Serialize)]
pub struct SteadyState {
    /// Subharmonic order p of a period-p orbit; `None` when no period up to 32 is found.
    pub period: Option<u32>,
    /// Periodic, chaotic or aperiodic.
    pub motion: Motion,
    /// Impact regime of Fig. 9 (case I, II, III).
    pub impact: Impact,
    /// Half range of q, q_a = (max q - min q) / 2.
    pub qa: f64,
    /// Mid range of q, q_m = (max q + min q) / 2.
    pub qm: f64,
    /// Smallest q over the analysed periods.
    pub q_min: f64,
    /// Largest q over the analysed periods.
    pub q_max: f64,
    /// Peak-to-peak dynamic transmission error pp(x), x = q + e/b (design.md 1).
    pub dte_pp: f64,
    /// Largest dynamic load factor D_L = (2 zeta q' + k f(q)) / F_m; `None` when F_m = 0.
    pub dl_max: Option<f64>,
    /// Largest Lyapunov exponent per unit time, when computed.
    pub lyapunov: Option<f64>,
    /// Floquet multipliers of a periodic orbit as (re, im).
    pub floquet: Option<[(f64, f64); 2]>,
    /// Floquet rate of a periodic orbit, ln(largest |multiplier|) / (p T): the exponent at which
    /// nearby trajectories approach it, per unit dimensionless time. A negative "Lyapunov
    /// exponent" measured on a slow approach to the orbit is this rate.
    pub floquet_rate: Option<f64>,
    /// Section points of the steady state: the p points of a periodic orbit (refined), or the
    /// analysed section points of non-periodic motion.
    pub poincare: Vec<State>,
    /// Transient periods actually integrated before the analysis.
    pub transient_periods: usize,
    /// False when no periodic orbit was found and the transient was too short for the slowest
    /// free decay to die out (zeta x transient time < [`SETTLED_DECAY`]): the motion is then
    /// reported as [`Motion::Unsettled`], not as aperiodic or chaotic.
    pub settled: bool,
    /// Section points of the Lyapunov run of non-periodic motion (the strange attractor's cloud),
    /// used to tell coexisting chaotic attractors apart.
    #[serde(skip)]
    pub cloud: Vec<State>,
    /// Section point where the integration stopped (after the analysis and, for non-periodic
    /// motion, the Lyapunov run): where a longer observation continues.
    #[serde(skip)]
    pub end: State,
    /// Forcing periods integrated from the initial condition to [`SteadyState::end`].
    pub age: usize,
}

impl SteadyState {
    /// True when the orbit is periodic with all multipliers inside the unit circle.
    pub fn is_stable_periodic(&self) -> bool {
        self.floquet
            .is_some_and(|m| m.iter().all(|(r, i)| r.hypot(*i) < 1.0))
    }
}

/// Tolerance (relative to the state scale) for section points to count as repeating.
const REPEAT_TOL: f64 = 1e-7;
/// Tighter tolerance that ends the transient early and triggers Newton refinement.
const SETTLE_TOL: f64 = 1e-9;
/// Section points repeating to this relative tolerance mark a still-converging periodic orbit.
const NEAR_TOL: f64 = 1e-4;
/// The transient is extended at most to this multiple of its nominal length.
const EXTENSION: usize = 8;
/// Periods between two shooting attempts from near returns during a transient.
const SHOOT_EVERY: usize = 8;
/// Longest continuation of a contracting motion (negative Lyapunov exponent, no orbit yet).
const MAX_CONVERGING_EXTENSION: usize = 20_000;

/// Integrate from `x0` to the steady state and analyse it.
pub fn steady_state<F: PeriodFlow + ?Sized>(
    flow: &F,
    x0: State,
    opts: &SteadyOptions,
) -> Result<SteadyState> {
    match steady_state_watched::<F, ()>(flow, x0, opts, &mut |_| Ok(None))? {
        Watched::Steady(s) => Ok(*s),
        Watched::Stopped(_) => unreachable_stop(),
    }
}

fn unreachable_stop() -> Result<SteadyState> {
    Err(GearError::Numerical(
        "internal: a no-op watcher stopped the transient".into(),
    ))
}

/// Outcome of a watched steady-state computation.
pub(crate) enum Watched<T> {
    /// The watcher recognised the trajectory during the transient and stopped it.
    Stopped(T),
    /// The trajectory was integrated to its steady state and analysed.
    Steady(Box<SteadyState>),
}

/// Where a transient ended: the state, the periods integrated, and the stable orbit it was
/// captured by, if any.
pub(crate) struct TransientEnd {
    pub(crate) x: State,
    pub(crate) used: usize,
    pub(crate) orbit: Option<PeriodicOrbit>,
}

/// [`steady_state`] with a watcher called on each transient section point; returning `Some`
/// stops the integration early (used to recognise already known attractors).
pub(crate) fn steady_state_watched<F: PeriodFlow + ?Sized, T>(
    flow: &F,
    x0: State,
    opts: &SteadyOptions,
    watch: &mut dyn FnMut(State) -> Result<Option<T>>,
) -> Result<Watched<T>> {
    check_state(x0)?;
    opts.validate()?;
    let model = flow.model();
    let transient = opts
        .transient
        .unwrap_or_else(|| default_transient(model.zeta, flow.period()));
    let end = match run_transient(flow, x0, transient, opts.settle, watch)? {
        Ok(end) => end,
        Err((t, _)) => return Ok(Watched::Stopped(t)),
    };
    let s = analyse(flow, end.x, end.orbit, end.used, opts)?;
    if s.motion != Motion::Converging {
        return Ok(Watched::Steady(Box::new(s)));
    }
    // A negative largest Lyapunov exponent without an orbit: the motion contracts onto a stable
    // orbit more slowly than the transient allowed. Continue for the time the exponent needs
    // to shrink a unit deviation to 1e-9 (twice that), bounded, and analyse again.
    let rate = s.lyapunov.unwrap_or(0.0).abs().max(f64::MIN_POSITIVE);
    let needed = 2.0 * (1e9f64).ln() / (rate * flow.period()) + 100.0;
    let more = (needed.min(MAX_CONVERGING_EXTENSION as f64) as usize)
        .min(MAX_TRANSIENT.saturating_sub(s.age));
    match run_transient(flow, s.end, more, opts.settle, watch)? {
        Err((t, _)) => Ok(Watched::Stopped(t)),
        Ok(e) if e.orbit.is_some() => Ok(Watched::Steady(Box::new(analyse(
            flow,
            e.x,
            e.orbit,
            s.age + e.used,
            opts,
        )?))),
        Ok(_) => Ok(Watched::Steady(Box::new(s))),
    }
}

/// Integrate the transient from `x0` for `nominal` periods (extended while the points nearly
/// repeat), ending early when the trajectory settles on a stable periodic orbit: its points
/// repeat to [`SETTLE_TOL`] and Newton refines the orbit, or a near return shot by Newton gives a
/// stable orbit that captures the trajectory (see [`shoot`], [`follow`]). `Err((t, used))` when
/// the watcher stopped it.
pub(crate) fn run_transient<F: PeriodFlow + ?Sized, T>(
    flow: &F,
    x0: State,
    nominal: usize,
    settle: bool,
    watch: &mut dyn FnMut(State) -> Result<Option<T>>,
) -> Result<std::result::Result<TransientEnd, (T, usize)>> {
    let history_len = 3 * MAX_PERIOD as usize;
    let mut history: Vec<State> = Vec::with_capacity(history_len + 1);
    let mut x = x0;
    let mut used = 0;
    let mut limit = nominal;
    let (mut shoot_every, mut next_shot) = (SHOOT_EVERY, SHOOT_EVERY);
    while used < limit {
        x = flow.step(x, None)?;
        used += 1;
        if !(x[0].is_finite() && x[1].is_finite()) {
            return Err(GearError::Numerical("the response diverged".into()));
        }
        if let Some(t) = watch(x)? {
            return Ok(Err((t, used)));
        }
        if !settle {
            continue;
        }
        history.push(x);
        if history.len() > history_len {
            history.remove(0);
        }
        if let Some(p) = settled_period(&history, SETTLE_TOL) {
            if let Some(o) = refine_orbit(flow, x, p)? {
                if o.spectral_radius() < 1.0 {
                    x = o.points[0];
                    return Ok(Ok(TransientEnd {
                        x,
                        used,
                        orbit: Some(o),
                    }));
                }
            }
        } else if used >= next_shot {
            next_shot = used + shoot_every;
            // A slowly contracting orbit (a multiplier near +-1) is found by shooting from a near
            // return instead of waiting for the transient to die out.
            if let Some(o) = shoot(flow, &history)? {
                if let Some((_, n)) = follow(flow, x, &o, MAX_TRANSIENT.saturating_sub(used))? {
                    return Ok(Ok(TransientEnd {
                        x: o.points[0],
                        used: used + n,
                        orbit: Some(o),
                    }));
                }
                // The shot orbit did not capture the trajectory. With a multiplier near 1 a
                // follow may run up to MAX_TRANSIENT periods before it gives up, so shots are
                // spaced ever wider after each miss: at most ~log2(nominal / 8) misses per
                // transient, not nominal / 8 (which took a discover fit 40 minutes on one
                // steady state).
                shoot_every *= 2;
                next_shot = used + shoot_every;
            }
        }
        // A motion that is periodic to 1e-4 but not yet to 1e-9 and that Newton could not
        // refine (a grazing orbit) gets more time rather than being reported as aperiodic.
        if used == limit
            && limit < EXTENSION * nominal
            && settled_period(&history, NEAR_TOL).is_some()
        {
            limit += nominal;
        }
    }
    Ok(Ok(TransientEnd {
        x,
        used,
        orbit: None,
    }))
}

/// Period of the last section points at the settling tolerance, if they repeat.
fn settled_period(history: &[State], rel_tol: f64) -> Option<u32> {
    let last = *history.last()?;
    let tol = rel_tol * scale(&[last]);
    // Cheap pre-check on the newest point before the full repetition test.
    let n = history.len();
    (1..=MAX_PERIOD).find(|&p| {
        let p = p as usize;
        n >= 3 * p
            && distance(last, history[n - 1 - p]) <= tol
            && detect_period(&history[n - 3 * p..], p as u32, tol) == Some(p as u32)
    })
}

/// Analyse the steady state that starts at section point `x`, `age` periods after the initial
/// condition.
fn analyse<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    orbit: Option<PeriodicOrbit>,
    age: usize,
    opts: &SteadyOptions,
) -> Result<SteadyState> {
    // A stable orbit the transient refined is described by its own p periods: kept periods
    // would only repeat its points (and were most of a continuation step's cost).
    if orbit.is_some() {
        return describe(flow, x, orbit, None, Vec::new(), age, opts);
    }
    let keep = opts.keep.max(1);
    // Section points of the kept periods (cheap: no observer).
    let mut points = Vec::with_capacity(keep);
    let mut y = x;
    for _ in 0..keep {
        points.push(y);
        y = flow.step(y, None)?;
    }
    let mut orbit = orbit;
    if orbit.is_none() {
        let sc = scale(&points);
        let detected = detect_period(
            &points,
            MAX_PERIOD.min(keep as u32 / 2).max(1),
            REPEAT_TOL * sc,
        );
        if let Some(p) = detected {
            orbit = refine_orbit(flow, x, p)?;
            if orbit.is_none() {
                // Repeating points Newton cannot refine (a grazing orbit): periodic, unrefined.
                return describe(flow, x, None, Some(p), points, age, opts);
            }
        }
    }
    if orbit.is_none() && opts.settle {
        // A slow approach to a stable orbit, or a long chaotic transient ending inside the kept
        // window: Newton from a near return of the last points, confirmed by capture.
        if let Some(o) = shoot(flow, &points)? {
            if let Some((_, n)) = follow(flow, y, &o, MAX_TRANSIENT.saturating_sub(age))? {
                let start = o.points[0];
                return describe(flow, start, Some(o), None, points, age + keep + n, opts);
            }
        }
    }
    describe(flow, x, orbit, None, points, age, opts)
}

/// The steady state from its kept section points `points` (starting at `x`) and the periodic
/// orbit found, if any (or the period of points Newton could not refine, `unrefined`).
fn describe<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    orbit: Option<PeriodicOrbit>,
    unrefined: Option<u32>,
    points: Vec<State>,
    age: usize,
    opts: &SteadyOptions,
) -> Result<SteadyState> {
    let model = flow.model();
    let keep = points.len();
    let period = orbit.as_ref().map(|o| o.period).or(unrefined);
    // Without a periodic orbit, the motion counts as settled only if the transient was long
    // enough for the free decay of the initial condition to die out; otherwise the kept points
    // are still a transient and say nothing about chaos or quasi-periodicity.
    let settled = period.is_some() || model.zeta * age as f64 * flow.period() >= SETTLED_DECAY;
    // A periodic orbit is fully described by p periods; otherwise analyse all kept periods.
    let (start, analysed) = match (&orbit, period) {
        (Some(o), _) => (o.points[0], o.period as usize),
        (None, Some(p)) => (x, p as usize),
        (None, None) => (x, keep),
    };
    let (ext, after) = extremes_over(flow, start, analysed)?;
    let floquet_rate = orbit
        .as_ref()
        .map(|o| o.spectral_radius().ln() / (o.period as f64 * flow.period()));
    let mut cloud = Vec::new();
    let lyapunov_periods = 20 + opts.lyapunov_periods;
    let (lyapunov, end, end_age) = match period {
        Some(_) => (
            floquet_rate.filter(|_| opts.lyapunov),
            after,
            age + analysed,
        ),
        None if settled && opts.classify_aperiodic => {
            let (l, end) = largest_lyapunov(flow, x, 20, opts.lyapunov_periods, Some(&mut cloud))?;
            (Some(l), end, age + lyapunov_periods)
        }
        None if opts.lyapunov => {
            let (l, end) = largest_lyapunov(flow, x, 20, opts.lyapunov_periods, None)?;
            (Some(l), end, age + lyapunov_periods)
        }
        None => (None, after, age + analysed),
    };
    let threshold = 1e-3 * model.zeta.max(1e-3);
    let motion = match (period, lyapunov) {
        (Some(_), _) => Motion::Periodic,
        (None, _) if !settled => Motion::Unsettled,
        (None, Some(l)) if l > threshold => Motion::Chaotic,
        (None, Some(l)) if l < -threshold => Motion::Converging,
        _ => Motion::Aperiodic,
    };
    let (q_min, q_max) = ext.q;
    let dl_max = (model.mean_force > 0.0).then(|| ext.mesh_force_max / model.mean_force);
    Ok(SteadyState {
        period,
        motion,
        impact: Impact::from_range(q_min),
        qa: 0.5 * (q_max - q_min),
        qm: 0.5 * (q_max + q_min),
        q_min,
        q_max,
        dte_pp: ext.dte.1 - ext.dte.0,
        dl_max,
        lyapunov,
        floquet: orbit.as_ref().map(|o| o.multipliers),
        floquet_rate,
        poincare: match &orbit {
            Some(o) => o.points.clone(),
            None => points,
        },
        transient_periods: age,
        settled,
        cloud,
        end,
        age: end_age,
    })
}

fn check_state(x: State) -> Result<()> {
    if !x[0].is_finite() {
        return Err(GearError::param(
            "q0",
            x[0],
            "initial displacement must be finite",
        ));
    }
    if !x[1].is_finite() {
        return Err(GearError::param(
            "v0",
            x[1],
            "initial velocity must be finite",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::GearPair;
    use crate::sim::ExactFlow;

    /// A transient cut by its budget is reported as not settled, never as aperiodic or chaotic
    /// (issue 22: Omega 1e3 was "aperiodic, double impact" where the steady state is period-1);
    /// the chaos of Fig. 4 stays chaotic and settled.
    #[test]
    fn unsettled_motion_is_not_classified() {
        let m = GearPair::paper(0.1, 0.2, 0.02, 1e3).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let s = steady_state(&f, [0.0, 0.0], &SteadyOptions::default()).unwrap();
        assert!(!s.settled);
        assert_eq!((s.period, s.motion), (None, Motion::Unsettled));
        let m = GearPair::paper(0.1, 0.2, 0.02, 1.0).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let s = steady_state(&f, [0.0, 0.0], &SteadyOptions::default()).unwrap();
        assert!(s.settled);
        assert_eq!(s.motion, Motion::Chaotic);
        let short = SteadyOptions {
            transient: Some(10),
            ..SteadyOptions::default()
        };
        let s = steady_state(&f, [0.0, 0.0], &short).unwrap();
        assert_eq!((s.settled, s.motion), (false, Motion::Unsettled));
        let huge = SteadyOptions {
            keep: MAX_KEEP + 1,
            ..SteadyOptions::default()
        };
        assert!(steady_state(&f, [0.0, 0.0], &huge).is_err());
    }

    /// Without the classification the chaos of Fig. 4 is reported `Aperiodic` with no exponent
    /// and no cloud, from the same transient and analysed window (the same pp, bit for bit);
    /// the state it hands on is the end of that window, where the classified one hands on the
    /// state after the exponent's 2020 periods.
    #[test]
    fn unclassified_aperiodic_motion_keeps_its_window() {
        let m = GearPair::paper(0.1, 0.2, 0.02, 1.0).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let full = steady_state(&f, [0.0, 0.0], &SteadyOptions::default()).unwrap();
        let plain = SteadyOptions {
            classify_aperiodic: false,
            ..SteadyOptions::default()
        };
        let s = steady_state(&f, [0.0, 0.0], &plain).unwrap();
        assert_eq!(full.motion, Motion::Chaotic);
        assert_eq!(
            (s.motion, s.lyapunov, s.settled),
            (Motion::Aperiodic, None, true)
        );
        assert!(s.cloud.is_empty() && !full.cloud.is_empty());
        assert_eq!(
            (s.dte_pp, s.q_min, s.q_max),
            (full.dte_pp, full.q_min, full.q_max)
        );
        let d = SteadyOptions::default();
        assert_eq!(full.age - s.age, 20 + d.lyapunov_periods - d.keep);
        assert_ne!(s.end, full.end);
    }

    /// Linear regime: eq. 13 gives q_a, q_m = 1 + F_m exactly, and pp(x) follows from the
    /// transfer function of x = q + e/b.
    #[test]
    fn linear_steady_state_matches_closed_form() {
        let (fm, fah, zeta, om) = (5.0, 0.05, 0.05, 0.8);
        let m = GearPair::paper(fm, fah, zeta, om).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let s = steady_state(&f, [0.0, 0.0], &SteadyOptions::default()).unwrap();
        let d = ((1.0 - om * om).powi(2) + (2.0 * zeta * om).powi(2)).sqrt();
        let qa = fah * om * om / d;
        assert_eq!(s.period, Some(1));
        assert_eq!(s.impact, Impact::None);
        assert!((s.qa - qa).abs() < 1e-10, "{} vs {qa}", s.qa);
        assert!((s.qm - (1.0 + fm)).abs() < 1e-10);
        // x = q + e/b has the transfer (1 + 2 i zeta w) / (1 - w^2 + 2 i zeta w) times F_ah.
        let xa = fah * (1.0 + (2.0 * zeta * om).powi(2)).sqrt() / d;
        assert!(
            (s.dte_pp - 2.0 * xa).abs() < 1e-9,
            "{} vs {}",
            s.dte_pp,
            2.0 * xa
        );
        // Floquet multipliers of a linear oscillator: |mu| = e^{-zeta T}.
        let rho = (-zeta * m.period()).exp();
        for (re, im) in s.floquet.unwrap() {
            assert!((re.hypot(im) - rho).abs() < 1e-10);
        }
    }

    /// Fig. 8(a)'s point from rest: a slow approach to the period-8 orbit (multiplier -0.898,
    /// issue 23's independent shooting), once reported as period-16 or aperiodic with a
    /// "Lyapunov exponent" -0.0021. It is the period-8 orbit, and -0.0021 is its Floquet rate,
    /// ln(0.898) / (8 T).
    #[test]
    fn slow_approach_is_reported_as_the_orbit() {
        let m = GearPair::paper(0.1, 0.2, 0.05, 1.0).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let s = steady_state(&f, [0.0, 0.0], &SteadyOptions::default()).unwrap();
        assert_eq!((s.period, s.motion), (Some(8), Motion::Periodic));
        let mu = s.floquet.unwrap()[1].0;
        assert!((mu + 0.898).abs() < 1e-3, "{mu}");
        let rate = s.floquet_rate.unwrap();
        assert!((rate - 0.898f64.ln() / (8.0 * m.period())).abs() < 1e-5);
        assert!((rate + 0.0021).abs() < 1e-4);
    }
}
