//! The truncated Fourier series of the multi-harmonic balance ansatz
//!
//! q(t) = a_0 + sum_{k=1..H} (a_k cos(k theta) + b_k sin(k theta)),  theta = Omega t / nu,
//!
//! stored as `[a_0, a_1, b_1, a_2, b_2, ..., a_H, b_H]`: its evaluation in the orbit phase theta
//! and its extreme values over one orbit period (for q_a, q_m and the impact regime of Fig. 9).

use crate::sim::golden_max;
use std::f64::consts::TAU;

/// Number of harmonics H of a coefficient vector of length 2H + 1.
#[inline]
pub(crate) fn harmonics_of(coeffs: &[f64]) -> usize {
    coeffs.len().saturating_sub(1) / 2
}

/// q, dq/dtheta and d^2q/dtheta^2 at orbit phase `theta` (cos/sin by complex rotation).
pub(crate) fn eval_theta(coeffs: &[f64], theta: f64) -> [f64; 3] {
    let h = harmonics_of(coeffs);
    let (s1, c1) = theta.sin_cos();
    let (mut c, mut s) = (1.0_f64, 0.0_f64);
    let mut out = [coeffs.first().copied().unwrap_or(0.0), 0.0, 0.0];
    for k in 1..=h {
        (c, s) = (c * c1 - s * s1, s * c1 + c * s1);
        let (a, b) = (coeffs[2 * k - 1], coeffs[2 * k]);
        let kf = k as f64;
        let val = a * c + b * s;
        out[0] += val;
        out[1] += kf * (b * c - a * s);
        out[2] -= kf * kf * val;
    }
    out
}

/// Samples per orbit period used to locate extrema and contact-boundary crossings: fine against
/// the shortest wavelength 2 pi / H of the series.
pub(crate) fn fine_samples(h: usize) -> usize {
    (32 * h).max(512)
}

/// Smallest and largest q over one orbit period: the best of a fine sampling, each candidate
/// refined by golden-section search on the series (exact to rounding at a smooth extremum).
pub(crate) fn extremes(coeffs: &[f64]) -> (f64, f64) {
    let m = fine_samples(harmonics_of(coeffs));
    let dt = TAU / m as f64;
    let q: Vec<f64> = (0..m)
        .map(|i| eval_theta(coeffs, i as f64 * dt)[0])
        .collect();
    // A sample can miss the true extremum by at most the largest change between neighbours, so
    // every local extremum within that margin of the best sample is refined.
    let margin = (0..m)
        .map(|i| (q[(i + 1) % m] - q[i]).abs())
        .fold(0.0, f64::max);
    let (mut lo, mut hi) = q
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let (best_lo, best_hi) = (lo, hi);
    for i in 0..m {
        let (prev, next) = (q[(i + m - 1) % m], q[(i + 1) % m]);
        let (a, b) = ((i as f64 - 1.0) * dt, (i as f64 + 1.0) * dt);
        if q[i] >= prev && q[i] >= next && q[i] >= best_hi - margin {
            hi = hi.max(golden_max(&|t| eval_theta(coeffs, t)[0], a, b));
        }
        if q[i] <= prev && q[i] <= next && q[i] <= best_lo + margin {
            lo = lo.min(-golden_max(&|t| -eval_theta(coeffs, t)[0], a, b));
        }
    }
    (lo, hi)
}

/// Orbit phases in [0, 2 pi) where the series crosses a contact boundary q = +-1, sorted: the
/// points where f'(q) of eq. 3c switches. Located by bisection between fine samples (a grazing
/// excursion shorter than a sample spacing can be missed).
pub(crate) fn boundary_crossings(coeffs: &[f64]) -> Vec<f64> {
    let m = fine_samples(harmonics_of(coeffs));
    let dt = TAU / m as f64;
    let q: Vec<f64> = (0..=m)
        .map(|i| eval_theta(coeffs, i as f64 * dt)[0])
        .collect();
    let mut out = Vec::new();
    for level in [1.0, -1.0] {
        let side = |v: f64| if level > 0.0 { v > level } else { v < level };
        for i in 0..m {
            if side(q[i]) == side(q[i + 1]) {
                continue;
            }
            let (mut a, mut b) = (i as f64 * dt, (i + 1) as f64 * dt);
            let sa = side(q[i]);
            for _ in 0..60 {
                let mid = 0.5 * (a + b);
                if side(eval_theta(coeffs, mid)[0]) == sa {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            out.push(0.5 * (a + b));
        }
    }
    out.sort_by(f64::total_cmp);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluation_and_extremes_of_a_known_series() {
        // q = 2 + 0.3 cos(theta) + 0.4 sin(theta) + 0.1 sin(2 theta)
        let c = [2.0, 0.3, 0.4, 0.0, 0.1];
        let th: f64 = 0.7;
        let exact = 2.0 + 0.3 * th.cos() + 0.4 * th.sin() + 0.1 * (2.0 * th).sin();
        let d1 = -0.3 * th.sin() + 0.4 * th.cos() + 0.2 * (2.0 * th).cos();
        let v = eval_theta(&c, th);
        assert!((v[0] - exact).abs() < 1e-15 && (v[1] - d1).abs() < 1e-15);
        let (lo, hi) = extremes(&[1.0, 0.0, 0.5]);
        assert!((lo - 0.5).abs() < 1e-14 && (hi - 1.5).abs() < 1e-14);
        let x = boundary_crossings(&[1.0, 0.0, 0.5]);
        assert_eq!(x.len(), 2);
        assert!(x[0].abs() < 1e-12 || (x[0] - std::f64::consts::PI).abs() < 1e-12);
    }
}
