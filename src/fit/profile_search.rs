//! The root search of every profile-likelihood interval in geardyn: of an engine fit's
//! parameter ([`super::profile_interval`], `validate`) and of a refitted effect's coordinate or
//! phase (`discover`). What differs between them is the inner fit (an [`InnerFit`]) and the
//! budget ([`SearchOptions`]); the search is this one.
//!
//! On one side of the estimate it looks for the distance d at which the signed root deviance
//! r(d) = sqrt(P(d) - P(0)), P the profile (-2 log L minimised over the other parameters),
//! reaches q (Venzon & Moolgavkar 1988; Bates & Watts 1988, Sec. 6.1). r is linear in d where
//! the model is linear in its parameters, so:
//! - it walks out from a first step (a Wald end, or a standard error) by secants of r from the
//!   estimate, each at least 1.25 and at most 4 times as far as the last point inside;
//! - once a point lies outside it may narrow the bracket by halving (always, while the outside
//!   end is a failed fit) until it is at most
//!   [`SearchOptions::bracket_width`] standard errors wide, its outside end fitted from its
//!   inside end (a start a standard error away can end on a ledge of a jumping response above
//!   the threshold, where a start a quarter of one away does not: set-084 of tools/indep-synth
//!   batch 515);
//! - then Brent's method on r - q.
//!
//! Every inner fit starts from the fit of the farthest point found inside the interval that is
//! no farther than its own (the estimate, at first): a start from a point outside may have
//! crossed a step of the sum of squares.
//!
//! Where the inner fits fail beyond some distance (a model that cannot be evaluated there), the
//! halving closes on the last point fitted and the side ends as [`SideEnd::Failed`]: not a
//! ratio end either, and the caller decides.
//!
//! A step that no start avoids is not a confidence bound: it says on which side of one
//! measured speed a jump falls, not how far the parameter may move. The search reports whether
//! its end is such a step (the profile rises by more than q^2 between the last point inside and
//! the first outside, these closer than [`STEP_WIDTH`] standard errors) and the caller decides
//! what to put there.

use crate::error::Result;
use crate::numeric::brent;

/// A profile that rises by more than q^2 within this many standard errors (or four times the
/// root search's tolerance, if wider) has stepped, not risen: where smooth, its slope at the
/// threshold is 2 q per standard error (about 4), so it rises by 0.04 in 0.01, a hundredth of
/// the threshold.
const STEP_WIDTH: f64 = 0.01;
/// The walk out goes at least this factor farther than the last point inside.
const MIN_GROWTH: f64 = 1.25;
/// And at most this factor.
const MAX_GROWTH: f64 = 4.0;
/// A side that stays inside to this many standard errors has no end (2^11, as far as twelve
/// doublings from one standard error reach).
const MAX_REACH_SE: f64 = 2048.0;
/// r - q is capped at this many q before the root search: a point that cannot be fitted is
/// infinite, and the cap keeps Brent's interpolation finite (it bisects there).
const EXCESS_CAP: f64 = 1e3;

/// One inner fit of a profile.
pub struct Fitted<S> {
    /// P(d) - P(0): the profile's rise over the estimate's minimum (negative where the inner
    /// fit found a better minimum than the estimate's), infinite where no fit could be made.
    pub rise: f64,
    /// The fitted other parameters, the start of fits farther out; None where the fit failed.
    pub fitted: Option<S>,
}

/// The inner fit of a profile: -2 log L minimised over everything else with the profiled
/// coordinate held at signed distance `u` from the estimate (internal units), from `start`.
pub trait InnerFit {
    type Start: Clone;
    fn fit_at(&self, u: f64, start: &Self::Start) -> Result<Fitted<Self::Start>>;
}

/// How one side's search runs.
#[derive(Clone, Copy, Debug)]
pub struct SearchOptions {
    /// The first point's distance from the estimate (internal units).
    pub first_step: f64,
    /// The profiled coordinate's standard error, or a stand-in (internal units): the unit of
    /// the bracket's width, the step test and the walk's reach.
    pub se: f64,
    /// The end is where r = q.
    pub q: f64,
    /// The side goes no farther than this distance (an amplitude's zero, a phase's half turn);
    /// a profile still inside there ends at [`SideEnd::Limit`].
    pub limit: Option<f64>,
    /// Inner fits per side at most; with them spent the end is the root search's next
    /// estimate, unfitted, or no end if no point was outside yet.
    pub max_fits: usize,
    /// A point whose r is within this of q is the end (0: the root search's tolerance decides).
    pub accept: f64,
    /// Before Brent's method the bracket is narrowed to at most this many standard errors, its
    /// outside end fitted from its inside end (None: the first bracket found is kept).
    pub bracket_width: Option<f64>,
    /// Brent's tolerance on the end (internal units).
    pub tolerance: f64,
    /// A point below the estimate's minimum by more than this (sigma^2) is a better fit, and
    /// the search hands it back instead of an end (None: it counts as inside).
    pub better_by: Option<f64>,
}

/// How one side ended.
pub enum SideEnd<S> {
    /// r crosses q at this distance from the estimate; `stepped` where the profile steps
    /// there rather than rises (see the module's notes).
    At { distance: f64, stepped: bool },
    /// Inside up to [`SearchOptions::limit`].
    Limit,
    /// Inside as far as the search went: no end on this side.
    Open,
    /// A point that fits better than the estimate, at signed distance `u`.
    Better { u: f64, fitted: S },
    /// The inner fit fails just beyond `distance` (the farthest point fitted inside, within the
    /// root search's tolerance of the failures): the ratio cannot be followed to q there, so
    /// this is no likelihood-ratio end.
    Failed { distance: f64 },
}

/// What an evaluation found: r - q (capped), or a better fit.
enum Step<S> {
    Excess(f64),
    Better(f64, S),
}

/// One side's search state.
struct Side<'a, F: InnerFit> {
    inner: &'a F,
    options: SearchOptions,
    dir: f64,
    /// The fits of the points inside the interval, by distance (the estimate's first).
    inside: Vec<(f64, F::Start)>,
    /// Every point evaluated: distance and rise P(d) - P(0).
    evaluated: Vec<(f64, f64)>,
    fits: usize,
}

/// The end of the profile on side `dir` (-1 or 1) of the estimate, whose own fit is `centre`.
pub fn search_side<F: InnerFit>(
    inner: &F,
    centre: F::Start,
    dir: f64,
    options: SearchOptions,
) -> Result<SideEnd<F::Start>> {
    let mut side = Side {
        inner,
        options,
        dir,
        inside: vec![(0.0, centre)],
        evaluated: Vec::new(),
        fits: 0,
    };
    side.run()
}

impl<F: InnerFit> Side<'_, F> {
    fn cap(&self) -> f64 {
        EXCESS_CAP * self.options.q
    }

    /// The inner fit at distance `d`, from the farthest point inside no farther than `d`.
    fn eval(&mut self, d: f64) -> Result<Step<F::Start>> {
        self.fits += 1;
        let start = self
            .inside
            .iter()
            .filter(|(x, _)| *x <= d)
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, s)| s)
            .unwrap_or(&self.inside[0].1);
        let p = self.inner.fit_at(self.dir * d, start)?;
        if let (Some(by), Some(f)) = (self.options.better_by, &p.fitted) {
            if p.rise < -by {
                return Ok(Step::Better(self.dir * d, f.clone()));
            }
        }
        let excess = (p.rise.max(0.0).sqrt() - self.options.q).min(self.cap());
        // A point fitted again (from a nearer start) keeps only its latest value.
        self.evaluated.retain(|(x, _)| *x != d);
        self.evaluated.push((d, p.rise));
        if let (true, Some(f)) = (excess <= 0.0, p.fitted) {
            self.inside.push((d, f));
        }
        Ok(Step::Excess(excess))
    }

    fn spent(&self) -> bool {
        self.fits >= self.options.max_fits
    }

    fn accepted(&self, excess: f64) -> bool {
        excess.abs() <= self.options.accept
    }

    /// The inner fit at `d`: its r - q, or the side's end where the point fits better than
    /// the estimate or lies within the accepted band.
    fn probe(&mut self, d: f64) -> Result<std::result::Result<f64, SideEnd<F::Start>>> {
        Ok(match self.eval(d)? {
            Step::Better(u, fitted) => Err(SideEnd::Better { u, fitted }),
            Step::Excess(e) if self.accepted(e) => Err(self.end(d)),
            Step::Excess(e) => Ok(e),
        })
    }

    fn run(&mut self) -> Result<SideEnd<F::Start>> {
        let o = self.options;
        // The bracket: a point inside (the estimate, at first), and once found one outside
        // with whether it was fitted from the inside one.
        let mut inner = (0.0, -o.q);
        let mut outer: Option<(f64, f64, bool)> = None;
        let mut d = o.first_step;
        // Each pass fits once: a step of the walk, a halving, or a refit of the outside end.
        while !self.spent() {
            let Some((d_out, e_out, from_inner)) = outer else {
                let next = o.limit.map_or(d, |l| d.min(l));
                let excess = match self.probe(next)? {
                    Ok(e) => e,
                    Err(end) => return Ok(end),
                };
                if excess > 0.0 {
                    outer = Some((next, excess, true));
                } else if o.limit == Some(next) {
                    return Ok(SideEnd::Limit);
                } else if next >= MAX_REACH_SE * o.se {
                    return Ok(SideEnd::Open);
                } else {
                    inner = (next, excess);
                    d = self.walk_from(next, excess);
                }
                continue;
            };
            let width = d_out - inner.0;
            // A failed fit outside gives Brent's interpolation nothing to go on: it is
            // halved towards until the bracket is within the tolerance, and if the fits still
            // fail there, the side ends at a failure, not at r = q.
            if e_out >= self.cap() && width <= o.tolerance {
                return Ok(SideEnd::Failed { distance: inner.0 });
            }
            let failed = e_out >= self.cap();
            let next = match o.bracket_width {
                _ if failed => 0.5 * (inner.0 + d_out),
                Some(w) if width > w * o.se => 0.5 * (inner.0 + d_out),
                Some(_) if !from_inner => d_out,
                _ => break,
            };
            let excess = match self.probe(next)? {
                Ok(e) => e,
                Err(end) => return Ok(end),
            };
            if excess > 0.0 {
                outer = Some((next, excess, true));
            } else if next < d_out {
                inner = (next, excess);
                outer = Some((d_out, e_out, false));
            } else {
                // The outside end, fitted from nearer in, is inside: the walk goes on.
                inner = (next, excess);
                outer = None;
                d = self.walk_from(next, excess);
            }
        }
        match outer {
            Some((d_out, e_out, _)) => self.root(inner, (d_out, e_out)),
            None => Ok(SideEnd::Open),
        }
    }

    /// The walk's next distance from a point inside at `d` with r - q = `excess`: the secant of
    /// r from the estimate through it.
    fn walk_from(&self, d: f64, excess: f64) -> f64 {
        let r = excess + self.options.q;
        let reach = if r > 0.0 {
            d * self.options.q / r
        } else {
            d * MAX_GROWTH
        };
        reach.clamp(d * MIN_GROWTH, d * MAX_GROWTH)
    }

    /// Brent's method on r - q in the bracket (inside, outside); with the fits spent, its next
    /// estimate, unfitted. An error or a better fit inside the search stops it.
    fn root(&mut self, inner: (f64, f64), outer: (f64, f64)) -> Result<SideEnd<F::Start>> {
        let mut stopped: Option<Result<Step<F::Start>>> = None;
        let cap = self.cap();
        let tolerance = self.options.tolerance;
        let root = brent(
            |d| {
                if stopped.is_some() || self.spent() {
                    return 0.0;
                }
                match self.eval(d) {
                    Ok(Step::Excess(e)) if self.accepted(e) => 0.0,
                    Ok(Step::Excess(e)) => e,
                    other => {
                        stopped = Some(other);
                        cap
                    }
                }
            },
            inner.0,
            outer.0,
            inner.1,
            outer.1,
            tolerance,
        );
        match stopped {
            Some(Err(e)) => Err(e),
            Some(Ok(Step::Better(u, fitted))) => Ok(SideEnd::Better { u, fitted }),
            _ => Ok(self.end(root)),
        }
    }

    /// The end at distance `root`, with whether the profile stepped there.
    fn end(&self, root: f64) -> SideEnd<F::Start> {
        let width = (STEP_WIDTH * self.options.se).max(4.0 * self.options.tolerance);
        SideEnd::At {
            distance: root,
            stepped: steps_up(&self.evaluated, width, self.options.q.powi(2)),
        }
    }
}

/// Whether the profile evaluated at `evaluated` (distance from the estimate, rise over the
/// minimum) steps up by more than `rise` (the threshold's height) between the last point
/// inside and the first outside, these closer than `width`: a jump, not a rise.
fn steps_up(evaluated: &[(f64, f64)], width: f64, rise: f64) -> bool {
    // The estimate (distance 0, rise 0) is inside: a profile can step at the estimate itself
    // (a jump on a measured speed there), and no other point inside is evaluated then.
    let estimate = [(0.0, 0.0)];
    let inside = evaluated
        .iter()
        .chain(&estimate)
        .filter(|(_, p)| *p <= rise)
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let outside = evaluated
        .iter()
        .filter(|(_, p)| *p > rise)
        .min_by(|a, b| a.0.total_cmp(&b.0));
    match (inside, outside) {
        (Some(i), Some(o)) => o.0 - i.0 <= width && o.1 - i.1 > rise,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A profile given by its signed root deviance `r(u)` (no fits); points where `better`
    /// holds fit better than the estimate by 1.
    struct Analytic<'a> {
        r: &'a dyn Fn(f64) -> f64,
        better: &'a dyn Fn(f64) -> bool,
    }

    impl InnerFit for Analytic<'_> {
        type Start = Vec<f64>;
        fn fit_at(&self, u: f64, _: &Vec<f64>) -> Result<Fitted<Vec<f64>>> {
            let r = (self.r)(u);
            Ok(Fitted {
                rise: if (self.better)(u) { -1.0 } else { r * r },
                fitted: r.is_finite().then(|| vec![u]),
            })
        }
    }

    /// `discover`'s budget: six fits, an end within 0.05 of q in r, no narrowing.
    fn budgeted(h: f64, limit: Option<f64>) -> SearchOptions {
        SearchOptions {
            first_step: h,
            se: h / 1.96,
            q: 1.96,
            limit,
            max_fits: 6,
            accept: 0.05,
            bracket_width: None,
            tolerance: 1e-3 * h,
            better_by: Some(0.1),
        }
    }

    /// `validate`'s: from one standard error, narrowed to a quarter of one, to 1e-6 of one.
    fn converged(se: f64) -> SearchOptions {
        SearchOptions {
            first_step: se,
            se,
            q: 1.96,
            limit: None,
            max_fits: 80,
            accept: 0.0,
            bracket_width: Some(0.25),
            tolerance: 1e-6 * se,
            better_by: None,
        }
    }

    fn end(r: &dyn Fn(f64) -> f64, dir: f64, options: SearchOptions) -> SideEnd<Vec<f64>> {
        let never = |_: f64| false;
        let f = Analytic { r, better: &never };
        search_side(&f, Vec::new(), dir, options).unwrap()
    }

    fn at(e: SideEnd<Vec<f64>>) -> f64 {
        match e {
            SideEnd::At { distance, .. } => distance,
            _ => f64::NAN,
        }
    }

    #[test]
    fn a_quadratic_profile_ends_at_the_wald_bound_from_any_first_step() {
        // Standard error 0.01: the ends are 1.96 x 0.01 away. The budgeted search stops within
        // 0.05 of q in r, 0.05 x 0.01 in u; the converged one within 1e-6 standard errors.
        let r = |u: f64| u.abs() / 0.01;
        for h in [0.005, 0.0196, 0.05, 0.3] {
            for dir in [-1.0, 1.0] {
                let d = at(end(&r, dir, budgeted(h, None)));
                assert!((d - 0.0196).abs() < 6e-4, "h {h}: {d}");
            }
        }
        let d = at(end(&r, 1.0, converged(0.01)));
        assert!((d - 0.0196).abs() < 1e-8, "{d}");
    }

    #[test]
    fn a_steeper_than_quadratic_profile_gives_a_narrower_side() {
        // r = (d / 0.01)^1.5 crosses 1.96 at d = 0.01 x 1.96^(2/3) = 0.01566.
        let r = |u: f64| (u.abs() / 0.01).powf(1.5);
        assert!((at(end(&r, 1.0, budgeted(0.0196, None))) - 0.01566).abs() < 6e-4);
        let exact = 0.01 * 1.96_f64.powf(2.0 / 3.0);
        assert!((at(end(&r, 1.0, converged(0.01))) - exact).abs() < 1e-8);
    }

    #[test]
    fn a_side_limited_ends_at_its_limit_when_the_profile_stays_low() {
        // An amplitude of 0.2 whose profile stays below q down to zero (limit 0.2 below).
        let r = |u: f64| u.abs() / 0.15;
        assert!(matches!(
            end(&r, -1.0, budgeted(0.1, Some(0.2))),
            SideEnd::Limit
        ));
        // Without the limit the same side crosses at 1.96 x 0.15.
        assert!((at(end(&r, -1.0, budgeted(0.1, None))) - 0.294).abs() < 0.01);
        // A phase side limited at half a turn: crossed before it where the profile rises.
        let r = |u: f64| u.abs() / 0.5;
        let pi = std::f64::consts::PI;
        assert!((at(end(&r, 1.0, budgeted(0.1, Some(pi)))) - 0.98).abs() < 0.03);
        let low = |u: f64| 0.3 * u.abs();
        assert!(matches!(
            end(&low, 1.0, budgeted(0.1, Some(pi))),
            SideEnd::Limit
        ));
    }

    #[test]
    fn a_flat_profile_leaves_the_side_open() {
        let flat = |u: f64| 0.01 * u.abs();
        assert!(matches!(
            end(&flat, 1.0, budgeted(0.01, None)),
            SideEnd::Open
        ));
        // Unbudgeted, it walks out to 2^11 standard errors and stops there.
        assert!(matches!(end(&flat, 1.0, converged(0.01)), SideEnd::Open));
    }

    #[test]
    fn a_side_whose_fits_fail_ends_as_failed_at_the_last_fitted_point() {
        // Fits fail beyond 0.015 (r would reach 1.96 only at 0.0196): the halving closes on
        // the failure and the side ends there as a failure, not as a ratio end.
        let failing = |u: f64| {
            let d = u.abs();
            if d > 0.015 {
                f64::INFINITY
            } else {
                d / 0.01
            }
        };
        match end(&failing, 1.0, converged(0.01)) {
            SideEnd::Failed { distance } => assert!((distance - 0.015).abs() < 1e-6, "{distance}"),
            _ => panic!("expected a failed side"),
        }
        // With its fits spent before the bracket closes, the side takes the root search's
        // estimate between the last point inside and the failure.
        let d = at(end(&failing, 1.0, budgeted(0.0196, None)));
        assert!(d > 0.012 && d < 0.0155, "{d}");
    }

    #[test]
    fn a_point_that_fits_better_than_the_estimate_is_handed_back() {
        let r = |_: f64| 0.0;
        let better = |u: f64| u > 0.005;
        let f = Analytic {
            r: &r,
            better: &better,
        };
        let e = search_side(&f, Vec::new(), 1.0, budgeted(0.01, None)).unwrap();
        assert!(matches!(e, SideEnd::Better { u, fitted } if u == 0.01 && fitted == vec![0.01]));
    }

    #[test]
    fn a_step_is_reported_as_a_step() {
        // A rise of 100 sigma^2 at 0.3 standard errors on a parabola: the end is the step,
        // flagged; on the parabola alone it is not.
        let stepped = |u: f64| {
            let q = u.abs() / 0.01;
            if u.abs() > 0.003 {
                (q * q + 100.0).sqrt()
            } else {
                q
            }
        };
        match end(&stepped, 1.0, converged(0.01)) {
            SideEnd::At { distance, stepped } => {
                assert!(stepped && (distance - 0.003).abs() < 1e-6, "{distance}");
            }
            _ => panic!("no end"),
        }
        let r = |u: f64| u.abs() / 0.01;
        assert!(matches!(
            end(&r, 1.0, converged(0.01)),
            SideEnd::At { stepped: false, .. }
        ));
    }

    #[test]
    fn a_step_at_the_estimate_itself_is_a_step() {
        // The profile is 69 sigma^2 up at any distance on this side (the estimate sits on a
        // jump at a measured speed): no point inside is evaluated, and the end is flagged.
        let ledge = |u: f64| if u == 0.0 { 0.0 } else { 69.0_f64.sqrt() };
        match end(&ledge, 1.0, converged(0.01)) {
            SideEnd::At { distance, stepped } => assert!(stepped && distance < 1e-5, "{distance}"),
            _ => panic!("no end"),
        }
    }
}
