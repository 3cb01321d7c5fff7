//! The 7th-order continuous extension (dense output) of one accepted DOP853 step.
//!
//! Hairer, Norsett & Wanner, *Solving ODEs I*, Sec. II.6 and II.10, as evaluated by `CONTD8` of
//! Hairer's `dop853.f`: with theta = (t - t0) / h and theta1 = 1 - theta,
//!
//! y(t) = y0 + theta (r1 + theta1 (r2 + theta (r3 + theta1 (r4 + theta (r5 + theta1 (r6 + theta r7)))))),
//!
//! r1 = y1 - y0, r2 = h f0 - r1, r3 = r1 - h f1 - r2, r4..r7 = h sum_j D_ij k_j.

use super::tableau::D;

/// Dense output of one accepted step, valid on `[t0, t1]`. When an event stopped the step, `t1`
/// is the event time and the polynomial (built on the full step `[t0, t0 + h]`) is only used up
/// to it.
#[derive(Clone, Copy, Debug)]
pub struct DenseStep<const N: usize> {
    t0: f64,
    t1: f64,
    h: f64,
    y0: [f64; N],
    r: [[f64; N]; 7],
}

impl<const N: usize> DenseStep<N> {
    /// Build the interpolant from the step data: start (t0, y0, f0), full step h, end (y1, f1)
    /// and the 16 stages k (12 main stages, the FSAL stage f1 and the 3 extra stages).
    pub(super) fn new(t0: f64, h: f64, y0: &[f64; N], y1: &[f64; N], k: &[[f64; N]; 16]) -> Self {
        let mut r = [[0.0; N]; 7];
        for i in 0..N {
            let dy = y1[i] - y0[i];
            let bspl = h * k[0][i] - dy;
            r[0][i] = dy;
            r[1][i] = bspl;
            r[2][i] = dy - h * k[12][i] - bspl;
            for (row, d) in D.iter().enumerate() {
                let mut s = 0.0;
                for (dj, kj) in d.iter().zip(k.iter()) {
                    s += dj * kj[i];
                }
                r[3 + row][i] = h * s;
            }
        }
        DenseStep {
            t0,
            t1: t0 + h,
            h,
            y0: *y0,
            r,
        }
    }

    /// Restrict the span to `[t0, t1]` (used when an event ends the step early).
    pub(super) fn truncate(&mut self, t1: f64) {
        self.t1 = t1;
    }

    /// Start and end time of the span on which the step is valid.
    pub fn span(&self) -> (f64, f64) {
        (self.t0, self.t1)
    }

    /// Interpolated state at time `t` (7th-order accurate inside the span; `CONTD8`).
    pub fn eval(&self, t: f64) -> [f64; N] {
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut y = [0.0; N];
        for (i, yi) in y.iter_mut().enumerate() {
            let p = r[3][i] + th * (r[4][i] + th1 * (r[5][i] + th * r[6][i]));
            *yi = self.y0[i] + th * (r[0][i] + th1 * (r[1][i] + th * (r[2][i] + th1 * p)));
        }
        y
    }

    /// Time derivative of the interpolant at `t` (6th-order accurate approximation of y').
    pub fn eval_derivative(&self, t: f64) -> [f64; N] {
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut dy = [0.0; N];
        for (i, di) in dy.iter_mut().enumerate() {
            // Differentiate the nested form from the inside out: (u, u') pairs in theta,
            // using d(theta)/d(theta) = 1 and d(theta1)/d(theta) = -1.
            let (mut u, mut du) = (r[6][i], 0.0);
            for (j, coef) in [r[5][i], r[4][i], r[3][i], r[2][i], r[1][i], r[0][i]]
                .iter()
                .enumerate()
            {
                // Multiplier alternates theta, theta1, theta, ... from the innermost level.
                let (m, dm) = if j % 2 == 0 { (th, 1.0) } else { (th1, -1.0) };
                let nu = coef + m * u;
                let ndu = dm * u + m * du;
                u = nu;
                du = ndu;
            }
            // Outermost: y = y0 + theta * u.
            *di = (u + th * du) / self.h;
        }
        dy
    }
}
