//! Pseudo-arclength continuation of multi-harmonic balance solutions in Omega, through folds, so
//! that both sides of every jump (Sec. 5, Fig. 11-13) and the unstable middle branch between them
//! are traced. Unknowns y = (x, Omega); predictor along the unit tangent t of R(y) = 0, corrector
//! by Newton on [R(y); t . (y - y_pred)] = 0; the step adapts to the corrector's effort and to the
//! turning of the tangent. A fold is a sign change of the Omega-component of the tangent; it is
//! located by regula falsi in the arclength and inserted as a point marked `fold`.

use super::aft::AftOptions;
use super::aft_guess::linear_guess;
use super::aft_point::HbPoint;
use super::aft_solve::Context;
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::progress::Progress;
use nalgebra::{DMatrix, DVector};

/// Step control of the pseudo-arclength continuation. Arclength is measured in the space of
/// (coefficients, Omega).
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationOptions {
    /// First arclength step.
    pub step: f64,
    /// Smallest step before the continuation gives up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Largest number of points on the branch (the continuation fails beyond it).
    pub max_points: usize,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            step: 0.01,
            min_step: 1e-7,
            max_step: 0.04,
            max_points: 5000,
        }
    }
}

/// Corrector iterations before a step is rejected.
const MAX_CORRECTOR: usize = 8;
/// Consecutive tangents must agree to this cosine (about 8 degrees), or the step is halved.
const MIN_TANGENT_COS: f64 = 0.99;
/// Regula falsi iterations locating a fold.
const FOLD_ITERATIONS: usize = 40;
/// Bisections locating a period doubling (the step shrinks by 2^-30).
const PD_BISECTIONS: usize = 30;

/// Trace the branch of multi-harmonic balance solutions of eq. 3a (generalised) from
/// `omega_start` to `omega_end` by pseudo-arclength continuation, starting from the linear
/// (no-impact, eq. 13) solution at `omega_start`, which is exact when the teeth stay in contact
/// there. Folds are passed and marked; every point carries its Floquet stability when
/// `opts.stability` is set. The branch ends with a point at `omega_end` (or where it turns back
/// beyond `omega_start`).
pub fn continue_branch(
    model: &GearPair,
    omega_start: f64,
    omega_end: f64,
    opts: &AftOptions,
    cont: &ContinuationOptions,
    progress: &dyn Progress,
) -> Result<Vec<HbPoint>> {
    check_omega("omega_start", omega_start)?;
    let m0 = model.at_omega(omega_start)?;
    let guess = linear_guess(&m0, opts)?;
    let start = super::solve_at(&m0, &guess, opts)?;
    continue_from(model, &start, omega_end, opts, cont, progress)
}

/// Pseudo-arclength continuation from a solved point `start` (e.g. from [`super::solve_at`] with
/// a guess from a simulation steady state, as for a subharmonic branch) towards `omega_end`.
/// `start` must have been computed with the same options.
pub fn continue_from(
    model: &GearPair,
    start: &HbPoint,
    omega_end: f64,
    opts: &AftOptions,
    cont: &ContinuationOptions,
    progress: &dyn Progress,
) -> Result<Vec<HbPoint>> {
    check_omega("omega_end", omega_end)?;
    check_steps(cont)?;
    let mut ctx = Context::new(model, opts)?;
    check_start(&ctx, start, omega_end, opts)?;
    let (w0, span) = (start.omega, omega_end - start.omega);
    let dir = span.signum();
    let n = ctx.aft.dim();
    let mut y = DVector::from_iterator(n + 1, start.coeffs.iter().copied().chain([w0]));
    let mut t = tangent(&mut ctx, &y, None)?;
    if t[n] * dir < 0.0 {
        t = -t;
    }
    let mut points = vec![HbPoint {
        fold: false,
        period_doubling: false,
        ..start.clone()
    }];
    let mut ds = cont.step;
    let mut reached = 0u64;
    progress.start(1000, "harmonic balance continuation");
    loop {
        if points.len() >= cont.max_points {
            return Err(GearError::Numerical(format!(
                "continuation reached {} points at Omega = {} before Omega = {omega_end}",
                cont.max_points, y[n]
            )));
        }
        let pred = &y + ds * &t;
        let step = corrector(&mut ctx, &pred, &t)
            .and_then(|(c, it)| tangent(&mut ctx, &c.y, Some(&t)).map(|tn| (c, tn, it)));
        let (cn, tn, iterations) = match step {
            Ok(s) if s.1.dot(&t) >= MIN_TANGENT_COS || ds <= 4.0 * cont.min_step => s,
            _ => {
                ds *= 0.5;
                if ds < cont.min_step {
                    return Err(GearError::Numerical(format!(
                        "continuation step fell below {} at Omega = {}",
                        cont.min_step, y[n]
                    )));
                }
                continue;
            }
        };
        let fold_here = t[n] * tn[n] < 0.0 && mark_fold(&mut ctx, (&y, &t, ds), &cn, &mut points);
        let wn = cn.y[n];
        if (wn - omega_end) * dir >= 0.0 || (wn - w0) * dir < 0.0 {
            // Past an end of the range: finish with the solution exactly at that end.
            let end = if (wn - omega_end) * dir >= 0.0 {
                omega_end
            } else {
                w0
            };
            points.extend(point_at_end(&mut ctx, &y, &cn.y, end));
            break;
        }
        let mut p = ctx_point(&ctx, &cn);
        p.fold = fold_here;
        if t[n] * tn[n] > 0.0 {
            points.extend(period_doubling_between(&mut ctx, (&y, &t, ds), &points, &p));
        }
        points.push(p);
        let frac = (((wn - w0) / span).clamp(0.0, 1.0) * 1000.0) as u64;
        if frac > reached {
            progress.advance(frac - reached);
            reached = frac;
        }
        y = cn.y;
        t = tn;
        ds = next_step(ds, iterations, cont);
    }
    progress.finish();
    mark_period_doubling(&mut points);
    Ok(points)
}

/// `start` must fit the model's harmonics and subharmonic order and lie off `omega_end`.
fn check_start(ctx: &Context, start: &HbPoint, omega_end: f64, opts: &AftOptions) -> Result<()> {
    ctx.check_coeffs(&start.coeffs)?;
    if start.subharmonic != opts.subharmonic {
        return Err(GearError::param(
            "subharmonic",
            start.subharmonic as f64,
            "the start point was computed with another subharmonic order",
        ));
    }
    if omega_end == start.omega {
        return Err(GearError::param(
            "omega_end",
            omega_end,
            "the end frequency must differ from the start frequency",
        ));
    }
    Ok(())
}

/// A fold between the last point and the next (`cn`): located and inserted as its own point,
/// or marked on the last point when it coincides with it; true when it coincides with the next
/// point instead (or cannot be located), which is then marked.
fn mark_fold(
    ctx: &mut Context,
    (y, t, ds): (&DVector<f64>, &DVector<f64>, f64),
    cn: &Corrected,
    points: &mut Vec<HbPoint>,
) -> bool {
    let near = |a: &DVector<f64>, b: &DVector<f64>| (a - b).amax() <= 1e-9 * (1.0 + b.amax());
    match locate_fold(ctx, y, t, ds) {
        Some(f) if near(&f.y, y) => {
            if let Some(last) = points.last_mut() {
                last.fold = true;
            }
            false
        }
        Some(f) if !near(&f.y, &cn.y) => {
            let mut p = ctx_point(ctx, &f);
            p.fold = true;
            points.push(p);
            false
        }
        _ => true,
    }
}

/// The solution exactly at `end`, from the chord between `y` and the step past it `yn` (none
/// when Newton fails there).
fn point_at_end(
    ctx: &mut Context,
    y: &DVector<f64>,
    yn: &DVector<f64>,
    end: f64,
) -> Option<HbPoint> {
    let n = y.len() - 1;
    let s = (end - y[n]) / (yn[n] - y[n]);
    let guess = y + s * (yn - y);
    ctx.newton(&guess.as_slice()[..n], end)
        .ok()
        .map(|(x, res)| ctx.point(x, end, res))
}

/// The period doubling between the last point and `p` when a Floquet multiplier crossed -1
/// between them (located by bisection).
fn period_doubling_between(
    ctx: &mut Context,
    (y, t, ds): (&DVector<f64>, &DVector<f64>, f64),
    points: &[HbPoint],
    p: &HbPoint,
) -> Option<HbPoint> {
    let before = points.last().and_then(below_minus_one)?;
    let after = below_minus_one(p)?;
    if before == after {
        return None;
    }
    locate_period_doubling(ctx, y, t, ds, before)
}

/// The next arclength step: longer after an easy corrector, shorter after a hard one.
fn next_step(ds: f64, iterations: usize, cont: &ContinuationOptions) -> f64 {
    if iterations <= 3 {
        (1.5 * ds).min(cont.max_step)
    } else if iterations >= 6 {
        0.5 * ds
    } else {
        ds
    }
}

/// Unit tangent of R(x, Omega) = 0 at y: the solution z of [dR/dx dR/dOmega; r^T] z = e_last,
/// normalised, where r is the previous tangent (so that z . r > 0) or e_Omega.
fn tangent(
    ctx: &mut Context,
    y: &DVector<f64>,
    prev: Option<&DVector<f64>>,
) -> Result<DVector<f64>> {
    let n = ctx.aft.dim();
    let lin = ctx.aft.linearise(&y.as_slice()[..n], y[n])?;
    let mut a = DMatrix::zeros(n + 1, n + 1);
    a.view_mut((0, 0), (n, n)).copy_from(&lin.jx);
    a.view_mut((0, n), (n, 1)).copy_from(&lin.jw);
    match prev {
        Some(r) => a.row_mut(n).copy_from(&r.transpose()),
        None => a[(n, n)] = 1.0,
    }
    let mut rhs = DVector::zeros(n + 1);
    rhs[n] = 1.0;
    let z = a
        .lu()
        .solve(&rhs)
        .filter(|z| z.iter().all(|v| v.is_finite()))
        .ok_or_else(|| {
            GearError::Numerical(format!("singular continuation matrix at Omega = {}", y[n]))
        })?;
    let norm = z.norm();
    if norm == 0.0 {
        return Err(GearError::Numerical("zero continuation tangent".into()));
    }
    Ok(z / norm)
}

/// A corrected continuation state y = (x, Omega) with its residual max |R|.
struct Corrected {
    y: DVector<f64>,
    residual: f64,
}

/// Newton on [R(y); t . (y - pred)] = 0 from the predictor; returns the point and the iterations.
fn corrector(
    ctx: &mut Context,
    pred: &DVector<f64>,
    t: &DVector<f64>,
) -> Result<(Corrected, usize)> {
    let n = ctx.aft.dim();
    let mut y = pred.clone();
    let mut first = f64::INFINITY;
    for it in 0..=MAX_CORRECTOR {
        let omega = y[n];
        if !(omega.is_finite() && omega > 0.0) {
            break;
        }
        let lin = ctx.aft.linearise(&y.as_slice()[..n], omega)?;
        let rn = lin.r.amax();
        let g = t.dot(&(&y - pred));
        if rn <= ctx.tolerance(omega) && g.abs() <= 1e-12 {
            return Ok((Corrected { y, residual: rn }, it));
        }
        if !rn.is_finite() || rn > 1e3 * first || it == MAX_CORRECTOR {
            break;
        }
        first = first.min(rn.max(ctx.tolerance(omega)));
        let mut a = DMatrix::zeros(n + 1, n + 1);
        a.view_mut((0, 0), (n, n)).copy_from(&lin.jx);
        a.view_mut((0, n), (n, 1)).copy_from(&lin.jw);
        a.row_mut(n).copy_from(&t.transpose());
        let mut rhs = DVector::zeros(n + 1);
        rhs.rows_mut(0, n).copy_from(&(-&lin.r));
        rhs[n] = -g;
        let Some(dy) = a.lu().solve(&rhs) else { break };
        y += dy;
    }
    Err(GearError::Numerical(
        "continuation corrector did not converge".into(),
    ))
}

/// Locate the fold between y (tangent t) and the point one arclength step `ds` ahead: the
/// arclength s where the Omega-component of the tangent vanishes, by Illinois regula falsi.
/// (The sampled residual is piecewise linear, so the component may jump across zero; the search
/// then ends at the jump.)
fn locate_fold(
    ctx: &mut Context,
    y: &DVector<f64>,
    t: &DVector<f64>,
    ds: f64,
) -> Option<Corrected> {
    let n = ctx.aft.dim();
    let (mut a, mut fa) = (0.0, t[n]);
    let (mut b, mut fb) = (ds, f64::NAN);
    let mut best: Option<(f64, Corrected)> = None;
    let mut side = 0i8;
    for _ in 0..FOLD_ITERATIONS {
        let s = if fb.is_finite() {
            (a * fb - b * fa) / (fb - fa)
        } else {
            b
        };
        let pred = y + s * t;
        let (cs, _) = corrector(ctx, &pred, t).ok()?;
        let fs = tangent(ctx, &cs.y, Some(t)).ok()?[n];
        if best.as_ref().is_none_or(|(f, _)| fs.abs() < *f) {
            best = Some((fs.abs(), cs));
        }
        if fs.abs() <= 1e-10 || (b - a).abs() <= 1e-10 * ds {
            break;
        }
        if fs * fa > 0.0 {
            a = s;
            fa = fs;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = s;
            fb = fs;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    best.map(|(_, c)| c)
}

/// Solution record of a corrected continuation state.
fn ctx_point(ctx: &Context, c: &Corrected) -> HbPoint {
    let n = ctx.aft.dim();
    ctx.point(c.y.as_slice()[..n].to_vec(), c.y[n], c.residual)
}

/// Number of real Floquet multipliers below -1, when computed.
fn below_minus_one(p: &HbPoint) -> Option<usize> {
    p.multipliers
        .map(|m| m.iter().filter(|(re, im)| *im == 0.0 && *re < -1.0).count())
}

/// Locate a period doubling between y (tangent t) and the point one arclength step `ds` ahead by
/// bisection in the arclength on the number of real multipliers below -1 (`before` at y).
/// Returns the point just past the crossing, or `None` when no intermediate point was found.
fn locate_period_doubling(
    ctx: &mut Context,
    y: &DVector<f64>,
    t: &DVector<f64>,
    ds: f64,
    before: usize,
) -> Option<HbPoint> {
    let (mut a, mut b) = (0.0, ds);
    let mut past = None;
    for _ in 0..PD_BISECTIONS {
        let s = 0.5 * (a + b);
        let (c, _) = corrector(ctx, &(y + s * t), t).ok()?;
        let p = ctx_point(ctx, &c);
        if below_minus_one(&p)? == before {
            a = s;
        } else {
            b = s;
            past = Some(p);
        }
    }
    past
}

/// Mark points where the number of real multipliers below -1 changes (period doubling).
fn mark_period_doubling(points: &mut [HbPoint]) {
    for i in 1..points.len() {
        if let (Some(a), Some(b)) = (below_minus_one(&points[i - 1]), below_minus_one(&points[i])) {
            points[i].period_doubling = a != b;
        }
    }
}

fn check_omega(name: &'static str, w: f64) -> Result<()> {
    if w.is_finite() && w > 0.0 {
        Ok(())
    } else {
        Err(GearError::param(
            name,
            w,
            "frequency must be finite and > 0",
        ))
    }
}

fn check_steps(c: &ContinuationOptions) -> Result<()> {
    if !(c.min_step.is_finite() && c.min_step > 0.0) {
        return Err(GearError::param(
            "min_step",
            c.min_step,
            "must be finite and > 0",
        ));
    }
    if !(c.max_step.is_finite() && c.max_step >= c.min_step) {
        return Err(GearError::param(
            "max_step",
            c.max_step,
            "must be finite and >= min_step",
        ));
    }
    if !(c.step.is_finite() && c.step >= c.min_step && c.step <= c.max_step) {
        return Err(GearError::param(
            "step",
            c.step,
            "must lie between min_step and max_step",
        ));
    }
    if c.max_points < 2 {
        return Err(GearError::param(
            "max_points",
            c.max_points as f64,
            "must be >= 2",
        ));
    }
    Ok(())
}
