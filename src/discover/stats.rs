//! Small statistical tools of the discovery workflow: Holm's step-down correction, the Monte
//! Carlo p-value, a difference-based noise estimate, the one-sided Clopper-Pearson bound (the
//! two-sided Wilson interval is [`crate::numeric::wilson95`]) and the Kolmogorov-Smirnov distance
//! from uniform. Closed forms, no dependencies.

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

/// Noise standard deviation of a curve sampled on an even grid, from its second differences
/// (Gasser, Sroka & Jennen-Steinmetz 1986 pseudo-residuals): d_i = y_{i-1} - 2 y_i + y_{i+1} has
/// variance 6 sigma^2 for white noise, and a smooth curve adds little. The median of |d| (MAD,
/// sigma = 1.4826 median|d| / sqrt 6) keeps resonance peaks and jumps from inflating it. Returns
/// None with fewer than 3 usable differences.
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

/// One-sided 95% upper confidence bound of a binomial proportion from k successes in n trials
/// (Clopper & Pearson 1934): the p at which P(X <= k; n, p) = 0.05, by bisection on the exact
/// binomial distribution function (terms summed in log space). 1 when k = n; None for n = 0.
pub fn clopper_pearson_upper95(k: usize, n: usize) -> Option<f64> {
    if n == 0 || k > n {
        return None;
    }
    if k == n {
        return Some(1.0);
    }
    let cdf = |p: f64| -> f64 {
        let (lp, lq) = (p.ln(), (1.0 - p).ln());
        let mut ln_choose = 0.0;
        let mut sum = 0.0;
        for i in 0..=k {
            if i > 0 {
                ln_choose += ((n - i + 1) as f64 / i as f64).ln();
            }
            sum += (ln_choose + i as f64 * lp + (n - i) as f64 * lq).exp();
        }
        sum
    };
    let (mut lo, mut hi) = (k as f64 / n as f64, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if cdf(mid) > 0.05 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Kolmogorov-Smirnov distance sup |F_n(p) - p| of sorted values in [0, 1] from the uniform
/// distribution (0 for no values).
pub fn ks_from_uniform(sorted: &[f64]) -> f64 {
    let n = sorted.len() as f64;
    sorted
        .iter()
        .enumerate()
        .map(|(i, &p)| (p - i as f64 / n).max((i + 1) as f64 / n - p))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clopper_pearson_bounds_match_closed_forms() {
        // k = 0: (1 - p)^n = 0.05, p = 1 - 0.05^(1/n).
        let u = clopper_pearson_upper95(0, 300).unwrap();
        assert!((u - (1.0 - 0.05f64.powf(1.0 / 300.0))).abs() < 1e-12, "{u}");
        // k = n - 1: 1 - p^n = 0.05, p = 0.95^(1/n).
        let u = clopper_pearson_upper95(9, 10).unwrap();
        assert!((u - 0.95f64.powf(0.1)).abs() < 1e-12, "{u}");
        // k = 1, n = 2: 1 - p^2 = 0.05 as well.
        let u = clopper_pearson_upper95(1, 2).unwrap();
        assert!((u - 0.95f64.sqrt()).abs() < 1e-12);
        assert_eq!(clopper_pearson_upper95(3, 3), Some(1.0));
        assert_eq!(clopper_pearson_upper95(0, 0), None);
    }

    #[test]
    fn ks_distance_of_an_even_grid_and_a_pile_up() {
        // Midpoints (i + 1/2) / n are the closest n points to uniform: distance 1 / (2n).
        let grid: Vec<f64> = (0..10).map(|i| (i as f64 + 0.5) / 10.0).collect();
        assert!((ks_from_uniform(&grid) - 0.05).abs() < 1e-15);
        // Everything at 0.01: the empirical CDF is 1 from 0.01 on, distance 0.99.
        assert!((ks_from_uniform(&[0.01; 5]) - 0.99).abs() < 1e-15);
        assert_eq!(ks_from_uniform(&[]), 0.0);
    }

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
