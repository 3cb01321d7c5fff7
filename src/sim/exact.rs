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
//! The scan runs on a grid s0 + k h from each segment start, where the closed form needs no exp or
//! sin/cos: e^{-zeta k h}, sin/cos(w_d k h) and the forcing rotation by Omega k h are tabulated
//! once per flow. Transcendental functions are evaluated only to locate a crossing (usually one
//! evaluation: a Halley step from the root of a quintic Hermite interpolant of the cell's end
//! samples lands on the root to rounding, and the state there is its Taylor extrapolation) and at
//! the end of the period.
//!
//! The tangent dynamics are products of the region matrices e^{A tau}: f is continuous, so the
//! vector field is continuous at q = +-1 and there is no saltation term.

use super::exact_bounds::{
    excluded, hermite_root, safe_horizon, within_rounding, Boundary, Crossing, Sample,
};
use super::flow::{Observer, PeriodFlow, Piece, State};
use crate::error::{GearError, Result};
use crate::fast_math::{exp_small, sin_cos, sin_cos_small, EXP_SMALL_LIMIT};
use crate::model::{GearPair, Region};
use nalgebra::Matrix2;

/// Maximum number of boundary crossings accepted within one forcing period (a Zeno guard).
const MAX_CROSSINGS_PER_PERIOD: usize = 100_000;
/// A Halley step this small (in time) from the Hermite start is taken as converged: the
/// error after it is about |d'''/d'| step^3 / 6, under 1e-15 for the model's derivatives.
const CONVERGED_STEP: f64 = 1e-5;
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
    /// sum_n sqrt(a_n^2 + b_n^2): bound on |q_p| of the harmonic part.
    harmonic_amplitude: f64,
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
        let mut amplitude = 0.0;
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
            amplitude += (a * a + b * b).sqrt();
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
            harmonic_amplitude: amplitude,
            harmonic_accel_bound: bound,
            harmonic_jerk_bound: jerk,
        }
    }

    /// Harmonic part of the particular solution and its first two derivatives at local time s,
    /// given (sin, cos) of the fundamental phase Omega s.
    #[inline]
    fn harmonic_at_phase(&self, omega: f64, s1: f64, c1: f64) -> [f64; 3] {
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
    /// (sin, cos) of the forcing phase Omega s0, which the scan grid rotates (see [`GridPoint`]).
    phase: (f64, f64),
    /// Bounds of |y''| and |y'''| of the homogeneous part at tau = 0 (they scale with its decay).
    hom_bounds: (f64, f64),
    /// Rounding level of the distance to a boundary: a few ulp of the largest term summed in
    /// the closed form (in the gap the ramp and e^{-2 zeta tau} terms grow like 1/zeta and cancel).
    noise: f64,
}

impl<'a> Segment<'a> {
    #[cfg(test)]
    fn start(flow: &'a ExactFlow, region: Region, s0: f64, x: State) -> Self {
        Self::start_at_phase(flow, region, s0, x, sin_cos(flow.omega * s0))
    }

    /// The segment of `region` through state x at time s0, given (sin, cos) of Omega s0 (known
    /// from the crossing that starts it, so not evaluated again).
    fn start_at_phase(
        flow: &'a ExactFlow,
        region: Region,
        s0: f64,
        x: State,
        phase: (f64, f64),
    ) -> Self {
        let law = flow.law(region);
        let [hq, hv, ha] = law.harmonic_at_phase(flow.omega, phase.0, phase.1);
        let y0 = x[0] - hq - law.constant;
        let yv0 = x[1] - hv - law.slope;
        let zeta = flow.zeta;
        // The homogeneous part at tau = 0, the same arithmetic as `full` with e^0 = 1, sin 0 = 0.
        let (hom, yq, yv, ya, hom_bounds, hom_size) = match region {
            Region::Gap => {
                let e = -yv0 * flow.half_inv_zeta;
                let d = y0 - e;
                let yv = -2.0 * zeta * e;
                // The gap mode has lambda = -2 zeta: |y''| = (2 zeta)^2 |e| decay, |y'''| one more.
                let c = 2.0 * zeta * e.abs();
                (
                    Homogeneous::Decaying { d, e },
                    d + e,
                    yv,
                    -2.0 * zeta * yv,
                    (2.0 * zeta * c, 4.0 * zeta * zeta * c),
                    d.abs() + e.abs() + law.slope.abs() * flow.period,
                )
            }
            _ => {
                let (a, b) = (y0, (yv0 + zeta * y0) * flow.inv_wd);
                let yv = flow.wd * b - zeta * a;
                // |lambda| = 1 for the contact modes: every derivative is bounded by the amplitude.
                let c = (a * a + b * b).sqrt();
                (
                    Homogeneous::Oscillating { a, b },
                    a,
                    yv,
                    -2.0 * zeta * yv - a,
                    (c, c),
                    c,
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
            phase,
            hom_bounds,
            noise: 8.0 * f64::EPSILON * (hom_size + law.constant.abs() + law.harmonic_amplitude),
        }
    }

    /// Whether its derivative bounds and rounding level are finite: with an infinite bound the
    /// crossing search can exclude nothing and would bisect every cell to the bottom (2^60
    /// halves), so an overflowing segment is an error, not a hang.
    fn bounded(&self) -> bool {
        let (m2, m3) = self.bounds_from_decay(1.0);
        m2.is_finite() && m3.is_finite() && self.noise.is_finite()
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

    /// [`Self::full`] and (sin, cos) of the forcing phase Omega s.
    #[inline]
    fn full_with_phase(&self, s: f64) -> ([f64; 3], (f64, f64)) {
        let (x, _, phase) = self.evaluate(s);
        (x, phase)
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
    #[inline(always)]
    fn full_with_decay(&self, s: f64) -> ([f64; 3], f64) {
        let (x, decay, _) = self.evaluate(s);
        (x, decay)
    }

    /// q, q', q'' at s, the homogeneous decay factor there and (sin, cos) of Omega s.
    ///
    /// Relative to the grid point s0 + k h just below s the closed form needs only the
    /// tabulated factors times those of the remainder delta = s - s0 - k h < h, whose arguments
    /// need no range reduction (|w_d delta|, |Omega delta| < pi/4) and whose decay e^{-zeta
    /// delta} is a short series: about half the cost of exp and two general sin/cos.
    #[inline(always)]
    fn evaluate(&self, s: f64) -> ([f64; 3], f64, (f64, f64)) {
        let flow = self.flow;
        let tau = s - self.s0;
        // Truncation is the floor here (tau >= 0; a negative tau from rounding gives k = 0).
        let k = (tau * flow.inv_scan_step) as u32;
        let grid = match flow.grid.get(k as usize) {
            Some(g) if flow.short_decay => g,
            _ => return self.evaluate_direct(s),
        };
        let delta = tau - f64::from(k) * flow.scan_step;
        let phase = rotate(
            rotate(self.phase, grid.forcing),
            sin_cos_small(flow.omega * delta),
        );
        let harmonic = self.law.harmonic_at_phase(flow.omega, phase.0, phase.1);
        let zeta = flow.zeta;
        let (decay, rotation) = match self.hom {
            Homogeneous::Oscillating { .. } => (
                grid.decay * exp_small(-zeta * delta),
                rotate(grid.rotation, sin_cos_small(flow.wd * delta)),
            ),
            Homogeneous::Decaying { .. } => {
                (grid.gap_decay * exp_small(-2.0 * zeta * delta), (0.0, 1.0))
            }
        };
        (self.combine(tau, harmonic, decay, rotation), decay, phase)
    }

    /// [`Self::evaluate`] from exp and sin/cos of the full arguments (beyond the table, or
    /// when zeta h is too large for the short decay series).
    #[cold]
    fn evaluate_direct(&self, s: f64) -> ([f64; 3], f64, (f64, f64)) {
        let tau = s - self.s0;
        let phase = sin_cos(self.flow.omega * s);
        let harmonic = self
            .law
            .harmonic_at_phase(self.flow.omega, phase.0, phase.1);
        let zeta = self.flow.zeta;
        let (decay, rotation) = match self.hom {
            Homogeneous::Oscillating { .. } => ((-zeta * tau).exp(), sin_cos(self.flow.wd * tau)),
            Homogeneous::Decaying { .. } => ((-2.0 * zeta * tau).exp(), (0.0, 1.0)),
        };
        (self.combine(tau, harmonic, decay, rotation), decay, phase)
    }

    /// q, q', q'' at the k-th scan grid point s0 + k h (the time, the values and the decay
    /// factor): the closed form with the flow's tabulated e^{-zeta k h}, sin/cos(w_d k h) and the
    /// forcing phase rotated by Omega k h, so no exp or sin/cos is evaluated.
    #[inline(always)]
    fn at_grid(&self, k: u32) -> (f64, [f64; 3], f64) {
        let tau = f64::from(k) * self.flow.scan_step;
        let s = self.s0 + tau;
        let Some(g) = self.flow.grid.get(k as usize) else {
            // Beyond the table (very long periods): the direct closed form.
            let (x, decay) = self.full_with_decay(s);
            return (s, x, decay);
        };
        let (sp, cp) = rotate(self.phase, g.forcing);
        let harmonic = self.law.harmonic_at_phase(self.flow.omega, sp, cp);
        let (decay, rotation) = match self.hom {
            Homogeneous::Oscillating { .. } => (g.decay, g.rotation),
            Homogeneous::Decaying { .. } => (g.gap_decay, (0.0, 1.0)),
        };
        (s, self.combine(tau, harmonic, decay, rotation), decay)
    }

    /// The closed form from its parts: the harmonic part [q, q', q''] at s0 + tau, the
    /// homogeneous decay factor and, in contact, (sin, cos) of w_d tau.
    #[inline]
    fn combine(
        &self,
        tau: f64,
        [hq, hv, ha]: [f64; 3],
        decay: f64,
        (sn, cs): (f64, f64),
    ) -> [f64; 3] {
        let zeta = self.flow.zeta;
        let (yq, yv, ya) = match self.hom {
            Homogeneous::Oscillating { a, b } => {
                let wd = self.flow.wd;
                let yq = decay * (a * cs + b * sn);
                let yv = decay * ((wd * b - zeta * a) * cs - (zeta * b + wd * a) * sn);
                (yq, yv, -2.0 * zeta * yv - yq)
            }
            Homogeneous::Decaying { d, e } => {
                let yv = -2.0 * zeta * e * decay;
                (d + e * decay, yv, -2.0 * zeta * yv)
            }
        };
        [
            hq + yq + self.law.constant + self.law.slope * tau,
            hv + yv + self.law.slope,
            ha + ya,
        ]
    }

    /// Upper bounds of the second and third derivatives of q on [s_from, s1], given the
    /// homogeneous decay factor at s_from (the homogeneous part only decays after it).
    #[inline]
    fn bounds_from_decay(&self, decay: f64) -> (f64, f64) {
        // A relative margin absorbs rounding in the bounds themselves.
        let margin = 1.0 + 1e-12;
        (
            (self.law.harmonic_accel_bound + self.hom_bounds.0 * decay) * margin + 1e-300,
            (self.law.harmonic_jerk_bound + self.hom_bounds.1 * decay) * margin + 1e-300,
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
                // expm1: 1 - g cancels when zeta tau is small (light damping, short gaps).
                let gm1 = (-2.0 * zeta * tau).exp_m1();
                Matrix2::new(1.0, -gm1 / (2.0 * zeta), 0.0, 1.0 + gm1)
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

/// Tabulated factors of the closed form at the scan grid point tau = k h of every segment.
#[derive(Clone, Copy, Debug)]
struct GridPoint {
    /// (sin, cos) of Omega k h, which rotates a segment's start phase to the grid point.
    forcing: (f64, f64),
    /// (sin, cos) of w_d k h.
    rotation: (f64, f64),
    /// e^{-zeta k h}, the contact-mode decay.
    decay: f64,
    /// e^{-2 zeta k h}, the gap-mode decay.
    gap_decay: f64,
}

/// (sin, cos) of the sum of the angles given by (sin, cos) pairs.
#[inline(always)]
fn rotate((s1, c1): (f64, f64), (s2, c2): (f64, f64)) -> (f64, f64) {
    (s1 * c2 + c1 * s2, c1 * c2 - s1 * s2)
}

/// Largest number of tabulated grid points (the scan falls back to the direct closed form beyond;
/// only forcing periods over ~400 time units, Omega < 0.016, need more).
const MAX_GRID_POINTS: usize = 1024;

/// Outcome of scanning a segment up to the end of the period.
enum Scan {
    /// The earliest boundary crossing and the boundary crossed.
    Crossed(Crossing, Boundary),
    /// No crossing: q, q', q'' at the end time.
    Reached([f64; 3]),
}

/// The exact piecewise-linear period map of eq. 3a for k(t) = 1 (the paper's model, with any
/// number of STE and external torque harmonics).
#[derive(Clone, Debug)]
pub struct ExactFlow {
    model: GearPair,
    omega: f64,
    zeta: f64,
    wd: f64,
    /// 1 / w_d and 1 / (2 zeta), so that segment starts multiply instead of divide.
    inv_wd: f64,
    half_inv_zeta: f64,
    period: f64,
    scan_step: f64,
    inv_scan_step: f64,
    /// 2 zeta h is within [`EXP_SMALL_LIMIT`], so the decay over a part of a grid cell is a
    /// short series (see [`Segment::evaluate`]).
    short_decay: bool,
    /// Closed-form factors at tau = k scan_step, k = 0, 1, ... (one period's worth).
    grid: Vec<GridPoint>,
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
        let (omega, zeta) = (model.omega, model.zeta);
        let wd = (1.0 - zeta * zeta).sqrt();
        let points = (pieces as usize + 1).min(MAX_GRID_POINTS);
        let grid = (0..points)
            .map(|k| {
                let tau = k as f64 * scan_step;
                GridPoint {
                    forcing: sin_cos(omega * tau),
                    rotation: sin_cos(wd * tau),
                    decay: (-zeta * tau).exp(),
                    gap_decay: (-2.0 * zeta * tau).exp(),
                }
            })
            .collect();
        Ok(ExactFlow {
            omega,
            zeta,
            wd,
            inv_wd: 1.0 / wd,
            half_inv_zeta: 0.5 / zeta,
            period,
            scan_step,
            inv_scan_step: 1.0 / scan_step,
            short_decay: 2.0 * zeta * scan_step <= EXP_SMALL_LIMIT,
            grid,
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
        // The acceleration decides only on a boundary at rest.
        let a = if x[1] == 0.0 && x[0].abs() == 1.0 {
            self.model.acceleration(s, x[0], x[1])
        } else {
            0.0
        };
        Region::of_state(x[0], x[1], a)
    }

    /// Earliest crossing of a boundary of `seg` in (s0, s_end], if any.
    #[cfg(test)]
    fn first_crossing(&self, seg: &Segment, s_end: f64) -> Option<(Crossing, Boundary)> {
        match self.scan(seg, s_end) {
            Scan::Crossed(c, bd) => Some((c, bd)),
            Scan::Reached(_) => None,
        }
    }

    /// Scan `seg` for its earliest boundary crossing in (s0, s_end].
    ///
    /// The scan visits the grid points s0 + k h, where the closed form is tabulated (no exp or
    /// sin/cos). From each it skips the whole cells inside the horizon over which the quadratic
    /// lower bound d + d' tau - M2 tau^2 / 2 provably stays positive; a cell it cannot skip is
    /// searched rigorously by [`Self::search`] from the samples at its two ends.
    fn scan(&self, seg: &Segment, s_end: f64) -> Scan {
        let bounds = Boundary::of(seg.law.region);
        let h = self.scan_step;
        let mut k = 0u32;
        let (mut a, mut xa, mut m) = (seg.s0, seg.at_start, seg.bounds_from_decay(1.0));
        loop {
            // The bound is positive strictly inside the horizon; the factor keeps rounding clear.
            let horizon = 0.999 * safe_horizon(bounds, xa, m.0);
            if a + horizon >= s_end {
                return Scan::Reached(seg.full(s_end));
            }
            // Whole cells inside the horizon (saturating; any count beyond s_end was caught above).
            let skip = (horizon * self.inv_scan_step) as u32;
            if skip > 0 {
                k = k.saturating_add(skip);
                let (s, x, decay) = seg.at_grid(k);
                (a, xa, m) = (s, x, seg.bounds_from_decay(decay));
                continue;
            }
            let last = seg.s0 + f64::from(k + 1) * h >= s_end;
            let (b, xb, decay) = if last {
                let (x, decay) = seg.full_with_decay(s_end);
                (s_end, x, decay)
            } else {
                seg.at_grid(k + 1)
            };
            let mb = seg.bounds_from_decay(decay);
            let mut best: Option<(Crossing, Boundary)> = None;
            for bd in bounds {
                let mut sa = bd.sample(a, xa);
                if k == 0 {
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
            if let Some((c, bd)) = best {
                return Scan::Crossed(c, bd);
            }
            if last {
                return Scan::Reached(xb);
            }
            k += 1;
            (a, xa, m) = (b, xb, mb);
        }
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
        // d' <= min(d'(a) + M2 t, d'(b) + M2 (w - t)) <= (d'(a) + d'(b) + M2 w) / 2 on [a, b].
        if b.d < 0.0 && a.dv + b.dv + m.0 * w < 0.0 {
            // d decreases throughout: exactly one root, found by safeguarded Halley.
            return Some(self.refine_root(seg, bd, a, b));
        }
        if depth >= MAX_DEPTH || within_rounding(a, w, m.0, seg.noise) {
            // Not excludable but no sign change at this resolution: a tangency (grazing touch)
            // whose penetration is below rounding (at MAX_DEPTH, below M2 w^2 / 8).
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
    /// started from the root of the quintic Hermite interpolant of the two samples (on a scan
    /// cell within ~1e-7 of the root, so one Halley step reaches rounding and the evaluation
    /// there confirms it). The returned time is where the last Halley step fell below rounding,
    /// with q' from the closed form there.
    fn refine_root(&self, seg: &Segment, bd: &Boundary, a: Sample, b: Sample) -> Crossing {
        let (mut lo, mut hi) = (a.s, b.s);
        // q' at hi, for the (rare) exit by bracket width.
        let mut v_hi = bd.sign * b.dv;
        let mut s = hermite_root(a, b);
        if !(s > lo && s < hi) {
            s = 0.5 * (lo + hi);
        }
        for _ in 0..200 {
            let (xs, phase) = seg.full_with_phase(s);
            let x = bd.sample(s, xs);
            let (d, dv) = (x.d, x.dv);
            if d <= 0.0 {
                hi = s;
                v_hi = bd.sign * dv;
            } else {
                lo = s;
            }
            // Halley's step (cubic convergence; q'' comes with the closed form for free).
            let den = 2.0 * dv * dv - d * x.dd;
            let step = if den != 0.0 {
                -2.0 * d * dv / den
            } else {
                -d / dv
            };
            // Below rounding of s or of the distance itself, further steps only wander in noise.
            let tol = 2.0 * f64::EPSILON * s.abs().max(1.0);
            if step.abs() <= tol + seg.noise / dv.abs() {
                return Crossing {
                    time: s,
                    velocity: bd.sign * dv,
                    phase,
                };
            }
            if hi - lo <= tol {
                break;
            }
            let next = s + step;
            // Halley converges cubically: from a start this close (the Hermite guess is ~1e-10
            // of the cell off), the step lands on the root to rounding, so the state there is
            // the Taylor extrapolation (error ~ d''' step^2, below 1e-20) and one closed-form
            // evaluation is saved per crossing.
            if step.abs() <= CONVERGED_STEP && next > lo && next < hi {
                let (sn, cs) = (self.omega * step).sin_cos();
                return Crossing {
                    time: next,
                    velocity: bd.sign * (dv + x.dd * step),
                    phase: (phase.0 * cs + phase.1 * sn, phase.1 * cs - phase.0 * sn),
                };
            }
            s = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
        }
        Crossing {
            time: hi,
            velocity: v_hi,
            phase: sin_cos(self.omega * hi),
        }
    }

    /// Integrate one period, calling `on_segment` for each closed-form piece.
    fn run_period(&self, x0: State, mut on_segment: impl FnMut(&Segment, f64)) -> Result<State> {
        let mut s = 0.0;
        let mut x = x0;
        let mut region = self.region_of(x, s);
        let mut phase = (0.0, 1.0);
        for _ in 0..MAX_CROSSINGS_PER_PERIOD {
            let mut seg = Segment::start_at_phase(self, region, s, x, phase);
            if !seg.bounded() {
                return Err(GearError::Numerical(
                    "the exact solution's derivative bounds overflow (state or forcing near f64's limit); the crossing search cannot exclude any interval".into(),
                ));
            }
            match self.scan(&seg, self.period) {
                Scan::Reached([q, v, _]) => {
                    seg.s1 = self.period;
                    on_segment(&seg, self.period - s);
                    return Ok([q, v]);
                }
                Scan::Crossed(c, bd) => {
                    let sc = c.time;
                    seg.s1 = sc;
                    on_segment(&seg, sc - s);
                    x = [bd.level, c.velocity];
                    s = sc;
                    phase = c.phase;
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

    /// A state near f64's limit overflows the closed form's derivative bounds: one period is an
    /// error, not a search that can exclude nothing (it bisected every cell 60 levels deep).
    #[test]
    fn overflowing_state_is_an_error_not_a_hang() {
        let flow = ExactFlow::new(&GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap()).unwrap();
        assert!(flow.step([1.0e300, -1.0e300], None).is_err());
        assert!(flow.step([1.2, 0.0], None).is_ok());
    }

    /// A pair at rest exactly on the drive flank with no load and no forcing stays there: its
    /// distance to the boundary is zero with every derivative, no bound can exclude a root and
    /// the crossing search used to halve every cell 60 levels deep (2^60 cells: a hang).
    #[test]
    fn pair_at_rest_on_a_flank_stays_there() {
        let flow = ExactFlow::new(&GearPair::paper(0.0, 0.0, 0.05, 0.8).unwrap()).unwrap();
        let mut x = [1.0, 0.0];
        for _ in 0..10 {
            x = flow.step(x, None).unwrap();
        }
        assert_eq!(x, [1.0, 0.0]);
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
        // the velocity handed to the next region is the closed form's at the crossing (to
        // rounding: it is extrapolated from the last Halley evaluation, ~1e-10 away)
        let v = seg.state(sc.time)[1];
        assert!(
            (sc.velocity - v).abs() <= 1e-14 * v.abs().max(1.0),
            "{} vs {v}",
            sc.velocity
        );
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
