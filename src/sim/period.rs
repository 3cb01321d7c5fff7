//! Periodic orbits of the Poincare map: period detection on a sequence of section points, Newton
//! refinement of a period-p orbit with the exact monodromy matrix, and its Floquet multipliers.

use super::flow::{PeriodFlow, State};
use crate::error::Result;
use nalgebra::Matrix2;

/// Largest subharmonic order searched for (period-32 orbits and shorter).
pub const MAX_PERIOD: u32 = 32;

/// Distance between two section points (Euclidean in (q, q')).
#[inline]
pub fn distance(a: State, b: State) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Scale of a set of section points, used to make tolerances relative: 1 + max |x|.
pub fn scale(points: &[State]) -> f64 {
    1.0 + points
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max)
}

/// Smallest p <= `max_period` such that the last points repeat with period p:
/// |P_{k+p} - P_k| <= tol for every k with both points among `points`, requiring at least two
/// full repetitions so that a coincidence cannot pass.
pub fn detect_period(points: &[State], max_period: u32, tol: f64) -> Option<u32> {
    (1..=max_period).find(|&p| {
        let p = p as usize;
        points.len() >= 3 * p
            && (0..points.len() - p).all(|k| distance(points[k], points[k + p]) <= tol)
    })
}

/// A period-p orbit refined to machine precision, with its Floquet multipliers.
#[derive(Clone, Debug)]
pub struct PeriodicOrbit {
    /// Subharmonic order p (the orbit repeats after p forcing periods).
    pub period: u32,
    /// The p section points, starting from the refined one.
    pub points: Vec<State>,
    /// Floquet multipliers (eigenvalues of the monodromy over p periods) as (re, im).
    pub multipliers: [(f64, f64); 2],
    /// Final residual |Phi^p(x) - x|.
    pub residual: f64,
}

impl PeriodicOrbit {
    /// Largest multiplier modulus: < 1 for an asymptotically stable orbit.
    pub fn spectral_radius(&self) -> f64 {
        self.multipliers
            .iter()
            .map(|(re, im)| re.hypot(*im))
            .fold(0.0, f64::max)
    }
}

/// Eigenvalues of a 2x2 matrix as (re, im) pairs.
pub fn eigenvalues2(m: &Matrix2<f64>) -> [(f64, f64); 2] {
    let tr = m.trace();
    let det = m.determinant();
    let disc = 0.25 * tr * tr - det;
    if disc >= 0.0 {
        let r = disc.sqrt();
        [(0.5 * tr + r, 0.0), (0.5 * tr - r, 0.0)]
    } else {
        let r = (-disc).sqrt();
        [(0.5 * tr, r), (0.5 * tr, -r)]
    }
}

/// Map x through p periods, returning the image and the monodromy matrix.
pub fn monodromy<F: PeriodFlow + ?Sized>(
    flow: &F,
    x: State,
    p: u32,
) -> Result<(State, Matrix2<f64>)> {
    let mut phi = Matrix2::identity();
    let mut y = x;
    for _ in 0..p {
        y = flow.step_tangent(y, &mut phi)?;
    }
    Ok((y, phi))
}

/// Newton's method on Phi^p(x) = x with the exact monodromy (shooting). Returns None when it does
/// not converge to a relative residual of 1e-12 within a few iterations (then x is not close to a
/// period-p orbit, or the orbit is grazing a boundary).
pub fn refine_orbit<F: PeriodFlow + ?Sized>(
    flow: &F,
    x0: State,
    p: u32,
) -> Result<Option<PeriodicOrbit>> {
    let mut x = x0;
    for _ in 0..12 {
        let (y, m) = monodromy(flow, x, p)?;
        let r = [y[0] - x[0], y[1] - x[1]];
        let res = r[0].hypot(r[1]);
        let sc = 1.0 + x[0].abs().max(x[1].abs());
        if res <= 1e-12 * sc {
            let mut points = Vec::with_capacity(p as usize);
            points.push(x);
            // The point after the last is x again: not integrated.
            for _ in 1..p {
                let z = flow.step(points[points.len() - 1], None)?;
                points.push(z);
            }
            // Newton on Phi^p also converges to orbits of any period dividing p: keep the least.
            let least = (1..p)
                .filter(|d| p.is_multiple_of(*d))
                .find(|&d| distance(points[d as usize], x) <= 1e-9 * sc);
            if let Some(d) = least {
                return refine_orbit(flow, x, d);
            }
            return Ok(Some(PeriodicOrbit {
                period: p,
                points,
                multipliers: eigenvalues2(&m),
                residual: res,
            }));
        }
        let j = m - Matrix2::identity();
        let Some(inv) = j.try_inverse() else {
            return Ok(None);
        };
        let dx = inv * nalgebra::Vector2::new(r[0], r[1]);
        // Newton step limited to a small move: far from the orbit the map is not smooth
        // (crossings appear or vanish), and a long step would only wander.
        let step = dx.norm();
        if !step.is_finite() || step > 0.1 * sc {
            return Ok(None);
        }
        x = [x[0] - dx[0], x[1] - dx[1]];
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn period_detection_needs_repetition() {
        let a = [1.0, 0.0];
        let b = [2.0, 0.5];
        let c = [0.5, -1.0];
        let seq: Vec<State> = (0..12).map(|k| [a, b, c][k % 3]).collect();
        assert_eq!(detect_period(&seq, 32, 1e-12), Some(3));
        assert_eq!(detect_period(&seq[..5], 32, 1e-12), None);
        let fixed = vec![a; 5];
        assert_eq!(detect_period(&fixed, 32, 1e-12), Some(1));
    }

    #[test]
    fn eigenvalues_of_rotation_and_diagonal() {
        let e = eigenvalues2(&Matrix2::new(2.0, 0.0, 0.0, 0.5));
        assert!((e[0].0 - 2.0).abs() < 1e-15 && (e[1].0 - 0.5).abs() < 1e-15);
        let r = eigenvalues2(&Matrix2::new(0.0, -1.0, 1.0, 0.0));
        assert!((r[0].1.abs() - 1.0).abs() < 1e-15 && r[0].0.abs() < 1e-15);
    }
}
