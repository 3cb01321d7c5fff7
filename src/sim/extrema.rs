//! Extremes of the response over analysed periods: q (for q_a, q_m and the impact regime), the
//! dynamic transmission error x = q + e/b, and the dynamic mesh force (for D_L, Sec. 7).

use super::flow::{PeriodFlow, Piece, State};
use crate::error::Result;
use crate::model::GearPair;

/// Advance `x` by `periods` forcing periods, folding every piece of the trajectory into fresh
/// extremes; returns them and the state reached.
pub(crate) fn extremes_over<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    periods: usize,
) -> Result<(Extremes, State)> {
    let model = flow.model();
    let mut ext = Extremes::default();
    let mut z = x;
    for _ in 0..periods {
        z = flow.step(z, Some(&mut |piece| ext.observe(model, piece)))?;
    }
    Ok((ext, z))
}

/// Running minima and maxima over the pieces of trajectory observed so far.
#[derive(Clone, Copy, Debug)]
pub struct Extremes {
    /// Smallest and largest q.
    pub q: (f64, f64),
    /// Smallest and largest dynamic transmission error x = q + e/b.
    pub dte: (f64, f64),
    /// Largest dynamic mesh force 2 zeta q' + k(t) f(q).
    pub mesh_force_max: f64,
}

impl Default for Extremes {
    fn default() -> Self {
        Extremes {
            q: (f64::INFINITY, f64::NEG_INFINITY),
            dte: (f64::INFINITY, f64::NEG_INFINITY),
            mesh_force_max: f64::NEG_INFINITY,
        }
    }
}

/// Samples per forcing period before local refinement.
const SAMPLES_PER_PERIOD: f64 = 96.0;

impl Extremes {
    /// Fold one piece of trajectory into the extremes: sample it, then refine each candidate
    /// extremum by golden-section search on the closed form / dense output.
    pub fn observe(&mut self, model: &GearPair, piece: &dyn Piece) {
        let (a, b) = piece.span();
        if b <= a {
            return;
        }
        let period = model.period();
        let n = ((b - a) / period * SAMPLES_PER_PERIOD).ceil().max(2.0) as usize;
        let h = (b - a) / n as f64;
        let q = |s: f64| piece.eval(s)[0];
        let x = |s: f64| model.dte(s, piece.eval(s)[0]);
        let force = |s: f64| {
            let st = piece.eval(s);
            model.mesh_force(s, st[0], st[1])
        };
        // One evaluation of the piece per sample serves all five extrema (the closed form's
        // evaluations dominate the cost of the analysis).
        let states: Vec<(f64, [f64; 2])> = (0..=n)
            .map(|i| {
                let s = if i == n { b } else { a + i as f64 * h };
                (s, piece.eval(s))
            })
            .collect();
        let q_samples: Vec<f64> = states.iter().map(|(_, st)| st[0]).collect();
        let x_samples: Vec<f64> = states.iter().map(|&(s, st)| model.dte(s, st[0])).collect();
        let force_samples = states
            .iter()
            .map(|&(s, st)| model.mesh_force(s, st[0], st[1]));
        let (qmin, qmax) = extreme_pair(&q, &q_samples, a, b, h);
        let (xmin, xmax) = extreme_pair(&x, &x_samples, a, b, h);
        let fmax = refine_max(&force, force_samples, a, b, h);
        self.q = (self.q.0.min(qmin), self.q.1.max(qmax));
        self.dte = (self.dte.0.min(xmin), self.dte.1.max(xmax));
        self.mesh_force_max = self.mesh_force_max.max(fmax);
    }
}

/// Minimum and maximum of f on [a, b] from its samples f(a + i h) (see [`refine_max`]).
fn extreme_pair(f: &dyn Fn(f64) -> f64, samples: &[f64], a: f64, b: f64, h: f64) -> (f64, f64) {
    let neg = |s: f64| -f(s);
    (
        -refine_max(&neg, samples.iter().map(|v| -v), a, b, h),
        refine_max(f, samples.iter().copied(), a, b, h),
    )
}

/// Maximum of f on [a, b]: best of the samples f(a + i h), i = 0..=n (the last at b), refined by
/// golden section on the cells either side of the best one.
fn refine_max(
    f: &dyn Fn(f64) -> f64,
    samples: impl Iterator<Item = f64>,
    a: f64,
    b: f64,
    h: f64,
) -> f64 {
    let mut best_i = 0;
    let mut best = f64::NEG_INFINITY;
    for (i, v) in samples.enumerate() {
        if v > best {
            best = v;
            best_i = i;
        }
    }
    // Refine on the cells either side of the best sample, also when it is an end of the piece:
    // the true maximum may lie just inside (golden section then converges to the end if not).
    let lo = (a + (best_i as f64 - 1.0) * h).max(a);
    let hi = (a + (best_i as f64 + 1.0) * h).min(b);
    best.max(golden_max(f, lo, hi))
}

/// Golden-section search for the maximum of a unimodal f on [lo, hi] (to 1e-12 relative in t).
pub(crate) fn golden_max(f: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    const R: f64 = 0.618_033_988_749_894_9;
    let mut c = hi - R * (hi - lo);
    let mut d = lo + R * (hi - lo);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..60 {
        if hi - lo <= 1e-12 * (1.0 + hi.abs()) {
            break;
        }
        if fc > fd {
            hi = d;
            d = c;
            fd = fc;
            c = hi - R * (hi - lo);
            fc = f(c);
        } else {
            lo = c;
            c = d;
            fc = fd;
            d = lo + R * (hi - lo);
            fd = f(d);
        }
    }
    fc.max(fd)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Sine;
    impl Piece for Sine {
        fn span(&self) -> (f64, f64) {
            (0.0, 2.0 * std::f64::consts::PI)
        }
        fn eval(&self, s: f64) -> [f64; 2] {
            [3.0 + 0.7 * (s + 0.3).sin(), 0.7 * (s + 0.3).cos()]
        }
    }

    #[test]
    fn extremes_of_a_sine_are_exact() {
        let m = GearPair {
            zeta: 0.05,
            mean_force: 1.0,
            omega: 1.0,
            ste: vec![],
            torque: vec![],
            stiffness: vec![],
        };
        let mut e = Extremes::default();
        e.observe(&m, &Sine);
        assert!((e.q.0 - 2.3).abs() < 1e-12 && (e.q.1 - 3.7).abs() < 1e-12);
        // mesh force = 2 zeta v + (q - 1): maximum of 0.07 cos + 0.7 sin + 2.
        let expect = 2.0 + (0.07f64.powi(2) + 0.49).sqrt();
        assert!((e.mesh_force_max - expect).abs() < 1e-12);
    }
}
