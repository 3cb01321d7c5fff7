//! Small statistical tools of the discovery workflow, closed forms: Holm's step-down correction,
//! the Monte Carlo p-value and a difference-based noise estimate.

/// Holm's step-down adjustment (Holm 1979) of p-values for family-wise error control:
/// sort p ascending, p_adj(i) = max_{j <= i} min(1, (m - j) p_(j)), returned in input order.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut idx: Vec<usize> = (0..m).collect();
    idx.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut out = vec![1.0; m];
    let mut running: f64 = 0.0;
    for (rank, &i) in idx.iter().enumerate() {
        running = running.max(((m - rank) as f64 * p[i]).min(1.0));
        out[i] = running;
    }
    out
}

/// Noise standard deviation of curves on an even grid from their second differences (Gasser,
/// Sroka & Jennen-Steinmetz 1986): d_i = y_{i-1} - 2 y_i + y_{i+1} has variance 6 sigma^2 for
/// white noise, a smooth curve adding little; the MAD, sigma = 1.4826 median|d| / sqrt 6, keeps
/// resonance peaks and jumps from inflating it. None with fewer than 3 usable differences.
pub fn noise_from_differences(curves: &[Vec<f64>]) -> Option<f64> {
    let mut d: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).abs()))
        .filter(|x| x.is_finite())
        .collect();
    if d.len() < 3 {
        return None;
    }
    d.sort_by(f64::total_cmp);
    let med = if d.len() % 2 == 1 {
        d[d.len() / 2]
    } else {
        0.5 * (d[d.len() / 2 - 1] + d[d.len() / 2])
    };
    Some(1.4826 * med / 6f64.sqrt())
}

/// Monte Carlo p-value with the observed statistic counted among the replicates,
/// (1 + #{T* >= T}) / (B + 1) (Davison & Hinkley 1997, eq. 4.11), never exactly zero.
pub fn bootstrap_p(observed: f64, replicates: &[f64]) -> f64 {
    let ge = replicates.iter().filter(|t| **t >= observed).count();
    (1 + ge) as f64 / (replicates.len() + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holm_adjusts_in_order() {
        let a = holm(&[0.01, 0.04, 0.03]);
        // sorted 0.01 (x3), 0.03 (x2), 0.04 (x1) -> 0.03, 0.06, max(0.06, 0.04).
        assert!((a[0] - 0.03).abs() < 1e-12 && (a[2] - 0.06).abs() < 1e-12);
        assert!((a[1] - 0.06).abs() < 1e-12);
    }

    #[test]
    fn difference_noise_estimate_recovers_sigma_on_a_smooth_curve() {
        let mut rng = crate::numeric::Rng::new(3);
        let c: Vec<f64> = (0..4000)
            .map(|i| (i as f64 * 0.01).sin() * 5.0 + 0.2 * rng.normal())
            .collect();
        let s = noise_from_differences(&[c]).unwrap();
        // MAD-based: standard error about 1.65 sigma / sqrt(n) ~ 0.005 here.
        assert!((s - 0.2).abs() < 0.02, "{s}");
    }
}
