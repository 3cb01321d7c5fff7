//! Adaptive embedded Runge-Kutta integration, DOP853, with dense output and event location.
//!
//! DOP853 is the explicit 8th-order method of Dormand & Prince with the 5th- and 3rd-order
//! embedded error estimates and the 7th-order continuous extension of Hairer, Norsett & Wanner,
//! *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993, Sec. II.10. The
//! algorithm (error norm, step-size control, initial step) follows Hairer's Fortran code
//! `dop853.f` (<http://www.unige.ch/~hairer/software.html>), with its default parameters: safety
//! factor 0.9, step ratio bounded to [1/3, 6] (FAC1 = 0.333, FAC2 = 6), no Lund stabilisation
//! (BETA = 0), and no step growth right after a rejection. The coefficients are in `tableau`
//! (transcribed from SciPy's `dop853_coefficients.py`, which reproduces `dop853.f`).
//!
//! Events g(t, y) = 0 are checked on each accepted step, by the sign of g at its ends and by an
//! interior extremum of g (a sign change of dg/dt) that could hide two crossings, and located on
//! the dense output to a few ulps of t (`events`). The integration stops at the first event, so
//! a caller can switch the right-hand side there and restart: no step straddles a
//! discontinuity of the vector field. The dense output (3 extra calls of f) is only built for
//! steps that need the scan or when an observer asks for it.

mod dense;
mod events;
mod tableau;

pub use dense::DenseStep;
pub use events::{Crossing, EventFunction, FnEvent, LevelCrossing};

use crate::error::{GearError, Result};
use events::EndData;
use tableau::{A, BHH, C, E5};

/// Right-hand side y' = f(t, y) of an N-dimensional first-order system. Closures
/// `Fn(f64, &[f64; N]) -> [f64; N]` implement it.
pub trait OdeSystem<const N: usize> {
    /// The derivative f(t, y).
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N];
}

impl<const N: usize, F: Fn(f64, &[f64; N]) -> [f64; N]> OdeSystem<N> for F {
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N] {
        self(t, y)
    }
}

/// Tolerances and limits of [`Dop853`]. A step is accepted when Hairer's error norm, with the
/// per-component scale atol_i + rtol max(|y_i|, |y_new_i|), is at most 1.
#[derive(Clone, Debug, PartialEq)]
pub struct Dop853Options<const N: usize> {
    /// Relative tolerance, in [1e-15, 1).
    pub rtol: f64,
    /// Absolute tolerance per component, > 0. `f64::INFINITY` excludes a component from error
    /// control (e.g. variational equations that should follow the steps of the state).
    pub atol: [f64; N],
    /// Largest step size allowed.
    pub h_max: f64,
    /// Largest number of attempted steps in one call of [`Dop853::integrate`] (Hairer's NMAX).
    pub max_steps: u64,
}

impl<const N: usize> Dop853Options<N> {
    /// Options with the same absolute tolerance for every component, no step-size bound and
    /// Hairer's default NMAX = 100000.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Dop853Options {
            rtol,
            atol: [atol; N],
            h_max: f64::INFINITY,
            max_steps: 100_000,
        }
    }

    fn validated(self) -> Result<Self> {
        if !(self.rtol.is_finite() && (1e-15..1.0).contains(&self.rtol)) {
            return Err(GearError::param(
                "rtol",
                self.rtol,
                "relative tolerance must be in [1e-15, 1)",
            ));
        }
        if let Some(&a) = self.atol.iter().find(|a| a.is_nan() || **a <= 0.0) {
            return Err(GearError::param(
                "atol",
                a,
                "absolute tolerance must be > 0 (infinite excludes a component)",
            ));
        }
        if self.atol.iter().all(|a| a.is_infinite()) {
            return Err(GearError::param(
                "atol",
                f64::INFINITY,
                "at least one component must be under error control",
            ));
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(GearError::param(
                "h_max",
                self.h_max,
                "maximum step size must be > 0",
            ));
        }
        if self.max_steps == 0 {
            return Err(GearError::param(
                "max_steps",
                0.0,
                "step limit must be >= 1",
            ));
        }
        Ok(self)
    }
}

/// Work counters of a [`Dop853`] integrator, cumulative over its calls.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dop853Stats {
    /// Calls of the right-hand side (12 per accepted step, 11 per rejected step, 3 more per
    /// dense output, 1 per automatic initial step).
    pub rhs_evaluations: u64,
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
}

/// Where an integration stopped: at `t_end`, or at an event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<const N: usize> {
    /// Time reached.
    pub t: f64,
    /// State at `t` (at an event, the dense-output value at the event time).
    pub y: [f64; N],
    /// Index into the event list of the event that stopped the integration, if one did.
    pub event: Option<usize>,
}

/// Values or rates of the events at one end of a step. A gear pair's period map restarts the
/// integration at every change of contact region, with one or two events; on the heap, these
/// four arrays were millions of allocations a `discover` run.
type EventValues = smallvec::SmallVec<[f64; 4]>;

/// Step-size controller constants of `dop853.f` (defaults of WORK(2), WORK(3), WORK(4)).
const SAFE: f64 = 0.9;
const FACC1: f64 = 1.0 / 0.333;
const FACC2: f64 = 1.0 / 6.0;
/// A remaining interval below this many units of t_end's magnitude is closed without a step.
const NEGLIGIBLE: f64 = 16.0 * f64::EPSILON;

/// The DOP853 integrator: options, the step size carried between calls, and work counters.
#[derive(Clone, Debug)]
pub struct Dop853<const N: usize> {
    opts: Dop853Options<N>,
    h_next: Option<f64>,
    stats: Dop853Stats,
}

impl<const N: usize> Dop853<N> {
    /// An integrator with validated options; the first call chooses its initial step.
    pub fn new(opts: Dop853Options<N>) -> Result<Self> {
        Ok(Dop853 {
            opts: opts.validated()?,
            h_next: None,
            stats: Dop853Stats::default(),
        })
    }

    /// Cumulative work counters.
    pub fn stats(&self) -> Dop853Stats {
        self.stats
    }

    /// Forget the step size carried from the previous call (the next call estimates one).
    pub fn reset_step_size(&mut self) {
        self.h_next = None;
    }

    /// Integrate y' = f(t, y) from (t0, y0) to `t_end` >= t0, stopping early at the first event
    /// (a sign change of one of `events` in its direction, located on the dense output). The
    /// `observer` receives the dense output of every accepted step, truncated at an event.
    /// The step size proposed at the end is kept for the next call (a restart after an event).
    ///
    /// Errors (`GearError::Numerical`): more than `max_steps` steps, a step size that underflows
    /// against t, or a non-finite solution.
    pub fn integrate<S: OdeSystem<N> + ?Sized>(
        &mut self,
        sys: &S,
        t0: f64,
        y0: [f64; N],
        t_end: f64,
        events: &[&dyn EventFunction<N>],
        mut observer: Option<&mut dyn FnMut(&DenseStep<N>)>,
    ) -> Result<Outcome<N>> {
        check_start(t0, &y0, t_end)?;
        if t_end == t0 {
            return Ok(Outcome {
                t: t0,
                y: y0,
                event: None,
            });
        }
        let mut walk = Walk::start(sys, events, t0, y0);
        self.stats.rhs_evaluations += 1;
        let mut h = match self.h_next {
            Some(h) => h,
            None => {
                self.stats.rhs_evaluations += 1;
                initial_step(sys, t0, &walk.y, &walk.f, &self.opts, t_end - t0)
            }
        }
        .min(self.opts.h_max);
        let mut reject = false;
        for _ in 0..self.opts.max_steps {
            let remaining = t_end - walk.t;
            if remaining <= NEGLIGIBLE * t_end.abs() {
                self.h_next = Some(h);
                return Ok(walk.close_remainder(t_end, &mut observer));
            }
            if !(h.is_finite() && 0.1 * h > walk.t.abs() * f64::EPSILON) {
                return Err(GearError::Numerical(format!(
                    "DOP853 step size {h:e} too small at t = {} (the solution may blow up or the right-hand side be discontinuous)",
                    walk.t
                )));
            }
            let last = walk.t + 1.01 * h >= t_end;
            if last {
                h = t_end - walk.t;
            }
            let y_new = stages(sys, walk.t, &walk.y, &walk.f, h, &mut walk.k);
            self.stats.rhs_evaluations += 11;
            let err = error_norm(&self.opts, &walk.y, &y_new, &walk.k, h);
            // err^EXPO1 with dop853.f's EXPO1 = 1/8, as three square roots: a libm `pow` per step was 4% of a discover run
            // that integrates a time-varying stiffness; the roots agree with it to an ulp.
            let fac11 = err.sqrt().sqrt().sqrt();
            if err <= 1.0 {
                let mut h_new = h / (fac11 / SAFE).clamp(FACC2, FACC1);
                if reject {
                    h_new = h_new.min(h);
                }
                let h_new = h_new.min(self.opts.h_max);
                let step = Step {
                    h,
                    y_new,
                    end: last.then_some(t_end),
                };
                if let Some(out) = self.accept(sys, events, &mut observer, &mut walk, step)? {
                    self.h_next = Some(h_new);
                    return Ok(out);
                }
                reject = false;
                h = h_new;
            } else {
                // Rejected (also when err is NaN: the comparison above fails).
                let fac = if fac11.is_finite() {
                    (fac11 / SAFE).min(FACC1)
                } else {
                    FACC1
                };
                h /= fac;
                reject = true;
                self.stats.rejected_steps += 1;
            }
        }
        Err(GearError::Numerical(format!(
            "DOP853 needed more than {} steps between t = {t0} and t = {t_end} (stopped at t = {})",
            self.opts.max_steps, walk.t
        )))
    }

    /// Take the accepted `step` from `walk`'s point: the events checked on it (on its dense
    /// output, built only when an event may change sign in it or the observer wants it), the
    /// observer called. Returns where the integration stops (an event inside the step, or its
    /// last step's end), or `None` with `walk` moved to the step's end.
    fn accept<S: OdeSystem<N> + ?Sized>(
        &mut self,
        sys: &S,
        events: &[&dyn EventFunction<N>],
        observer: &mut Option<&mut dyn FnMut(&DenseStep<N>)>,
        walk: &mut Walk<N>,
        step: Step<N>,
    ) -> Result<Option<Outcome<N>>> {
        let Step { h, y_new, end } = step;
        if y_new.iter().any(|v| !v.is_finite()) {
            return Err(GearError::Numerical(format!(
                "DOP853 solution became non-finite after t = {}",
                walk.t
            )));
        }
        let t_new = end.unwrap_or(walk.t + h);
        let f_new = sys.rhs(t_new, &y_new);
        self.stats.rhs_evaluations += 1;
        self.stats.accepted_steps += 1;
        walk.k[12] = f_new;
        for (i, e) in events.iter().enumerate() {
            walk.g1[i] = e.value(t_new, &y_new);
            walk.r1[i] = e.rate(t_new, &y_new, &f_new);
        }
        let ends = EndData {
            g0: &walk.g0,
            g1: &walk.g1,
            r0: &walk.r0,
            r1: &walk.r1,
        };
        let scan = !events.is_empty() && events::needs_scan(events, &ends);
        if scan || observer.is_some() {
            extra_stages(sys, walk.t, &walk.y, h, &mut walk.k);
            self.stats.rhs_evaluations += 3;
            let mut dense = DenseStep::new(walk.t, h, &walk.y, &y_new, &walk.k);
            if let Some(t_end) = end {
                dense.truncate(t_end);
            }
            let hit = if scan {
                events::locate(events, &dense, &ends)
            } else {
                None
            };
            if let Some(hit) = &hit {
                dense.truncate(hit.t);
            }
            if let Some(obs) = observer.as_mut() {
                obs(&dense);
            }
            if let Some(hit) = hit {
                return Ok(Some(Outcome {
                    t: hit.t,
                    y: dense.eval(hit.t),
                    event: Some(hit.index),
                }));
            }
        }
        walk.advance(t_new, y_new, f_new);
        Ok(end.map(|t| Outcome {
            t,
            y: walk.y,
            event: None,
        }))
    }
}

/// An interval and initial state `integrate` can start from: finite, forward, finite state.
fn check_start<const N: usize>(t0: f64, y0: &[f64; N], t_end: f64) -> Result<()> {
    if !(t0.is_finite() && t_end.is_finite() && t_end >= t0) {
        return Err(GearError::Numerical(format!(
            "integration interval [{t0}, {t_end}] must be finite and forward"
        )));
    }
    if y0.iter().any(|v| !v.is_finite()) {
        return Err(GearError::Numerical(format!(
            "non-finite initial state {y0:?} at t = {t0}"
        )));
    }
    Ok(())
}

/// One accepted step: its size, the solution at its end, and `Some(t_end)` when it is the
/// call's last step (its end then is t_end exactly).
struct Step<const N: usize> {
    h: f64,
    y_new: [f64; N],
    end: Option<f64>,
}

/// What one `integrate` call carries from step to step: the point reached, the right-hand side
/// there, the events' values and rates at the two ends of a step, and the stages.
struct Walk<const N: usize> {
    t: f64,
    y: [f64; N],
    f: [f64; N],
    g0: EventValues,
    r0: EventValues,
    g1: EventValues,
    r1: EventValues,
    k: [[f64; N]; 16],
}

impl<const N: usize> Walk<N> {
    /// At (t0, y0), with f and the events evaluated there (one call of f).
    fn start<S: OdeSystem<N> + ?Sized>(
        sys: &S,
        events: &[&dyn EventFunction<N>],
        t0: f64,
        y0: [f64; N],
    ) -> Self {
        let f = sys.rhs(t0, &y0);
        let ne = events.len();
        Walk {
            t: t0,
            y: y0,
            f,
            g0: events.iter().map(|e| e.value(t0, &y0)).collect(),
            r0: events.iter().map(|e| e.rate(t0, &y0, &f)).collect(),
            g1: smallvec::smallvec![0.0; ne],
            r1: smallvec::smallvec![0.0; ne],
            k: [[0.0; N]; 16],
        }
    }

    /// Move to the end of an accepted step; its end's event values become the next start's.
    fn advance(&mut self, t: f64, y: [f64; N], f: [f64; N]) {
        self.t = t;
        self.y = y;
        self.f = f;
        std::mem::swap(&mut self.g0, &mut self.g1);
        std::mem::swap(&mut self.r0, &mut self.r1);
    }

    /// A remainder of a few ulps (an event just before t_end): no step can resolve it, and one
    /// Euler step closes it with an error of order remaining^2.
    fn close_remainder(
        &self,
        t_end: f64,
        observer: &mut Option<&mut dyn FnMut(&DenseStep<N>)>,
    ) -> Outcome<N> {
        let remaining = t_end - self.t;
        let y_end: [f64; N] = std::array::from_fn(|i| self.y[i] + remaining * self.f[i]);
        if let Some(obs) = observer.as_mut() {
            obs(&DenseStep::new(
                self.t,
                remaining,
                &self.y,
                &y_end,
                &[self.f; 16],
            ));
        }
        Outcome {
            t: t_end,
            y: y_end,
            event: None,
        }
    }
}

/// The 12 main stages of one step of size h; fills k[0..12] (k[0] = f) and returns y_new.
#[inline]
fn stages<const N: usize, S: OdeSystem<N> + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    f: &[f64; N],
    h: f64,
    k: &mut [[f64; N]; 16],
) -> [f64; N] {
    k[0] = *f;
    stage::<N, 1, S>(sys, t, y, h, k);
    stage::<N, 2, S>(sys, t, y, h, k);
    stage::<N, 3, S>(sys, t, y, h, k);
    stage::<N, 4, S>(sys, t, y, h, k);
    stage::<N, 5, S>(sys, t, y, h, k);
    stage::<N, 6, S>(sys, t, y, h, k);
    stage::<N, 7, S>(sys, t, y, h, k);
    stage::<N, 8, S>(sys, t, y, h, k);
    stage::<N, 9, S>(sys, t, y, h, k);
    stage::<N, 10, S>(sys, t, y, h, k);
    stage::<N, 11, S>(sys, t, y, h, k);
    combine::<N, 12>(y, h, k)
}

/// The 3 extra stages of the dense output (k[13..16]); needs k[12] = f(t + h, y_new).
#[inline]
fn extra_stages<const N: usize, S: OdeSystem<N> + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    h: f64,
    k: &mut [[f64; N]; 16],
) {
    stage::<N, 13, S>(sys, t, y, h, k);
    stage::<N, 14, S>(sys, t, y, h, k);
    stage::<N, 15, S>(sys, t, y, h, k);
}

/// Stage `R`: k[R] = f(t + c_R h, y + h sum_j a_Rj k_j).
#[inline(always)]
fn stage<const N: usize, const R: usize, S: OdeSystem<N> + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    h: f64,
    k: &mut [[f64; N]; 16],
) {
    let ys = combine::<N, R>(y, h, k);
    k[R] = sys.rhs(t + C[R] * h, &ys);
}

/// y + h sum_j a_Rj k_j over the stages j < R. The row is a compile-time constant, so the
/// compiler drops its zero coefficients (half of the tableau) instead of testing each one at
/// every step (13% of a DOP853 sweep's instructions, callgrind); the sum keeps its order, and
/// with it its bits.
#[inline(always)]
fn combine<const N: usize, const R: usize>(y: &[f64; N], h: f64, k: &[[f64; N]; 16]) -> [f64; N] {
    let mut acc = [0.0; N];
    for (aj, kj) in A[R].iter().zip(k).take(R) {
        if *aj != 0.0 {
            for (s, v) in acc.iter_mut().zip(kj) {
                *s += aj * v;
            }
        }
    }
    let mut out = *y;
    for (o, s) in out.iter_mut().zip(acc) {
        *o += h * s;
    }
    out
}

/// Hairer's DOP853 error norm: err = |h| err5^2 / sqrt(n (err5^2 + 0.01 err3^2)), with the
/// 5th-order (E5) and 3rd-order (b - BHH) estimates scaled per component. Components with an
/// infinite atol are left out, and n counts only the controlled ones.
fn error_norm<const N: usize>(
    opts: &Dop853Options<N>,
    y: &[f64; N],
    y_new: &[f64; N],
    k: &[[f64; N]; 16],
    h: f64,
) -> f64 {
    let (mut err5, mut err3, mut n) = (0.0, 0.0, 0usize);
    for i in 0..N {
        if opts.atol[i].is_infinite() {
            continue;
        }
        let sk = opts.atol[i] + opts.rtol * y[i].abs().max(y_new[i].abs());
        let mut e5 = 0.0;
        let mut bsum = 0.0;
        for j in 0..12 {
            e5 += E5[j] * k[j][i];
            bsum += A[12][j] * k[j][i];
        }
        let mut e3 = bsum;
        for &(j, c) in &BHH {
            e3 -= c * k[j][i];
        }
        err5 += (e5 / sk) * (e5 / sk);
        err3 += (e3 / sk) * (e3 / sk);
        n += 1;
    }
    let mut deno = err5 + 0.01 * err3;
    if deno <= 0.0 {
        deno = 1.0;
    }
    h.abs() * err5 * (1.0 / (n as f64 * deno)).sqrt()
}

/// Initial step size of `dop853.f` (function HINIT, iord = 8): a first guess from |y| / |f|, one
/// explicit Euler step to estimate the second derivative, and h = (0.01 / max(|f'|, |f|))^(1/8).
fn initial_step<const N: usize, S: OdeSystem<N> + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    f: &[f64; N],
    opts: &Dop853Options<N>,
    span: f64,
) -> f64 {
    let h_max = opts.h_max.min(span);
    let sk: [f64; N] = std::array::from_fn(|i| opts.atol[i] + opts.rtol * y[i].abs());
    let wnorm = |v: &[f64; N]| -> f64 {
        v.iter()
            .zip(&sk)
            .map(|(a, s)| (a / s) * (a / s))
            .sum::<f64>()
            .sqrt()
    };
    let dnf = wnorm(f).powi(2);
    let dny = wnorm(y).powi(2);
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    let y1: [f64; N] = std::array::from_fn(|i| y[i] + h * f[i]);
    let f1 = sys.rhs(t + h, &y1);
    let df: [f64; N] = std::array::from_fn(|i| f1[i] - f[i]);
    let der2 = wnorm(&df) / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        1e-6f64.max(h * 1e-3)
    } else {
        (0.01 / der12).powf(1.0 / 8.0)
    };
    let h = (100.0 * h).min(h1).min(h_max);
    if h.is_finite() && h > 0.0 {
        h
    } else {
        1e-6f64.min(h_max)
    }
}

#[cfg(test)]
mod tests;
