//! The period map of eq. 3a integrated by DOP853 with region switching (design.md section 6).
//!
//! Inside each region of eq. 3c (contact, gap, back contact) the right-hand side is smooth:
//! q' = v, v' = F(s) - 2 zeta v - k(s) (kappa q - c) with the region's kappa and c. The integrator
//! works on that smooth extension, so its stages may look slightly past q = +-1 without seeing
//! the kink; the crossing is an event located on the 7th-order dense output, the step is cut
//! there, and integration restarts on the far side with the next region's right-hand side. No
//! step straddles a kink, so the method keeps its order. This covers any model, including a
//! time-varying mesh stiffness k(t), which the exact solver does not.
//!
//! The tangent map integrates the variational equation d/ds Phi = J(s) Phi,
//! J = [[0, 1], [-k(s) f'(q), -2 zeta]], f' = kappa of the region, along the trajectory. f is
//! continuous, so the vector field is continuous at the switching surfaces and Phi needs no
//! saltation matrix there (design.md section 6).

use super::excitation_table::ExcitationTable;
use super::flow::{Observer, PeriodFlow, Piece, State};
use super::rk::{
    Crossing, DenseStep, Dop853, Dop853Options, EventFunction, LevelCrossing, OdeSystem,
};
use crate::error::{GearError, Result};
use crate::model::{GearPair, Region};
use nalgebra::Matrix2;
use std::sync::atomic::{AtomicU64, Ordering};

/// Absolute tolerance as a multiple of rtol. q and q' are O(1) (q in units of the half
/// backlash), so atol = rtol / 100 makes the relative tolerance govern everywhere except near
/// zero crossings of q' (turning points), where it keeps the error bounded by 1e-2 rtol.
pub const ATOL_PER_RTOL: f64 = 1e-2;
/// Largest step in dimensionless time: below a quarter of the free period 2 pi / sqrt(k) for
/// k <= 2, so q has at most one extremum per step, which the event scan relies on.
const H_MAX: f64 = 1.0;
/// Maximum number of boundary crossings accepted within one forcing period (a Zeno guard).
const MAX_CROSSINGS_PER_PERIOD: usize = 100_000;

/// A switching surface q = level of a region and the region beyond it.
#[derive(Clone, Copy, Debug)]
struct Boundary {
    event: LevelCrossing,
    beyond: Region,
}

impl Boundary {
    const fn new(level: f64, crossing: Crossing, beyond: Region) -> Self {
        Boundary {
            event: LevelCrossing {
                component: 0,
                level,
                crossing,
            },
            beyond,
        }
    }

    /// The surfaces that end a stay in `region` (q - 1 falling out of contact, and so on).
    fn of(region: Region) -> &'static [Boundary] {
        const CONTACT: [Boundary; 1] = [Boundary::new(1.0, Crossing::Falling, Region::Gap)];
        const BACK: [Boundary; 1] = [Boundary::new(-1.0, Crossing::Rising, Region::Gap)];
        const GAP: [Boundary; 2] = [
            Boundary::new(1.0, Crossing::Rising, Region::Contact),
            Boundary::new(-1.0, Crossing::Falling, Region::BackContact),
        ];
        match region {
            Region::Contact => &CONTACT,
            Region::BackContact => &BACK,
            Region::Gap => &GAP,
        }
    }
}

/// Right-hand side of eq. 3a in one region (its smooth extension beyond the boundaries), for
/// the state (N = 2) or the state with the variational equation (N = 6: q, q', then Phi by
/// columns).
struct RegionRhs<'a> {
    table: &'a ExcitationTable,
    zeta: f64,
    kappa: f64,
    offset: f64,
}

impl<'a> RegionRhs<'a> {
    fn new(table: &'a ExcitationTable, zeta: f64, region: Region) -> Self {
        RegionRhs {
            table,
            zeta,
            kappa: region.kappa(),
            offset: region.force_offset(),
        }
    }

    /// Mesh stiffness k(s) and acceleration q'' at (s, q, v).
    #[inline]
    fn accel(&self, s: f64, q: f64, v: f64) -> (f64, f64) {
        let (f, k) = self.table.at(s);
        let a = f - 2.0 * self.zeta * v - k * (self.kappa * q - self.offset);
        (k, a)
    }
}

impl OdeSystem<2> for RegionRhs<'_> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], self.accel(s, y[0], y[1]).1]
    }
}

impl OdeSystem<6> for RegionRhs<'_> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 6]) -> [f64; 6] {
        let (k, a) = self.accel(s, y[0], y[1]);
        let stiff = k * self.kappa;
        let damp = 2.0 * self.zeta;
        [
            y[1],
            a,
            y[3],
            -stiff * y[2] - damp * y[3],
            y[5],
            -stiff * y[4] - damp * y[5],
        ]
    }
}

impl Piece for DenseStep<2> {
    fn span(&self) -> (f64, f64) {
        DenseStep::span(self)
    }
    fn eval(&self, s: f64) -> State {
        DenseStep::eval(self, s)
    }
}

/// The period map of eq. 3a by DOP853 with event location and region switching: any
/// [`GearPair`], including a time-varying mesh stiffness.
#[derive(Debug)]
pub struct RkFlow {
    model: GearPair,
    table: ExcitationTable,
    rtol: f64,
    period: f64,
    h_max: f64,
    rhs_evaluations: AtomicU64,
}

impl Clone for RkFlow {
    fn clone(&self) -> Self {
        RkFlow {
            model: self.model.clone(),
            table: self.table.clone(),
            rtol: self.rtol,
            period: self.period,
            h_max: self.h_max,
            rhs_evaluations: AtomicU64::new(self.rhs_evaluations()),
        }
    }
}

impl RkFlow {
    /// A DOP853 period map with relative tolerance `rtol` in [1e-14, 1e-3] and absolute
    /// tolerance `rtol * ATOL_PER_RTOL` on q and q'. Fails on an invalid model or tolerance.
    pub fn new(model: &GearPair, rtol: f64) -> Result<Self> {
        let model = model.clone().validated()?;
        if !(rtol.is_finite() && (1e-14..=1e-3).contains(&rtol)) {
            return Err(GearError::param(
                "rtol",
                rtol,
                "relative tolerance of the Runge-Kutta flow must be in [1e-14, 1e-3]",
            ));
        }
        let period = model.period();
        let n = model.max_order().max(1) as f64;
        Ok(RkFlow {
            rtol,
            period,
            // Also a quarter of the fastest excitation period, for the same reason as H_MAX.
            h_max: H_MAX.min(period / (4.0 * n)),
            rhs_evaluations: AtomicU64::new(0),
            table: ExcitationTable::new(&model),
            model,
        })
    }

    /// Relative tolerance of the integrator.
    pub fn rtol(&self) -> f64 {
        self.rtol
    }

    /// Right-hand-side evaluations (of the 2- or 6-dimensional system) since construction or
    /// the last reset, over all threads (for benchmarks).
    pub fn rhs_evaluations(&self) -> u64 {
        self.rhs_evaluations.load(Ordering::Relaxed)
    }

    /// Reset the right-hand-side evaluation counter to zero.
    pub fn reset_rhs_evaluations(&self) {
        self.rhs_evaluations.store(0, Ordering::Relaxed);
    }

    fn options<const N: usize>(&self) -> Dop853Options<N> {
        let mut opts = Dop853Options::new(self.rtol, self.rtol * ATOL_PER_RTOL);
        // Only q and q' steer the steps: the variational components follow the same steps, so
        // the state of `step_tangent` is bitwise that of `step`.
        for a in opts.atol.iter_mut().skip(2) {
            *a = f64::INFINITY;
        }
        opts.h_max = self.h_max;
        opts
    }

    /// Integrate one period from `x0` (q, q', and for N = 6 the columns of Phi), switching
    /// region at each crossing of q = +-1.
    fn run_period<const N: usize>(
        &self,
        x0: [f64; N],
        mut observer: Option<&mut dyn FnMut(&DenseStep<N>)>,
    ) -> Result<[f64; N]>
    where
        for<'a> RegionRhs<'a>: OdeSystem<N>,
    {
        let mut solver = Dop853::new(self.options::<N>())?;
        let (q, v) = (x0[0], x0[1]);
        let mut region = Region::of_state(q, v, self.model.acceleration(0.0, q, v));
        let mut s = 0.0;
        let mut x = x0;
        let result = (|| {
            for _ in 0..MAX_CROSSINGS_PER_PERIOD {
                let rhs = RegionRhs::new(&self.table, self.model.zeta, region);
                let bounds = Boundary::of(region);
                let events: smallvec::SmallVec<[&dyn EventFunction<N>; 2]> = bounds
                    .iter()
                    .map(|b| &b.event as &dyn EventFunction<N>)
                    .collect();
                let obs = observer
                    .as_mut()
                    .map(|o| &mut **o as &mut dyn FnMut(&DenseStep<N>));
                let out = solver.integrate(&rhs, s, x, self.period, &events, obs)?;
                match out.event {
                    None => return Ok(out.y),
                    Some(i) => {
                        let bd = bounds[i];
                        x = out.y;
                        // Continue exactly on the surface, in the region beyond it.
                        x[0] = bd.event.level;
                        s = out.t;
                        region = bd.beyond;
                    }
                }
            }
            Err(GearError::Numerical(format!(
                "more than {MAX_CROSSINGS_PER_PERIOD} boundary crossings in one forcing period (Zeno-like chatter)"
            )))
        })();
        self.rhs_evaluations
            .fetch_add(solver.stats().rhs_evaluations, Ordering::Relaxed);
        result
    }
}

impl PeriodFlow for RkFlow {
    fn model(&self) -> &GearPair {
        &self.model
    }

    fn method(&self) -> &'static str {
        "dop853"
    }

    fn step(&self, x: State, observer: Option<Observer<'_>>) -> Result<State> {
        match observer {
            Some(obs) => {
                let mut forward = |d: &DenseStep<2>| obs(d);
                self.run_period(x, Some(&mut forward))
            }
            None => self.run_period(x, None),
        }
    }

    fn step_tangent(&self, x: State, phi: &mut Matrix2<f64>) -> Result<State> {
        let y = self.run_period([x[0], x[1], 1.0, 0.0, 0.0, 1.0], None)?;
        let m = Matrix2::new(y[2], y[4], y[3], y[5]);
        *phi = m * *phi;
        Ok([y[0], y[1]])
    }

    fn period(&self) -> f64 {
        self.period
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Term;
    use crate::sim::ExactFlow;

    /// Observing the pieces changes nothing, the pieces tile [0, T] and are continuous, and no
    /// piece has q on both sides of a boundary (no step straddles a kink).
    #[test]
    fn pieces_tile_the_period_without_straddling() {
        let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        let flow = RkFlow::new(&model, 1e-10).unwrap();
        let mut x = [0.3, 0.9];
        for _ in 0..5 {
            let mut spans: Vec<(f64, f64, State, State)> = Vec::new();
            let mut obs = |p: &dyn Piece| {
                let (a, b) = p.span();
                spans.push((a, b, p.eval(a), p.eval(b)));
                let mid = p.eval(0.5 * (a + b))[0];
                for j in 1..16 {
                    let q = p.eval(a + (b - a) * j as f64 / 16.0)[0];
                    for level in [-1.0, 1.0] {
                        assert!(
                            (q - level).signum() == (mid - level).signum()
                                || (q - level).abs() < 1e-12,
                            "piece [{a}, {b}] straddles q = {level}"
                        );
                    }
                }
            };
            let y = flow.step(x, Some(&mut obs)).unwrap();
            assert_eq!(y, flow.step(x, None).unwrap());
            assert_eq!(spans.first().unwrap().0, 0.0);
            assert_eq!(spans.last().unwrap().1, flow.period());
            for w in spans.windows(2) {
                assert_eq!(w[0].1, w[1].0);
                assert!((w[0].3[0] - w[1].2[0]).abs() < 1e-12);
                assert!((w[0].3[1] - w[1].2[1]).abs() < 1e-12);
            }
            x = y;
        }
    }

    /// The tangent map matches that of the exact solver and a finite-difference Jacobian, and
    /// its state is bitwise that of `step`.
    #[test]
    fn tangent_matches_exact_and_finite_differences() {
        let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        let flow = RkFlow::new(&model, 1e-12).unwrap();
        let exact = ExactFlow::new(&model).unwrap();
        for x in [[0.3, 0.9], [1.5, -0.2], [-1.4, 1.1]] {
            let mut phi = Matrix2::identity();
            let y = flow.step_tangent(x, &mut phi).unwrap();
            assert_eq!(y, flow.step(x, None).unwrap());
            let mut phi_exact = Matrix2::identity();
            exact.step_tangent(x, &mut phi_exact).unwrap();
            let scale = phi_exact.abs().max().max(1.0);
            assert!(
                (phi - phi_exact).abs().max() < 1e-8 * scale,
                "{phi} vs {phi_exact}"
            );
            let h = 1e-6;
            for j in 0..2 {
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (yp, ym) = (flow.step(xp, None).unwrap(), flow.step(xm, None).unwrap());
                for i in 0..2 {
                    let fd = (yp[i] - ym[i]) / (2.0 * h);
                    assert!((fd - phi[(i, j)]).abs() < 1e-5 * (1.0 + fd.abs()));
                }
            }
        }
    }

    /// With k(t) varying the flow still runs, its tangent has Liouville's determinant
    /// exp(-2 zeta T) (the trace of J is -2 zeta whatever k), and it counts its work.
    #[test]
    fn varying_stiffness_runs_and_keeps_liouville() {
        let mut model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        model.stiffness.push(Term::new(1, 0.2));
        let flow = RkFlow::new(&model, 1e-11).unwrap();
        assert_eq!(flow.rhs_evaluations(), 0);
        let mut phi = Matrix2::identity();
        flow.step_tangent([1.2, 0.3], &mut phi).unwrap();
        let expected = (-2.0 * model.zeta * flow.period()).exp();
        assert!((phi.determinant() - expected).abs() < 1e-9 * expected);
        assert!(flow.rhs_evaluations() > 100);
        flow.reset_rhs_evaluations();
        assert_eq!(flow.rhs_evaluations(), 0);
    }

    /// A free oscillation about q = 2 whose first minimum dips 1e-7 below the contact boundary
    /// (a brief, shallow excursion into the gap) is switched into the gap region, and one that
    /// stays 1e-7 above is not; both agree with the exact solver.
    #[test]
    fn shallow_dip_into_gap_is_switched() {
        let zeta = 0.05;
        let model = GearPair {
            zeta,
            mean_force: 1.0,
            omega: 0.3,
            ste: vec![],
            torque: vec![],
            stiffness: vec![],
        };
        let flow = RkFlow::new(&model, 1e-12).unwrap();
        let exact = ExactFlow::new(&model).unwrap();
        let wd = (1.0 - zeta * zeta).sqrt();
        for (depth, expect_gap) in [(1e-7, true), (-1e-7, false)] {
            // q = 2 + A e^{-zeta t}(cos + zeta/w_d sin): first minimum 2 - A e^{-zeta pi / w_d}.
            let amp = (1.0 + depth) * (zeta * std::f64::consts::PI / wd).exp();
            let x0 = [2.0 + amp, 0.0];
            let mut gap_pieces = 0;
            let mut obs = |p: &dyn Piece| {
                let (a, b) = p.span();
                if p.eval(0.5 * (a + b))[0] < 1.0 {
                    gap_pieces += 1;
                }
            };
            let y = flow.step(x0, Some(&mut obs)).unwrap();
            assert_eq!(gap_pieces > 0, expect_gap, "depth {depth}");
            let ye = exact.step(x0, None).unwrap();
            assert!((y[0] - ye[0]).abs() < 1e-9 && (y[1] - ye[1]).abs() < 1e-9);
        }
    }

    #[test]
    fn rejects_bad_tolerance() {
        let model = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        assert!(RkFlow::new(&model, 0.0).is_err());
        assert!(RkFlow::new(&model, f64::NAN).is_err());
        assert!(RkFlow::new(&model, 0.5).is_err());
        assert!(RkFlow::new(&model, 1e-9).is_ok());
    }
}
