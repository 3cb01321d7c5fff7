//! The Wilson score interval of a binomial proportion (Wilson 1927), for coverage and detection
//! rates counted over seeds.

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
}
