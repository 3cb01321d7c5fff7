//! Time integration with `ode_solvers`' Dopri5 (Dormand-Prince 5(4)), restarted at every crossing
//! of the backlash boundaries q = +-1 (event location on a quintic Hermite interpolant of each
//! accepted step, then a re-integration from the step's start to the root), and the up-sweep
//! steady-state logic: transient until the Poincare section (forcing phase 0) repeats with some
//! period p <= 32, then the peak-to-peak of x = q + e/b over that orbit (or, when no period is
//! found within the transient budget, over a window of 64 forcing periods).

use crate::model::{region_of, Excitation};
use ode_solvers::dop_shared::{IntegrationError, OutputType, System};
use ode_solvers::{Dopri5, Vector2};
use std::collections::VecDeque;
use std::f64::consts::PI;

pub type State = Vector2<f64>;

/// Solver settings.
#[derive(Clone, Debug)]
pub struct SimConfig {
    pub rtol: f64,
    pub atol: f64,
    /// Transient budget in units of zeta * t (free decay e^{-zeta t}); the transient ends earlier
    /// as soon as the section repeats.
    pub transient_zeta_t: f64,
    /// Minimum transient periods at each speed (before the repetition test may end it).
    pub min_transient_periods: usize,
    /// Section repetition tolerance (max norm on q, q').
    pub section_tol: f64,
    /// Largest period looked for.
    pub max_period: usize,
    /// Window (forcing periods) over which pp is taken when no period is found.
    pub window_periods: usize,
    /// Extra forcing periods, beyond the end of the 64-period window, before a converged
    /// period-p orbit's state is carried to the next speed (0: the window's end). Only changes
    /// which point of a subharmonic orbit starts the next speed (and so, at multi-stable speeds,
    /// which branch the sweep follows).
    pub carry_shift: usize,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            rtol: 1e-10,
            atol: 1e-12,
            transient_zeta_t: 40.0,
            min_transient_periods: 4,
            section_tol: 1e-11,
            max_period: 32,
            window_periods: 64,
            carry_shift: 0,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Event {
    t: f64,
    boundary: f64,
    new_region: i8,
}

/// Extremes of x = q + e/b.
#[derive(Clone, Copy, Debug)]
pub struct Extremes {
    pub max: f64,
    pub min: f64,
}

impl Extremes {
    fn new() -> Self {
        Extremes {
            max: f64::NEG_INFINITY,
            min: f64::INFINITY,
        }
    }
    fn add(&mut self, x: f64) {
        if x > self.max {
            self.max = x;
        }
        if x < self.min {
            self.min = x;
        }
    }
}

/// Quintic Hermite interpolant of q on one step, from q, q', q'' at both ends.
struct Hermite {
    x0: f64,
    h: f64,
    c: [f64; 6], // p(s) = q0 H0 + h v0 H1 + h^2 a0 H2 + q1 H3 + h v1 H4 + h^2 a1 H5
}

impl Hermite {
    fn new(x0: f64, y0: &State, a0: f64, x1: f64, y1: &State, a1: f64) -> Self {
        let h = x1 - x0;
        Hermite {
            x0,
            h,
            c: [y0[0], h * y0[1], h * h * a0, y1[0], h * y1[1], h * h * a1],
        }
    }
    fn q(&self, s: f64) -> f64 {
        let s2 = s * s;
        let s3 = s2 * s;
        let s4 = s3 * s;
        let s5 = s4 * s;
        let h0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
        let h1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
        let h2 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5;
        let h3 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
        let h4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
        let h5 = 0.5 * s3 - s4 + 0.5 * s5;
        self.c[0] * h0
            + self.c[1] * h1
            + self.c[2] * h2
            + self.c[3] * h3
            + self.c[4] * h4
            + self.c[5] * h5
    }
    /// dq/dt (not d/ds).
    fn v(&self, s: f64) -> f64 {
        let s2 = s * s;
        let s3 = s2 * s;
        let s4 = s3 * s;
        let d0 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4;
        let d1 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4;
        let d2 = s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4;
        let d3 = 30.0 * s2 - 60.0 * s3 + 30.0 * s4;
        let d4 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4;
        let d5 = 1.5 * s2 - 4.0 * s3 + 2.5 * s4;
        (self.c[0] * d0
            + self.c[1] * d1
            + self.c[2] * d2
            + self.c[3] * d3
            + self.c[4] * d4
            + self.c[5] * d5)
            / self.h
    }
    fn t(&self, s: f64) -> f64 {
        self.x0 + s * self.h
    }
}

/// Root of g on [lo, hi] where g(lo) and g(hi) differ in sign (bisection to machine precision).
fn bisect<G: Fn(f64) -> f64>(g: G, mut lo: f64, mut hi: f64) -> f64 {
    let glo = g(lo);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let gm = g(mid);
        if (gm > 0.0) == (glo > 0.0) && gm != 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Mutable bookkeeping shared with the solver's step callback.
struct Tracker {
    prev_t: f64,
    prev_y: State,
    prev_a: f64,
    last_h: f64,
    event: Option<Event>,
    measure: bool,
    ext: Extremes,
    /// Largest mesh force 2 zeta q' + k f(q) over the measured periods.
    fmax: f64,
    steps: u64,
}

struct Segment<'a> {
    ex: &'a Excitation,
    region: i8,
    detect: bool,
    tr: &'a mut Tracker,
}

impl Segment<'_> {
    fn find_event(&self, her: &Hermite, y1: &State) -> Option<Event> {
        let outside = |q: f64| -> Option<f64> {
            match self.region {
                1 if q < 1.0 => Some(1.0),
                -1 if q > -1.0 => Some(-1.0),
                0 if q > 1.0 => Some(1.0),
                0 if q < -1.0 => Some(-1.0),
                _ => None,
            }
        };
        // End of the step outside the region, or a graze: an extremum of q inside the step that
        // leaves the region and comes back.
        let (boundary, s_hi) = if let Some(bd) = outside(y1[0]) {
            (bd, 1.0)
        } else if (self.tr.prev_y[1] > 0.0) != (y1[1] > 0.0) {
            let s_ext = bisect(|s| her.v(s), 0.0, 1.0);
            let q_ext = her.q(s_ext);
            match outside(q_ext) {
                Some(bd) if (q_ext - bd).abs() > 1e-13 => (bd, s_ext),
                _ => return None,
            }
        } else {
            return None;
        };
        // Lower end of the root search: a point inside the region. A step that starts on the
        // boundary (just after an event) and makes a brief excursion into the region before
        // leaving it again has its crossing after the excursion's extremum, not at s = 0.
        let inside = |q: f64| outside(q).is_none() && q != boundary;
        let mut s_lo = 0.0;
        if (self.tr.prev_y[1] > 0.0) != (y1[1] > 0.0) {
            let s_ext = bisect(|s| her.v(s), 0.0, 1.0);
            if s_ext < s_hi && inside(her.q(s_ext)) {
                s_lo = s_ext;
            }
        }
        let s = bisect(|s| her.q(s) - boundary, s_lo, s_hi);
        let new_region = match (self.region, boundary > 0.0) {
            (1, _) => 0,
            (-1, _) => 0,
            (_, true) => 1,
            (_, false) => -1,
        };
        Some(Event {
            t: her.t(s),
            boundary,
            new_region,
        })
    }
}

impl System<f64, State> for Segment<'_> {
    fn system(&self, t: f64, y: &State, dy: &mut State) {
        dy[0] = y[1];
        dy[1] = self.ex.accel(t, y[0], y[1], self.region);
    }

    fn solout(&mut self, t: f64, y: &State, dy: &State) -> bool {
        let h = t - self.tr.prev_t;
        if h <= 0.0 {
            return false;
        }
        self.tr.steps += 1;
        let her = Hermite::new(self.tr.prev_t, &self.tr.prev_y, self.tr.prev_a, t, y, dy[1]);
        if self.detect {
            if let Some(ev) = self.find_event(&her, y) {
                self.tr.event = Some(ev);
                return true;
            }
        }
        if self.tr.measure {
            let ex = self.ex;
            let xd0 = self.tr.prev_y[1] + ex.ste_dot(self.tr.prev_t);
            let xd1 = y[1] + ex.ste_dot(t);
            if (xd0 > 0.0) != (xd1 > 0.0) {
                let s = bisect(|s| her.v(s) + ex.ste_dot(her.t(s)), 0.0, 1.0);
                self.tr.ext.add(her.q(s) + ex.ste(her.t(s)));
            }
            self.tr.ext.add(y[0] + ex.ste(t));
            // Mesh force: its value at the step's end, and an interior maximum where its
            // derivative changes sign from + to - (root on the Hermite interpolant).
            let r = self.region;
            let g1 = ex.mesh_force(t, y[0], y[1], r);
            if g1 > self.tr.fmax {
                self.tr.fmax = g1;
            }
            let gd0 = ex.mesh_force_dot(self.tr.prev_t, self.tr.prev_y[0], self.tr.prev_y[1], r);
            let gd1 = ex.mesh_force_dot(t, y[0], y[1], r);
            if gd0 > 0.0 && gd1 <= 0.0 {
                let s = bisect(
                    |s| ex.mesh_force_dot(her.t(s), her.q(s), her.v(s), r),
                    0.0,
                    1.0,
                );
                let g = ex.mesh_force(her.t(s), her.q(s), her.v(s), r);
                if g > self.tr.fmax {
                    self.tr.fmax = g;
                }
            }
        }
        self.tr.prev_t = t;
        self.tr.prev_y = *y;
        self.tr.prev_a = dy[1];
        self.tr.last_h = h;
        false
    }
}

/// Integrator state carried along a sweep: (q, q') at forcing phase 0 and the region.
#[derive(Clone, Copy, Debug)]
pub struct Carried {
    pub y: State,
    pub region: i8,
    pub h: f64,
}

impl Carried {
    pub fn new(q: f64, v: f64) -> Self {
        Carried {
            y: State::new(q, v),
            region: region_of(q, v),
            h: 0.0,
        }
    }
}

fn run_dopri(
    seg: Segment<'_>,
    t0: f64,
    t1: f64,
    y0: State,
    h0: f64,
    cfg: &SimConfig,
) -> Result<(), IntegrationError> {
    let span = t1 - t0;
    let h = if h0 > 0.0 { h0.min(span) } else { 0.0 };
    let mut solver = Dopri5::from_param(
        seg,
        t0,
        t1,
        span,
        y0,
        cfg.rtol,
        cfg.atol,
        0.9,
        0.04,
        0.2,
        10.0,
        span,
        h,
        50_000_000,
        u32::MAX,
        OutputType::Sparse,
    );
    solver.integrate().map(|_| ())
}

/// One forcing period [0, T] from the carried state (phase 0 to phase 0), with event handling.
fn one_period(
    ex: &Excitation,
    c: &mut Carried,
    period: f64,
    cfg: &SimConfig,
    measure: bool,
    ext: &mut Extremes,
    fmax: &mut f64,
    steps: &mut u64,
) -> Result<(), IntegrationError> {
    let mut t = 0.0;
    let mut tr = Tracker {
        prev_t: 0.0,
        prev_y: c.y,
        prev_a: 0.0,
        last_h: c.h,
        event: None,
        measure,
        ext: *ext,
        fmax: *fmax,
        steps: 0,
    };
    if measure {
        tr.ext.add(c.y[0] + ex.ste(0.0));
        tr.fmax = tr.fmax.max(ex.mesh_force(0.0, c.y[0], c.y[1], c.region));
    }
    let mut guard = 0;
    loop {
        guard += 1;
        if guard > 100_000 {
            eprintln!(
                "indep-synth: event loop did not advance: t {t} period {period} y {:?} region {}",
                c.y, c.region
            );
            return Err(IntegrationError::StepSizeUnderflow { x: t });
        }
        if period - t < 1e-13 {
            break;
        }
        let y0 = c.y;
        tr.prev_t = t;
        tr.prev_y = y0;
        tr.prev_a = ex.accel(t, y0[0], y0[1], c.region);
        tr.event = None;
        let h0 = tr.last_h;
        if let Err(e) = run_dopri(
            Segment {
                ex,
                region: c.region,
                detect: true,
                tr: &mut tr,
            },
            t,
            period,
            y0,
            h0,
            cfg,
        ) {
            eprintln!("indep-synth: Dopri5 failed: t {t} period {period} y {:?} region {} h0 {h0} guard {guard}: {e}", c.y, c.region);
            return Err(e);
        }
        match tr.event.take() {
            None => {
                c.y = tr.prev_y;
                break;
            }
            Some(ev) => {
                // Re-integrate from the start of the step that crossed to the root, in the same
                // region (its branch of f is smooth up to the boundary), without events.
                let (xs, ys) = (tr.prev_t, tr.prev_y);
                let mut y_root = ys;
                if ev.t - xs > 1e-14 {
                    let h_keep = tr.last_h;
                    if let Err(e) = run_dopri(
                        Segment {
                            ex,
                            region: c.region,
                            detect: false,
                            tr: &mut tr,
                        },
                        xs,
                        ev.t,
                        ys,
                        h_keep,
                        cfg,
                    ) {
                        eprintln!("indep-synth: Dopri5 failed re-integrating to an event: xs {xs} ev {:?} ys {:?} region {} h {h_keep}: {e}", ev, ys, c.region);
                        return Err(e);
                    }
                    y_root = tr.prev_y;
                    tr.last_h = h_keep;
                }
                y_root[0] = ev.boundary;
                c.y = y_root;
                c.region = ev.new_region;
                t = ev.t;
                if measure {
                    tr.ext.add(c.y[0] + ex.ste(t));
                    tr.fmax = tr.fmax.max(ex.mesh_force(t, c.y[0], c.y[1], c.region));
                }
            }
        }
    }
    c.h = tr.last_h;
    *ext = tr.ext;
    *fmax = tr.fmax;
    *steps += tr.steps;
    Ok(())
}

/// Result at one speed.
#[derive(Clone, Debug)]
pub struct SteadyPoint {
    /// Peak-to-peak of x = q + e/b (dimensionless; times b gives um).
    pub x_pp: f64,
    /// Largest mesh force 2 zeta q' + k f(q) over the same periods (units of b k_h; D_L =
    /// force_max / F_m).
    pub force_max: f64,
    /// Least period found (in forcing periods), or None when the section did not repeat within
    /// the transient budget (chaotic, or still converging).
    pub period: Option<usize>,
    /// Forcing periods integrated as transient.
    pub transient_periods: usize,
    /// Last section-repetition distance at the found period (or at lag 1 when none).
    pub section_distance: f64,
    /// Range of q at the section over the measured periods (diagnostic).
    #[allow(dead_code)]
    pub min_q: f64,
    #[allow(dead_code)]
    pub max_q: f64,
    pub steps: u64,
}

/// Steady state at one speed, starting from (and updating) the carried state.
pub fn steady_state(
    ex: &Excitation,
    c: &mut Carried,
    cfg: &SimConfig,
) -> Result<SteadyPoint, IntegrationError> {
    let period = 2.0 * PI / ex.omega;
    let budget = ((cfg.transient_zeta_t / (ex.zeta * period)).ceil() as usize)
        .max(cfg.min_transient_periods + 1);
    let mut hist: VecDeque<State> = VecDeque::with_capacity(cfg.max_period + 2);
    hist.push_back(c.y);
    let mut found: Option<usize> = None;
    let mut dist = f64::INFINITY;
    let mut steps = 0u64;
    let mut dummy = Extremes::new();
    let mut dummy_f = f64::NEG_INFINITY;
    let mut k = 0usize;
    let mut limit = budget;
    let mut min_dist = f64::INFINITY;
    loop {
        if k >= limit {
            // Budget spent: a motion that is visibly settling onto an orbit (the section repeats
            // to 1e-4 at some lag, e.g. near a fold where a multiplier is close to 1) is followed
            // up to 5 budgets; chaotic motion is measured as it is.
            if min_dist < 1e-4 && limit < 5 * budget {
                limit += budget;
            } else {
                break;
            }
        }
        one_period(
            ex,
            c,
            period,
            cfg,
            false,
            &mut dummy,
            &mut dummy_f,
            &mut steps,
        )?;
        k += 1;
        hist.push_back(c.y);
        if hist.len() > cfg.max_period + 1 {
            hist.pop_front();
        }
        if k >= cfg.min_transient_periods {
            let last = hist.len() - 1;
            for p in 1..=cfg.max_period.min(last) {
                let a = &hist[last];
                let b = &hist[last - p];
                let d = (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
                if p == 1 {
                    dist = d;
                }
                if p <= cfg.max_period {
                    min_dist = if p == 1 { d } else { min_dist.min(d) };
                }
                if d < cfg.section_tol {
                    // Least period: the smallest divisor of p at which the section already
                    // repeats (a converged period-1 orbit can pass the test first at a lag p > 1
                    // when its transient rotates with a complex multiplier).
                    let mut least = p;
                    for q in 1..p {
                        if p % q == 0 {
                            let c = &hist[last - q];
                            let dq = (a[0] - c[0]).abs().max((a[1] - c[1]).abs());
                            if dq < 1e3 * cfg.section_tol.max(d) {
                                least = q;
                                break;
                            }
                        }
                    }
                    found = Some(least);
                    dist = d;
                    break;
                }
            }
            if found.is_some() {
                break;
            }
        }
    }
    let mut ext = Extremes::new();
    let mut fmax = f64::NEG_INFINITY;
    let (mut qmin, mut qmax) = (f64::INFINITY, f64::NEG_INFINITY);
    let measure_periods = match found {
        Some(p) => p,
        None => cfg.window_periods,
    };
    // q range: sample the section only (diagnostic).
    for _ in 0..measure_periods {
        one_period(ex, c, period, cfg, true, &mut ext, &mut fmax, &mut steps)?;
        qmin = qmin.min(c.y[0]);
        qmax = qmax.max(c.y[0]);
    }
    if let Some(p) = found {
        // The state carried to the next speed is the one at the end of a 64-period window, as if
        // the whole window had been integrated: (64 - p) more periods on the orbit, which for a
        // converged period-p orbit is (64 mod p) periods.
        let extra = (cfg.window_periods.saturating_sub(p) + cfg.carry_shift) % p;
        for _ in 0..extra {
            one_period(
                ex,
                c,
                period,
                cfg,
                false,
                &mut dummy,
                &mut dummy_f,
                &mut steps,
            )?;
        }
    }
    Ok(SteadyPoint {
        x_pp: ext.max - ext.min,
        force_max: fmax,
        period: found,
        transient_periods: k,
        section_distance: dist,
        min_q: qmin,
        max_q: qmax,
        steps,
    })
}
