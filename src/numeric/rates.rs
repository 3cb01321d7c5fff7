//! Rates counted over seeds: the Wilson score interval of a binomial proportion (Wilson 1927),
//! its exact one-sided upper bound (Clopper & Pearson 1934), and the Kolmogorov-Smirnov
//! distance of p-values from the uniform law; and the rate a chi-square test can reach, its
//! power under a non-central chi-square law.

/// Wilson score 95% interval of a binomial proportion k / n (Wilson 1927):
/// (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n), z = 1.96.
pub fn wilson95(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (z, nf) = (1.959_963_985, n as f64);
    let p = k as f64 / nf;
    let den = 1.0 + z * z / nf;
    let centre = (p + z * z / (2.0 * nf)) / den;
    let half = z * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt() / den;
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// One-sided 95% upper confidence bound of a binomial proportion from k successes in n trials
/// (Clopper & Pearson 1934): the 95% point of Beta(k + 1, n - k). 1 when k = n; None for n = 0.
pub fn clopper_pearson_upper95(k: usize, n: usize) -> Option<f64> {
    use statrs::distribution::{Beta, ContinuousCDF};
    if n == 0 || k > n {
        return None;
    }
    if k == n {
        return Some(1.0);
    }
    Beta::new((k + 1) as f64, (n - k) as f64)
        .ok()
        .map(|b| b.inverse_cdf(0.95))
}

/// Power of a chi-square test with `dof` degrees of freedom at level `level` when its statistic
/// follows the non-central chi-square law of non-centrality `lambda`: P(X > c), c the null
/// law's 1 - level point, by the Poisson mixture of central laws (Johnson, Kotz & Balakrishnan
/// 1995, eq. 29.2), its weights in logarithms over the Poisson law's bulk (mean +- 40 standard
/// deviations), where exp(-lambda / 2) alone would underflow. statrs has the central law only.
pub fn chi_square_power(dof: f64, lambda: f64, level: f64) -> Option<f64> {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    use statrs::function::gamma::ln_gamma;
    let c = ChiSquared::new(dof).ok()?.inverse_cdf(1.0 - level);
    if !(lambda.is_finite() && lambda >= 0.0 && c.is_finite()) {
        return None;
    }
    // Far beyond the critical point the power is 1 to double precision.
    if lambda.sqrt() - c.sqrt() > 40.0 {
        return Some(1.0);
    }
    let half = lambda / 2.0;
    let spread = 40.0 * half.sqrt() + 20.0;
    let (first, last) = ((half - spread).max(0.0) as u64, (half + spread) as u64);
    let mut sum = 0.0;
    for j in first..=last {
        let j = j as f64;
        let log_weight = if half > 0.0 {
            -half + j * half.ln() - ln_gamma(j + 1.0)
        } else if j == 0.0 {
            0.0
        } else {
            f64::NEG_INFINITY
        };
        sum += log_weight.exp() * ChiSquared::new(dof + 2.0 * j).ok()?.sf(c);
    }
    Some(sum.min(1.0))
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
    fn wilson_interval_brackets_the_proportion() {
        let (lo, hi) = wilson95(5, 100);
        assert!(
            lo > 0.015 && lo < 0.03 && hi > 0.10 && hi < 0.12,
            "{lo} {hi}"
        );
        assert_eq!(wilson95(0, 100).0, 0.0);
    }

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
    fn chi_square_power_matches_the_normal_form_for_one_degree() {
        // One degree: P((Z + sqrt(lambda))^2 > z^2) = Phi(sqrt(lambda) - z) + Phi(-sqrt(lambda) - z).
        use statrs::distribution::{ContinuousCDF, Normal};
        let n = Normal::new(0.0, 1.0).unwrap();
        let z = n.inverse_cdf(1.0 - 0.01 / 2.0);
        for lambda in [0.0_f64, 1.0, 7.85, 20.0, 60.0] {
            let exact = n.cdf(lambda.sqrt() - z) + n.cdf(-lambda.sqrt() - z);
            let p = chi_square_power(1.0, lambda, 0.01).unwrap();
            assert!((p - exact).abs() < 1e-9, "{lambda}: {p} vs {exact}");
        }
        // A large non-centrality (exp(-lambda / 2) underflows) has power 1.
        assert!((chi_square_power(2.0, 5e3, 0.01).unwrap() - 1.0).abs() < 1e-9);
        // Two degrees at lambda 0 is the level.
        let p = chi_square_power(2.0, 0.0, 0.05).unwrap();
        // statrs inverts the central law numerically, to about 1e-9.
        assert!((p - 0.05).abs() < 1e-8, "{p}");
    }
}
