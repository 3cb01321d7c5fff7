//! Event functions g(t, y) and their location on the dense output of an accepted step.
//!
//! A sign change of g between the ends of a step is located by the Illinois variant of regula
//! falsi (Dowell & Jarratt, BIT 11, 1971), kept inside a shrinking bracket with a bisection
//! fallback, to a bracket width of a few ulps of t. A pair of roots inside one step (a shallow
//! dip through the level and back, invisible at the step ends) is found by locating the extremum
//! of g, the root of its rate dg/dt along the dense output, and testing the sign of g there.

use super::dense::DenseStep;

/// Direction of a sign change of g that counts as an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    /// g goes from <= 0 to > 0.
    Rising,
    /// g goes from >= 0 to < 0.
    Falling,
    /// A strict sign change either way (a start exactly on the level does not count, so a
    /// restart on the level does not fire at once).
    Either,
}

impl Crossing {
    /// Whether the move of g from `a` to `b` is a crossing in this direction. The start value
    /// may be exactly 0 (a restart on the level) but the end value must be strictly past it, so
    /// a trajectory leaving the level away from the event side does not fire.
    #[inline]
    pub fn fires(self, a: f64, b: f64) -> bool {
        match self {
            Crossing::Rising => a <= 0.0 && b > 0.0,
            Crossing::Falling => a >= 0.0 && b < 0.0,
            Crossing::Either => (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0),
        }
    }

    /// Whether an interior extremum of g, with rate `r0` at the start and `r1` at the end of a
    /// step, turns g toward the event side (a minimum for `Falling`, a maximum for `Rising`).
    #[inline]
    fn turns_toward(self, r0: f64, r1: f64) -> bool {
        let minimum = r0 < 0.0 && r1 > 0.0;
        let maximum = r0 > 0.0 && r1 < 0.0;
        match self {
            Crossing::Rising => maximum,
            Crossing::Falling => minimum,
            Crossing::Either => minimum || maximum,
        }
    }
}

/// An event function g(t, y) of an N-dimensional system, with its crossing direction.
pub trait EventFunction<const N: usize> {
    /// Value of g at (t, y).
    fn value(&self, t: f64, y: &[f64; N]) -> f64;

    /// Rate dg/dt along the flow at (t, y) with y' = `ydot`. It serves to detect and locate an
    /// extremum of g inside a step; the default, a one-sided directional difference, is
    /// adequate for that.
    fn rate(&self, t: f64, y: &[f64; N], ydot: &[f64; N]) -> f64 {
        let ynorm = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let fnorm = ydot.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if fnorm == 0.0 {
            return 0.0;
        }
        let delta = 1e-7 * (1.0 + ynorm) / fnorm;
        let mut yp = *y;
        for (a, b) in yp.iter_mut().zip(ydot) {
            *a += delta * b;
        }
        (self.value(t + delta, &yp) - self.value(t, y)) / delta
    }

    /// Which sign changes of g are events.
    fn crossing(&self) -> Crossing;
}

/// The event `y[component] = level`: g = `y[component] - level`, with an exact rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelCrossing {
    /// Index of the state component.
    pub component: usize,
    /// Level whose crossing is the event.
    pub level: f64,
    /// Direction that counts.
    pub crossing: Crossing,
}

impl<const N: usize> EventFunction<N> for LevelCrossing {
    #[inline]
    fn value(&self, _t: f64, y: &[f64; N]) -> f64 {
        y.get(self.component).map_or(f64::NAN, |v| v - self.level)
    }
    #[inline]
    fn rate(&self, _t: f64, _y: &[f64; N], ydot: &[f64; N]) -> f64 {
        ydot.get(self.component).copied().unwrap_or(f64::NAN)
    }
    fn crossing(&self) -> Crossing {
        self.crossing
    }
}

/// An event given by a closure g(t, y) and a direction.
pub struct FnEvent<F> {
    /// The event function g(t, y).
    pub g: F,
    /// Direction that counts.
    pub crossing: Crossing,
}

impl<const N: usize, F: Fn(f64, &[f64; N]) -> f64> EventFunction<N> for FnEvent<F> {
    fn value(&self, t: f64, y: &[f64; N]) -> f64 {
        (self.g)(t, y)
    }
    fn crossing(&self) -> Crossing {
        self.crossing
    }
}

/// Maximum iterations of the bracketing root finders (each halves the bracket at worst every
/// other iteration, so 200 covers any f64 bracket).
const MAX_ITER: usize = 200;

/// Whether the bracket [a, b] is as narrow as it usefully gets (a few ulps of t).
#[inline]
fn converged(a: f64, b: f64) -> bool {
    (b - a).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) + f64::MIN_POSITIVE
}

/// Illinois regula falsi for the first point past a sign change of `h` on [a, b], where
/// `past(h(a))` is false and `past(h(b))` is true. Returns the end of the final bracket on the
/// `past` side, so the returned time is never before the crossing.
fn illinois(
    h: impl Fn(f64) -> f64,
    past: impl Fn(f64) -> bool,
    mut a: f64,
    mut ha: f64,
    mut b: f64,
    mut hb: f64,
) -> f64 {
    // side: +1 when the last two updates moved b, -1 when they moved a.
    let mut side = 0i8;
    for _ in 0..MAX_ITER {
        if converged(a, b) {
            break;
        }
        let mut t = if hb != ha {
            (a * hb - b * ha) / (hb - ha)
        } else {
            0.5 * (a + b)
        };
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        let ht = h(t);
        if past(ht) {
            b = t;
            hb = ht;
            if side == 1 {
                ha *= 0.5;
            }
            side = 1;
        } else {
            a = t;
            ha = ht;
            if side == -1 {
                hb *= 0.5;
            }
            side = -1;
        }
    }
    b
}

/// Result of scanning one accepted step for events.
pub(super) struct Hit {
    /// Index of the event that fired first.
    pub index: usize,
    /// Event time (on the far side of the level, within a few ulps of the root).
    pub t: f64,
}

/// Per-event data at the two ends of a step: values and rates of g.
pub(super) struct EndData<'a> {
    pub g0: &'a [f64],
    pub g1: &'a [f64],
    pub r0: &'a [f64],
    pub r1: &'a [f64],
}

/// Whether the step needs the dense output to be scanned for events (a sign change at the
/// ends, or an extremum that turns g toward the event side).
pub(super) fn needs_scan<const N: usize>(
    events: &[&dyn EventFunction<N>],
    ends: &EndData<'_>,
) -> bool {
    events.iter().enumerate().any(|(i, ev)| {
        let c = ev.crossing();
        c.fires(ends.g0[i], ends.g1[i]) || c.turns_toward(ends.r0[i], ends.r1[i])
    })
}

/// Earliest event on the step described by `dense`, if any. The rate of g inside the step is
/// taken from the derivative of the dense output, so the scan costs no right-hand-side calls.
pub(super) fn locate<const N: usize>(
    events: &[&dyn EventFunction<N>],
    dense: &DenseStep<N>,
    ends: &EndData<'_>,
) -> Option<Hit> {
    let (ta, tb) = dense.span();
    let mut best: Option<Hit> = None;
    for (i, ev) in events.iter().enumerate() {
        let c = ev.crossing();
        let g = |t: f64| ev.value(t, &dense.eval(t));
        let (ga, gb) = (ends.g0[i], ends.g1[i]);
        // Right end of the bracket of the first crossing, and g there.
        let mut bracket: Option<(f64, f64)> = None;
        if c.turns_toward(ends.r0[i], ends.r1[i]) {
            // Extremum of g: the root of its rate, which has opposite signs r0, r1 at the ends.
            let rate = |t: f64| ev.rate(t, &dense.eval(t), &dense.eval_derivative(t));
            let r0 = ends.r0[i];
            let t_ext = illinois(
                rate,
                |r| r != 0.0 && r.signum() != r0.signum(),
                ta,
                r0,
                tb,
                ends.r1[i],
            );
            let ge = g(t_ext);
            if c.fires(ga, ge) {
                bracket = Some((t_ext, ge));
            }
        }
        if bracket.is_none() && c.fires(ga, gb) {
            bracket = Some((tb, gb));
        }
        let Some((b, gb_)) = bracket else { continue };
        // The start value stays exact (it may be 0 on a restart) so that the first root after
        // the start is found; the result lies on the far side of the level.
        let t = illinois(g, |v| c.fires(ga, v), ta, ga, b, gb_);
        if best.as_ref().is_none_or(|h| t < h.t) {
            best = Some(Hit { index: i, t });
        }
    }
    best
}
