//! Dense time histories of a trajectory (for phase-plane and time-history figures, Figs 2, 4, 5,
//! 7, 8), sampled from the closed-form pieces or the dense output of each period.

use super::flow::{PeriodFlow, State};
use crate::error::Result;
use serde::Serialize;

/// One sample of a trajectory.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Sample {
    /// Dimensionless time since the first sampled period began.
    pub t: f64,
    /// Displacement q.
    pub q: f64,
    /// Velocity q'.
    pub v: f64,
    /// Dynamic transmission error x = q + e/b.
    pub dte: f64,
    /// Dynamic mesh force 2 zeta q' + k f(q).
    pub mesh_force: f64,
}

/// Sample `periods` forcing periods from section point `x0` at `per_period` equally spaced times
/// per period (plus each period's end). Returns the samples and the final state.
pub fn sample_trajectory<F: PeriodFlow + ?Sized>(
    flow: &F,
    x0: State,
    periods: usize,
    per_period: usize,
) -> Result<(Vec<Sample>, State)> {
    let model = flow.model();
    let period = flow.period();
    let h = period / per_period.max(1) as f64;
    let mut out = Vec::with_capacity(periods * per_period + 1);
    let mut x = x0;
    for k in 0..periods {
        let t0 = k as f64 * period;
        let mut next = 0usize;
        x = flow.step(
            x,
            Some(&mut |piece| {
                let (a, b) = piece.span();
                while next <= per_period {
                    let s = (next as f64 * h).min(period);
                    if s > b || (s == b && next < per_period && b < period) {
                        break;
                    }
                    if s >= a {
                        let st = piece.eval(s);
                        out.push(Sample {
                            t: t0 + s,
                            q: st[0],
                            v: st[1],
                            dte: model.dte(s, st[0]),
                            mesh_force: model.mesh_force(s, st[0], st[1]),
                        });
                    }
                    next += 1;
                }
            }),
        )?;
        if k + 1 < periods {
            // The end of this period is the start of the next: keep one copy.
            out.pop();
        }
    }
    Ok((out, x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::GearPair;
    use crate::sim::ExactFlow;

    #[test]
    fn samples_are_uniform_and_continuous() {
        let m = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        let f = ExactFlow::new(&m).unwrap();
        let (s, end) = sample_trajectory(&f, [0.5, 0.0], 3, 64).unwrap();
        assert_eq!(s.len(), 3 * 64 + 1);
        let h = m.period() / 64.0;
        for w in s.windows(2) {
            assert!((w[1].t - w[0].t - h).abs() < 1e-9);
        }
        assert!((s.last().unwrap().q - end[0]).abs() < 1e-12);
    }
}
