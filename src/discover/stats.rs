//! Small statistical tools of the discovery workflow: the normal and chi-square tails, the
//! Wald-Wolfowitz runs test, Holm's step-down correction, a difference-based noise estimate and
//! the one-sided Clopper-Pearson bound (the two-sided Wilson interval is
//! [`crate::numeric::wilson95`]). Closed forms, no dependencies.

/// Standard normal upper tail P(Z > z), from erfc by the Numerical Recipes Chebyshev fit
/// (fractional error < 1.2e-7 everywhere), which is ample for p-values.
pub fn normal_sf(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Chi-square upper tail P(X > x) with `df` degrees of freedom by the Wilson-Hilferty cube-root
/// normal approximation ((X/k)^(1/3) is nearly normal with mean 1 - 2/(9k), variance 2/(9k));
/// used only to rank candidates, never for a decision (those are bootstrap-calibrated).
pub fn chi2_sf(x: f64, df: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let v = 2.0 / (9.0 * df);
    normal_sf(((x / df).cbrt() - (1.0 - v)) / v.sqrt())
}

/// Wald-Wolfowitz runs test along frequency, as a standard normal score: with n+ positive and n-
/// negative signs and R runs, E(R) = 1 + 2 n+ n- / n and Var(R) = (E(R) - 1)(E(R) - 2)/(n - 1).
/// Returns (R - E(R)) / sd(R) summed over the independent sequences (one per load) as a single
/// z (sum of R and of the moments). Too few runs (negative z) means residuals that keep their
/// sign over stretches of frequency: structure the model misses.
pub fn runs_z(sequences: &[Vec<f64>]) -> f64 {
    let (mut r, mut mean, mut var) = (0.0, 0.0, 0.0);
    for s in sequences {
        let signs: Vec<bool> = s.iter().filter(|x| **x != 0.0).map(|x| *x > 0.0).collect();
        let n = signs.len() as f64;
        let np = signs.iter().filter(|b| **b).count() as f64;
        let nm = n - np;
        if np == 0.0 || nm == 0.0 || n < 3.0 {
            continue;
        }
        r += 1.0 + signs.windows(2).filter(|w| w[0] != w[1]).count() as f64;
        let m = 1.0 + 2.0 * np * nm / n;
        mean += m;
        var += (m - 1.0) * (m - 2.0) / (n - 1.0);
    }
    if var > 0.0 {
        (r - mean) / var.sqrt()
    } else {
        0.0
    }
}

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
    fn normal_and_chi2_tails_match_tables() {
        assert!((normal_sf(1.959_964) - 0.025).abs() < 1e-6);
        assert!((normal_sf(-1.0) - 0.841_344_7).abs() < 1e-6);
        // chi2(0.95; 2) = 5.991, chi2(0.95; 10) = 18.307 (tables).
        assert!((chi2_sf(5.991, 2.0) - 0.05).abs() < 0.004);
        assert!((chi2_sf(18.307, 10.0) - 0.05).abs() < 0.002);
    }

    #[test]
    fn holm_adjusts_in_order() {
        let a = holm(&[0.01, 0.04, 0.03]);
        // sorted 0.01 (x3), 0.03 (x2), 0.04 (x1) -> 0.03, 0.06, max(0.06, 0.04).
        assert!((a[0] - 0.03).abs() < 1e-12 && (a[2] - 0.06).abs() < 1e-12);
        assert!((a[1] - 0.06).abs() < 1e-12);
    }

    #[test]
    fn runs_test_sees_alternation_and_blocks() {
        let alt: Vec<f64> = (0..40)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let blocks: Vec<f64> = (0..40).map(|i| if i < 20 { 1.0 } else { -1.0 }).collect();
        assert!(runs_z(&[alt]) > 5.0);
        assert!(runs_z(&[blocks]) < -5.0);
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
