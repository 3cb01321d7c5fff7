//! Exact event-to-event solution of eq. 3a with k = 1 (design.md section 6).
//!
//! In each region of eq. 3c the equation is linear with constant coefficients and harmonic
//! forcing, q'' + 2 zeta q' + kappa q = F_m + c + sum_n (s_n sin n Omega t + c_n cos n Omega t),
//! so the solution between crossings of q = +-1 is closed form: a particular solution (constant,
//! or a ramp F_m t / (2 zeta) in the gap, plus harmonics) and the homogeneous solution
//! e^{-zeta tau}(A cos w_d tau + B sin w_d tau) in contact or D + E e^{-2 zeta tau} in the gap.
//!
//! Crossings are located without sampling sign checks alone: over each scan interval the distance
//! d(s) to a boundary is bounded below by d(a) + d'(a) tau - M tau^2 / 2, where M is a rigorous
//! bound of |q''| from the closed form (harmonic amplitudes times (n Omega)^2 plus the decaying
//! homogeneous amplitude). An interval is skipped only when that bound proves d > 0 on it; otherwise
//! it is bisected, so a grazing crossing cannot be stepped over.
//!
//! The tangent dynamics are products of the region matrices e^{A tau}: f is continuous, so the
//! vector field is continuous at q = +-1 and there is no saltation term.

use super::fast_math::sin_cos;
use super::flow::{Observer, PeriodFlow, Piece, State};
use crate::error::{GearError, Result};
use crate::model::{GearPair, Region};
use nalgebra::Matrix2;

/// Maximum number of boundary crossings accepted within one forcing period (a Zeno guard).
const MAX_CROSSINGS_PER_PERIOD: usize = 100_000;
/// Bisection depth below which an interval the bound cannot exclude is taken as a tangency.
const MAX_DEPTH: u32 = 60;

/// Closed-form particular solution of one region.
#[derive(Clone, Debug)]
struct RegionLaw {
    region: Region,
    /// Constant part of the particular solution (contact regions).
    constant: f64,
    /// Ramp F_m / (2 zeta) of the particular solution (gap only).
    slope: f64,
    /// Per harmonic order n (index n-1): coefficients (a_n, b_n) of a cos + b sin.
    harmonics: Vec<(f64, f64)>,
    /// sum_n (n Omega)^2 sqrt(a_n^2 + b_n^2): bound on |q_p''| of the harmonic part.
    harmonic_accel_bound: f64,
    /// sum_n (n Omega)^3 sqrt(a_n^2 + b_n^2): bound on the third derivative of the harmonic part.
    harmonic_jerk_bound: f64,
}

impl RegionLaw {
    fn new(model: &GearPair, region: Region) -> Self {
        let zeta = model.zeta;
        let kappa = region.kappa();
        let c = model.mean_force + region.force_offset();
        let n_max = model.max_order() as usize;
        let mut harmonics = vec![(0.0, 0.0); n_max];
        let mut bound = 0.0;
        let mut jerk = 0.0;
        for h in model.forcing_harmonics() {
            let w = h.order as f64 * model.omega;
            // forcing = Re(Fc e^{iwt}) with Fc = cos_coef - i sin_coef; X = Fc / (kappa - w^2 + 2 i zeta w)
            let (fr, fi) = (h.cos_coef, -h.sin_coef);
            let (dr, di) = (kappa - w * w, 2.0 * zeta * w);
            let den = dr * dr + di * di;
            let xr = (fr * dr + fi * di) / den;
            let xi = (fi * dr - fr * di) / den;
            let (a, b) = (xr, -xi);
            harmonics[h.order as usize - 1] = (a, b);
            bound += w * w * (a * a + b * b).sqrt();
            jerk += w * w * w * (a * a + b * b).sqrt();
        }
        let (constant, slope) = if kappa > 0.0 {
            (c, 0.0)
        } else {
            (0.0, c / (2.0 * zeta))
        };
        RegionLaw {
            region,
            constant,
            slope,
            harmonics,
            harmonic_accel_bound: bound,
            harmonic_jerk_bound: jerk,
        }
    }

    /// Harmonic part of the particular solution and its first two derivatives at local time s.
    #[inline]
    fn harmonic(&self, omega: f64, s: f64) -> [f64; 3] {
        let (s1, c1) = sin_cos(omega * s);
        let Some((&(a, b), higher)) = self.harmonics.split_first() else {
            return [0.0; 3];
        };
        // Order 1, then higher orders by the angle-addition recurrence (no further sin/cos).
        let y = a * c1 + b * s1;
        let (mut q, mut v, mut acc) = (y, omega * (b * c1 - a * s1), -omega * omega * y);
        let (mut sn, mut cn, mut order) = (s1, c1, 1.0);
        for &(a, b) in higher {
            (sn, cn) = (sn * c1 + cn * s1, cn * c1 - sn * s1);
            order += 1.0;
            let w = order * omega;
            let y = a * cn + b * sn;
            q += y;
            v += w * (b * cn - a * sn);
            acc -= w * w * y;
        }
        [q, v, acc]
    }
}

/// Homogeneous part of a segment, referred to the segment start.
#[derive(Clone, Copy, Debug)]
enum Homogeneous {
    /// e^{-zeta tau} (a cos w_d tau + b sin w_d tau), in contact.
    Oscillating { a: f64, b: f64 },
    /// d + e e^{-2 zeta tau}, in the gap.
    Decaying { d: f64, e: f64 },
}

/// One closed-form piece of trajectory inside a single region.
#[derive(Clone, Copy)]
struct Segment<'a> {
    flow: &'a ExactFlow,
    law: &'a RegionLaw,
    s0: f64,
    s1: f64,
    hom: Homogeneous,
    /// q, q', q'' at s0 from the closed form (what `full(s0)` returns), kept because every
    /// crossing search starts there.
    at_start: [f64; 3],
}

impl<'a> Segment<'a> {
    fn start(flow: &'a ExactFlow, region: Region, s0: f64, x: State) -> Self {
        let law = flow.law(region);
        let [hq, hv, ha] = law.harmonic(flow.omega, s0);
        let y0 = x[0] - hq - law.constant;
        let yv0 = x[1] - hv - law.slope;
        let zeta = flow.zeta;
        // The homogeneous part at tau = 0, the same arithmetic as `full` with e^0 = 1, sin 0 = 0.
        let (hom, yq, yv, ya) = match region {
            Region::Gap => {
                let e = -yv0 / (2.0 * zeta);
                let d = y0 - e;
                let yv = -2.0 * zeta * e;
                (Homogeneous::Decaying { d, e }, d + e, yv, -2.0 * zeta * yv)
            }
            _ => {
                let (a, b) = (y0, (yv0 + zeta * y0) / flow.wd);
                let yv = flow.wd * b - zeta * a;
                (
                    Homogeneous::Oscillating { a, b },
                    a,
                    yv,
                    -2.0 * zeta * yv - a,
                )
            }
        };
        Segment {
            flow,
            law,
            s0,
            s1: s0,
            hom,
            at_start: [hq + yq + law.constant, hv + yv + law.slope, ha + ya],
        }
    }

    #[inline]
    fn state(&self, s: f64) -> State {
        let [q, v, _] = self.full(s);
        [q, v]
    }

    /// q, q' and q'' at local time s, all from the closed form.
    #[inline]
    fn full(&self, s: f64) -> [f64; 3] {
        self.full_with_decay(s).0
    }

    /// [`Self::full`] and the bounds of [`Self::bounds_from_decay`] from s on (for s >= s0),
    /// sharing the decay factor of the homogeneous part.
    #[inline]
    fn full_and_bounds(&self, s: f64) -> ([f64; 3], (f64, f64)) {
        let (x, decay) = self.full_with_decay(s);
        (x, self.bounds_from_decay(decay))
    }

    /// q, q', q'' at s and the homogeneous decay factor there (e^{-zeta tau} in contact,
    /// e^{-2 zeta tau} in the gap).
    #[inline]
    fn full_with_decay(&self, s: f64) -> ([f64; 3], f64) {
        let tau = s - self.s0;
        let [hq, hv, ha] = self.law.harmonic(self.flow.omega, s);
        let zeta = self.flow.zeta;
        let (yq, yv, ya, decay) = match self.hom {
            Homogeneous::Oscillating { a, b } => {
                let e = (-zeta * tau).exp();
                let (sn, cs) = sin_cos(self.flow.wd * tau);
                let wd = self.flow.wd;
                let yq = e * (a * cs + b * sn);
                let yv = e * ((wd * b - zeta * a) * cs - (zeta * b + wd * a) * sn);
                (yq, yv, -2.0 * zeta * yv - yq, e)
            }
            Homogeneous::Decaying { d, e } => {
                let g = (-2.0 * zeta * tau).exp();
                let yv = -2.0 * zeta * e * g;
                (d + e * g, yv, -2.0 * zeta * yv, g)
            }
        };
        (
            [
                hq + yq + self.law.constant + self.law.slope * tau,
                hv + yv + self.law.slope,
                ha + ya,
            ],
            decay,
        )
    }

    /// Upper bounds of the second and third derivatives of q on [s_from, s1], given the
    /// homogeneous decay factor at s_from (the homogeneous part only decays after it).
    #[inline]
    fn bounds_from_decay(&self, decay: f64) -> (f64, f64) {
        let zeta = self.flow.zeta;
        // |lambda| = 1 for the contact modes; the gap mode has lambda = -2 zeta.
        let (h2, h3) = match self.hom {
            Homogeneous::Oscillating { a, b } => {
                let c = (a * a + b * b).sqrt() * decay;
                (c, c)
            }
            Homogeneous::Decaying { e, .. } => {
                let c = 2.0 * zeta * e.abs() * decay;
                (2.0 * zeta * c, 4.0 * zeta * zeta * c)
            }
        };
        // A relative margin absorbs rounding in the bounds themselves.
        let margin = 1.0 + 1e-12;
        (
            (self.law.harmonic_accel_bound + h2) * margin + 1e-300,
            (self.law.harmonic_jerk_bound + h3) * margin + 1e-300,
        )
    }

    /// State-transition matrix e^{A tau} of the region (the tangent dynamics).
    fn transition(&self, tau: f64) -> Matrix2<f64> {
        let zeta = self.flow.zeta;
        match self.hom {
            Homogeneous::Oscillating { .. } => {
                let wd = self.flow.wd;
                let e = (-zeta * tau).exp();
                let (sn, cs) = sin_cos(wd * tau);
                Matrix2::new(
                    e * (cs + zeta / wd * sn),
                    e * sn / wd,
                    -e * sn / wd,
                    e * (cs - zeta / wd * sn),
                )
            }
            Homogeneous::Decaying { .. } => {
                let g = (-2.0 * zeta * tau).exp();
                Matrix2::new(1.0, (1.0 - g) / (2.0 * zeta), 0.0, g)
            }
        }
    }
}

impl Piece for Segment<'_> {
    fn span(&self) -> (f64, f64) {
        (self.s0, self.s1)
    }
    fn eval(&self, s: f64) -> State {
        self.state(s)
    }
}

/// A boundary of a region: the distance to it is `sign * (q - level)`, positive inside.
#[derive(Clone, Copy, Debug)]
struct Boundary {
    level: f64,
    sign: f64,
    /// Region entered when the distance becomes negative.
    beyond: Region,
}

impl Boundary {
    fn of(region: Region) -> &'static [Boundary] {
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
    fn distance(&self, x: State) -> (f64, f64) {
        (self.sign * (x[0] - self.level), self.sign * x[1])
    }

    #[inline]
    fn sample(&self, s: f64, x: [f64; 3]) -> Sample {
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
struct Sample {
    s: f64,
    d: f64,
    dv: f64,
    dd: f64,
}

/// A located boundary crossing: its time (just on the far side) and q' there.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    time: f64,
    velocity: f64,
}

/// Smallest positive root of the quadratic Taylor model d + d' t + d'' t^2 / 2 at a sample.
fn taylor_root(x: Sample) -> Option<f64> {
    let (c, b, a) = (x.d, x.dv, 0.5 * x.dd);
    if a.abs() < 1e-300 {
        return (b < 0.0).then(|| x.s - c / b);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let r = disc.sqrt();
    // Numerically stable pair of roots.
    let qq = -0.5 * (b + b.signum() * r);
    let roots = [qq / a, if qq != 0.0 { c / qq } else { f64::NAN }];
    roots
        .into_iter()
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |u| u.min(t))))
        .map(|t| x.s + t)
}

/// True when a Taylor lower bound from sample `x` proves d > 0 on (0, w] away from x, looking
/// forward (dir = 1) or backward (dir = -1).
#[inline]
fn excluded(x: Sample, w: f64, (m2, m3): (f64, f64), dir: f64) -> bool {
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

/// The exact piecewise-linear period map of eq. 3a for k(t) = 1 (the paper's model, with any
/// number of STE and external torque harmonics).
#[derive(Clone, Debug)]
pub struct ExactFlow {
    model: GearPair,
    omega: f64,
    zeta: f64,
    wd: f64,
    period: f64,
    scan_step: f64,
    laws: [RegionLaw; 3],
}

impl ExactFlow {
    /// Build the closed-form region solutions. Fails when the model has a time-varying mesh
    /// stiffness, which this solver does not cover (use the Runge-Kutta flow).
    pub fn new(model: &GearPair) -> Result<Self> {
        let model = model.clone().validated()?;
        if model.has_stiffness_variation() {
            return Err(GearError::Unsupported(
                "the exact piecewise solver requires k(t) = 1; use the adaptive Runge-Kutta integrator for time-varying mesh stiffness".into(),
            ));
        }
        let period = model.period();
        let n = model.max_order().max(1) as f64;
        // Scan intervals short against the fastest excitation and the free oscillation (w_d ~ 1).
        let pieces = (16.0 * n).max((period / 0.4).ceil());
        let scan_step = period / pieces;
        Ok(ExactFlow {
            omega: model.omega,
            zeta: model.zeta,
            wd: (1.0 - model.zeta * model.zeta).sqrt(),
            period,
            scan_step,
            laws: [
                RegionLaw::new(&model, Region::Contact),
                RegionLaw::new(&model, Region::Gap),
                RegionLaw::new(&model, Region::BackContact),
            ],
            model,
        })
    }

    fn law(&self, region: Region) -> &RegionLaw {
        match region {
            Region::Contact => &self.laws[0],
            Region::Gap => &self.laws[1],
            Region::BackContact => &self.laws[2],
        }
    }

    /// Region of a state, with the boundary case decided by the direction of motion.
    fn region_of(&self, x: State, s: f64) -> Region {
        let a = self.model.acceleration(s, x[0], x[1]);
        Region::of_state(x[0], x[1], a)
    }

    /// Earliest crossing of a boundary of `seg` in (s_start, s_end], if any.
    ///
    /// Far from the boundaries the scan advances by the horizon over which the quadratic lower
    /// bound d + d' tau - M2 tau^2 / 2 provably stays positive; closer than one nominal scan step it
    /// searches fixed intervals with [`Self::search`].
    fn first_crossing(&self, seg: &Segment, s_end: f64) -> Option<(Crossing, Boundary)> {
        let bounds = Boundary::of(seg.law.region);
        let mut a = seg.s0;
        let mut xa = seg.at_start;
        let mut m = seg.bounds_from_decay(1.0);
        while a < s_end {
            let horizon = bounds
                .iter()
                .map(|bd| {
                    let (d, dv) = bd.distance([xa[0], xa[1]]);
                    if d > 0.0 {
                        (dv + (dv * dv + 2.0 * m.0 * d).sqrt()) / m.0
                    } else {
                        0.0
                    }
                })
                .fold(f64::INFINITY, f64::min);
            if 0.9 * horizon > self.scan_step {
                a = (a + 0.9 * horizon).min(s_end);
                (xa, m) = seg.full_and_bounds(a);
                continue;
            }
            // Near a boundary: a bracket just beyond the linear estimate of the crossing keeps the
            // interval short (monotone, so Newton applies at once); any length is rigorous.
            let approach = bounds
                .iter()
                .map(|bd| {
                    let (d, dv) = bd.distance([xa[0], xa[1]]);
                    if dv < 0.0 && d > 0.0 {
                        2.0 * d / -dv
                    } else {
                        f64::INFINITY
                    }
                })
                .fold(f64::INFINITY, f64::min);
            let b = (a + self.scan_step.min(approach.max(1e-3 * self.scan_step))).min(s_end);
            let (xb, mb) = seg.full_and_bounds(b);
            let mut best: Option<(Crossing, Boundary)> = None;
            for bd in bounds {
                let mut sa = bd.sample(a, xa);
                if a == seg.s0 {
                    // At a segment start on a boundary the distance is exactly zero by construction.
                    sa.d = sa.d.max(0.0);
                }
                let sb = bd.sample(b, xb);
                if let Some(s) = self.search(seg, bd, sa, sb, m, 0) {
                    if best.is_none_or(|(t, _)| s.time < t.time) {
                        best = Some((s, *bd));
                    }
                }
            }
            if best.is_some() {
                return best;
            }
            a = b;
            xa = xb;
            m = mb;
        }
        None
    }

    /// Earliest root of the distance to `bd` on (a, b]. The interval is discarded only when a
    /// Taylor lower bound proves d > 0 on it: d(a) + d'(a) tau - M2 tau^2 / 2 (from either end),
    /// or d(a) + d'(a) tau + d''(a) tau^2 / 2 - M3 tau^3 / 6, with M2, M3 bounds of the second
    /// and third derivatives of q. Otherwise it is bisected, left half first.
    fn search(
        &self,
        seg: &Segment,
        bd: &Boundary,
        a: Sample,
        b: Sample,
        m: (f64, f64),
        depth: u32,
    ) -> Option<Crossing> {
        let w = b.s - a.s;
        if w <= 0.0 {
            return None;
        }
        if a.d >= 0.0 && (excluded(a, w, m, 1.0) || (b.d > 0.0 && excluded(b, w, m, -1.0))) {
            return None;
        }
        if b.d < 0.0 && a.dv + m.0 * w < 0.0 {
            // d decreases throughout: exactly one root, found by safeguarded Newton.
            return Some(self.refine_root(seg, bd, a, b));
        }
        if depth >= MAX_DEPTH {
            // Not excludable but no sign change at this resolution: a tangency (grazing touch)
            // whose penetration is below M2 w^2 / 8, i.e. far below rounding.
            return (b.d < 0.0).then(|| self.refine_root(seg, bd, a, b));
        }
        let mid = 0.5 * (a.s + b.s);
        let (xm, m_right) = seg.full_and_bounds(mid);
        let sm = bd.sample(mid, xm);
        self.search(seg, bd, a, sm, m, depth + 1).or_else(|| {
            if sm.d < 0.0 {
                // The left half holds no root but ends below the boundary: the root is at mid.
                Some(self.refine_root(seg, bd, a, sm))
            } else {
                self.search(seg, bd, sm, b, m_right, depth + 1)
            }
        })
    }

    /// Root of the boundary distance in [a, b] where d(a) >= 0 > d(b): Halley kept in the bracket,
    /// started from the quadratic Taylor model at a, and returned on the far side of the boundary
    /// (d <= 0) so the next region starts beyond it.
    fn refine_root(&self, seg: &Segment, bd: &Boundary, a: Sample, b: Sample) -> Crossing {
        let (mut lo, mut hi) = (a.s, b.s);
        // q' at hi, so that the caller need not evaluate the closed form there again.
        let mut v_hi = bd.sign * b.dv;
        let mut s = taylor_root(a)
            .filter(|&t| t > lo && t < hi)
            .unwrap_or_else(|| {
                // Secant between the bracket ends.
                let t = a.s + a.d / (a.d - b.d) * (b.s - a.s);
                if t > lo && t < hi {
                    t
                } else {
                    0.5 * (lo + hi)
                }
            });
        for _ in 0..200 {
            let x = bd.sample(s, seg.full(s));
            let (d, dv) = (x.d, x.dv);
            if d <= 0.0 {
                hi = s;
                v_hi = bd.sign * dv;
            } else {
                lo = s;
            }
            let tol = 2.0 * f64::EPSILON * s.abs().max(1.0);
            if hi - lo <= tol {
                break;
            }
            // Halley's step (cubic convergence; q'' comes with the closed form for free), which
            // from the Taylor start usually lands within rounding in one step.
            let den = 2.0 * dv * dv - d * x.dd;
            let newton = if den != 0.0 {
                s - 2.0 * d * dv / den
            } else {
                s - d / dv
            };
            if (newton - s).abs() <= tol {
                if d <= 0.0 {
                    return Crossing {
                        time: s,
                        velocity: bd.sign * dv,
                    };
                }
                // The root lies within rounding to the right: probe just past it.
                s = (s + 2.0 * tol).min(hi);
                continue;
            }
            s = if dv != 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
        }
        Crossing {
            time: hi,
            velocity: v_hi,
        }
    }

    /// Integrate one period, calling `on_segment` for each closed-form piece.
    fn run_period(&self, x0: State, mut on_segment: impl FnMut(&Segment, f64)) -> Result<State> {
        let mut s = 0.0;
        let mut x = x0;
        let mut region = self.region_of(x, s);
        for _ in 0..MAX_CROSSINGS_PER_PERIOD {
            let mut seg = Segment::start(self, region, s, x);
            match self.first_crossing(&seg, self.period) {
                None => {
                    seg.s1 = self.period;
                    let xe = seg.state(self.period);
                    on_segment(&seg, self.period - s);
                    return Ok(xe);
                }
                Some((Crossing { time: sc, velocity }, bd)) => {
                    seg.s1 = sc;
                    on_segment(&seg, sc - s);
                    x = [bd.level, velocity];
                    s = sc;
                    region = bd.beyond;
                }
            }
        }
        Err(GearError::Numerical(format!(
            "more than {MAX_CROSSINGS_PER_PERIOD} boundary crossings in one forcing period (Zeno-like chatter)"
        )))
    }
}

impl PeriodFlow for ExactFlow {
    fn model(&self) -> &GearPair {
        &self.model
    }

    fn method(&self) -> &'static str {
        "exact"
    }

    fn step(&self, x: State, observer: Option<Observer<'_>>) -> Result<State> {
        match observer {
            Some(obs) => self.run_period(x, |seg, _| obs(seg)),
            None => self.run_period(x, |_, _| {}),
        }
    }

    fn step_tangent(&self, x: State, phi: &mut Matrix2<f64>) -> Result<State> {
        self.run_period(x, |seg, tau| *phi = seg.transition(tau) * *phi)
    }

    fn period(&self) -> f64 {
        self.period
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With F_m large and a small STE the teeth never separate: the steady state is the linear
    /// response of eq. 13, q = 1 + F_m + q_a sin(Omega t + phi).
    #[test]
    fn linear_regime_matches_eq13() {
        let (fm, fah, zeta, om) = (5.0, 0.05, 0.05, 0.8);
        let flow = ExactFlow::new(&GearPair::paper(fm, fah, zeta, om).unwrap()).unwrap();
        let mut x = [1.0 + fm, 0.0];
        for _ in 0..400 {
            x = flow.step(x, None).unwrap();
        }
        let qa = fah * om * om / ((1.0 - om * om).powi(2) + (2.0 * zeta * om).powi(2)).sqrt();
        let phase = -(2.0 * zeta * om).atan2(1.0 - om * om);
        let q0 = 1.0 + fm + qa * phase.sin();
        let v0 = qa * om * phase.cos();
        assert!((x[0] - q0).abs() < 1e-10, "{} vs {}", x[0], q0);
        assert!((x[1] - v0).abs() < 1e-10, "{} vs {}", x[1], v0);
    }

    /// Free flight through the gap with no forcing has the closed form q = q0 + v0 (1 - e^{-2 zeta t}) / (2 zeta)
    /// and the crossing time of q = -1 follows from it; the solver must hit it to rounding.
    #[test]
    fn gap_crossing_time_is_exact() {
        let zeta = 0.05;
        let model = GearPair {
            zeta,
            mean_force: 0.0,
            omega: 0.1,
            ste: vec![],
            torque: vec![],
            stiffness: vec![],
        };
        let flow = ExactFlow::new(&model).unwrap();
        let (q0, v0) = (0.5, -0.4);
        let seg = Segment::start(&flow, Region::Gap, 0.0, [q0, v0]);
        let (sc, bd) = flow.first_crossing(&seg, flow.period).unwrap();
        let expected = -((1.0 - (-1.0 - q0) * 2.0 * zeta / v0).ln()) / (2.0 * zeta);
        assert!(
            (sc.time - expected).abs() < 1e-12,
            "{} vs {expected}",
            sc.time
        );
        // the velocity handed to the next region is the closed form's at the crossing
        let v = seg.state(sc.time)[1];
        assert_eq!(sc.velocity, v);
        assert_eq!(bd.beyond, Region::BackContact);
    }

    /// A free oscillation about q = 1 + F_m whose first minimum (at t = pi / w_d) lies 1e-9 below
    /// the boundary must be detected even though it is a brief, shallow dip between scan samples;
    /// one whose minimum lies 1e-9 above must not be.
    #[test]
    fn grazing_dip_is_found_and_near_miss_is_not() {
        let zeta = 0.05;
        let model = GearPair {
            zeta,
            mean_force: 1.0,
            omega: 0.3,
            ste: vec![],
            torque: vec![],
            stiffness: vec![],
        };
        let flow = ExactFlow::new(&model).unwrap();
        let wd = (1.0 - zeta * zeta).sqrt();
        let t_min = std::f64::consts::PI / wd;
        for (depth, expect_hit) in [(1e-9, true), (-1e-9, false)] {
            // q = 2 + A e^{-zeta t}(cos + zeta/w_d sin): minimum 2 - A e^{-zeta pi / w_d}.
            let amp = (1.0 + depth) * (zeta * t_min).exp();
            let seg = Segment::start(&flow, Region::Contact, 0.0, [2.0 + amp, 0.0]);
            let hit = flow.first_crossing(&seg, flow.period);
            match (hit, expect_hit) {
                (Some((sc, _)), true) => {
                    assert!((sc.time - t_min).abs() < 1e-3, "{} vs {t_min}", sc.time)
                }
                (None, false) => {}
                (h, _) => panic!("depth {depth}: unexpected {:?}", h.map(|x| x.0.time)),
            }
        }
    }

    /// The tangent map must equal a finite-difference Jacobian of the period map, including
    /// trajectories that cross both boundaries.
    #[test]
    fn tangent_matches_finite_differences() {
        let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        let flow = ExactFlow::new(&model).unwrap();
        for x in [[0.3, 0.9], [1.5, -0.2], [-1.4, 1.1]] {
            let mut phi = Matrix2::identity();
            let y = flow.step_tangent(x, &mut phi).unwrap();
            let y2 = flow.step(x, None).unwrap();
            assert_eq!(y, y2);
            let h = 1e-7;
            for j in 0..2 {
                let mut xp = x;
                let mut xm = x;
                xp[j] += h;
                xm[j] -= h;
                let yp = flow.step(xp, None).unwrap();
                let ym = flow.step(xm, None).unwrap();
                for i in 0..2 {
                    let fd = (yp[i] - ym[i]) / (2.0 * h);
                    assert!(
                        (fd - phi[(i, j)]).abs() < 1e-5 * (1.0 + fd.abs()),
                        "d{i}/d{j}: fd {fd} vs {}",
                        phi[(i, j)]
                    );
                }
            }
            // Liouville: det = exp(-2 zeta T).
            let det = phi.determinant();
            let expected = (-2.0 * model.zeta * flow.period()).exp();
            assert!((det - expected).abs() < 1e-10 * expected.max(1e-300) + 1e-14);
        }
    }
}
