//! Where a segment of the exact solution leaves its region (design.md section 6): the signed
//! distance to each boundary q = +-1 and its derivatives, the quadratic and cubic Taylor lower
//! bounds that prove an interval free of crossings (so a grazing crossing cannot be stepped
//! over), and the quintic Hermite start of the root refinement.

use super::flow::State;
use crate::model::Region;

/// A boundary of a region: the distance to it is `sign * (q - level)`, positive inside.
#[derive(Clone, Copy, Debug)]
pub(super) struct Boundary {
    pub(super) level: f64,
    pub(super) sign: f64,
    /// Region entered when the distance becomes negative.
    pub(super) beyond: Region,
}

impl Boundary {
    pub(super) fn of(region: Region) -> &'static [Boundary] {
        const CONTACT: [Boundary; 1] = [Boundary {
            level: 1.0,
            sign: 1.0,
            beyond: Region::Gap,
        }];
        const BACK: [Boundary; 1] = [Boundary {
            level: -1.0,
            sign: -1.0,
            beyond: Region::Gap,
        }];
        const GAP: [Boundary; 2] = [
            Boundary {
                level: 1.0,
                sign: -1.0,
                beyond: Region::Contact,
            },
            Boundary {
                level: -1.0,
                sign: 1.0,
                beyond: Region::BackContact,
            },
        ];
        match region {
            Region::Contact => &CONTACT,
            Region::BackContact => &BACK,
            Region::Gap => &GAP,
        }
    }

    #[inline]
    pub(super) fn distance(&self, x: State) -> (f64, f64) {
        (self.sign * (x[0] - self.level), self.sign * x[1])
    }

    #[inline]
    pub(super) fn sample(&self, s: f64, x: [f64; 3]) -> Sample {
        let (d, dv) = self.distance([x[0], x[1]]);
        Sample {
            s,
            d,
            dv,
            dd: self.sign * x[2],
        }
    }
}

/// Distance to a boundary and its first two derivatives at time s.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    pub(super) s: f64,
    pub(super) d: f64,
    pub(super) dv: f64,
    pub(super) dd: f64,
}

/// A located boundary crossing: its time (the root to rounding) and q' there from the closed form.
#[derive(Clone, Copy, Debug)]
pub(super) struct Crossing {
    pub(super) time: f64,
    pub(super) velocity: f64,
    /// (sin, cos) of Omega time, for the segment that starts there.
    pub(super) phase: (f64, f64),
}

/// Root in (a, b) of the quintic Hermite interpolant of d, d', d'' at samples a and b, where
/// d(a) >= 0 > d(b): a starting point for the refinement (its error on a scan cell of width w is
/// about max|d^(6)| (w/2)^6 / 720 / |d'|, ~1e-7 here). Safeguarded Newton on the polynomial,
/// from the secant point.
pub(super) fn hermite_root(a: Sample, b: Sample) -> f64 {
    let w = b.s - a.s;
    // p(t) on t in [0, 1] with p, p', p'' matching the samples scaled to unit width.
    let (y0, dy) = (a.d, b.d - a.d);
    let (v0, v1) = (a.dv * w, b.dv * w);
    let (a0, a1) = (a.dd * w * w, b.dd * w * w);
    let c3 = 10.0 * dy - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1;
    let c4 = -15.0 * dy + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1;
    let c5 = 6.0 * dy - 3.0 * (v0 + v1) - 0.5 * (a0 - a1);
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut t = y0 / -dy;
    for _ in 0..16 {
        let p = y0 + t * (v0 + t * (0.5 * a0 + t * (c3 + t * (c4 + t * c5))));
        let dp = v0 + t * (a0 + t * (3.0 * c3 + t * (4.0 * c4 + t * 5.0 * c5)));
        if p > 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let next = t - p / dp;
        let next = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        // Quadratic convergence: after a step this small the error is ~1e-10 of the cell, from
        // which one Halley step of the refinement reaches rounding.
        let done = (next - t).abs() <= 1e-5;
        t = next;
        if done {
            break;
        }
    }
    a.s + t * w
}

/// Time over which the quadratic lower bound d + d' t - M2 t^2 / 2 of the distance to each of
/// `bounds` stays positive from the state x (0 on or beyond a boundary).
#[inline]
pub(super) fn safe_horizon(bounds: &[Boundary], x: [f64; 3], m2: f64) -> f64 {
    bounds
        .iter()
        .map(|bd| {
            let (d, dv) = bd.distance([x[0], x[1]]);
            if d <= 0.0 {
                return 0.0;
            }
            // The positive root of the bound, in the form without cancellation.
            let r = (dv * dv + 2.0 * m2 * d).sqrt();
            if dv < 0.0 {
                2.0 * d / (r - dv)
            } else {
                (dv + r) / m2
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// True when the quadratic Taylor bound d + d' t - M2 t^2 / 2 from sample `x` keeps the
/// distance above -`noise` (its rounding level) on [0, w]: a root in there is a touch within
/// rounding, which halving cannot resolve. Where d, d' and M2 are themselves at rounding (a
/// pair at rest on a flank with no forcing; every force ~1e-16 b) each half is as undecided
/// as the whole, and without this stop the search visited 2^60 cells.
#[inline]
pub(super) fn within_rounding(x: Sample, w: f64, m2: f64, noise: f64) -> bool {
    x.d.min(x.d + x.dv * w - 0.5 * m2 * w * w) >= -noise
}

/// True when a Taylor lower bound from sample `x` proves d > 0 on (0, w] away from x, looking
/// forward (dir = 1) or backward (dir = -1).
#[inline]
pub(super) fn excluded(x: Sample, w: f64, (m2, m3): (f64, f64), dir: f64) -> bool {
    let (d, dv, dd) = (x.d, dir * x.dv, x.dd);
    if d < 0.0 || (d == 0.0 && dv < 0.0) {
        return false;
    }
    // Quadratic bound: concave, so its minimum on [0, w] is at an end.
    if (d > 0.0 || dv > 0.0) && d + dv * w - 0.5 * m2 * w * w > 0.0 {
        return true;
    }
    // Cubic bound L(t) = d + dv t + dd t^2 / 2 - m3 t^3 / 6: check the end and the interior
    // stationary points (roots of dv + dd t - m3 t^2 / 2).
    let cubic = |t: f64| d + t * (dv + t * (0.5 * dd - m3 * t / 6.0));
    if cubic(w) <= 0.0 {
        return false;
    }
    if d == 0.0 && dv == 0.0 && dd <= 0.0 {
        // Starting on the boundary, positive just after only if the leading term is.
        return false;
    }
    let disc = dd * dd + 2.0 * m3 * dv;
    if disc >= 0.0 {
        let r = disc.sqrt();
        for t in [(dd - r) / m3, (dd + r) / m3] {
            if t > 0.0 && t < w && cubic(t) <= 0.0 {
                return false;
            }
        }
    }
    true
}
