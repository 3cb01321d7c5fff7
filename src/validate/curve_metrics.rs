//! Comparisons of a predicted curve with a measured one: RMS error and jump locations.

/// Root-mean-square of the differences.
pub fn rms(diffs: &[f64]) -> f64 {
    if diffs.is_empty() {
        return f64::NAN;
    }
    (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64).sqrt()
}

/// Smallest and largest of the values (None when there are none).
pub fn min_max(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |r, x| {
        Some(r.map_or((x, x), |(lo, hi): (f64, f64)| (lo.min(x), hi.max(x))))
    })
}

/// Speed of the first jump of a curve (sorted by speed): the first step between consecutive points
/// that exceeds `factor` times the median step and a quarter of the largest step; the midpoint
/// speed is returned.
pub fn jump_location(curve: &[(f64, f64)], factor: f64) -> Option<f64> {
    if curve.len() < 4 {
        return None;
    }
    let steps: Vec<(f64, f64)> = curve
        .windows(2)
        .map(|w| (0.5 * (w[0].0 + w[1].0), (w[1].1 - w[0].1).abs()))
        .collect();
    let mut sizes: Vec<f64> = steps.iter().map(|s| s.1).collect();
    sizes.sort_by(f64::total_cmp);
    let median = sizes[sizes.len() / 2];
    let biggest = sizes[sizes.len() - 1];
    let threshold = (factor * median.max(1e-12)).max(0.25 * biggest);
    steps
        .iter()
        .find(|s| s.1 > threshold && s.1 > factor * median.max(1e-12))
        .map(|s| s.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_max_of_values_and_of_nothing() {
        assert_eq!(min_max([3.0, -1.5, 2.0]), Some((-1.5, 3.0)));
        assert_eq!(min_max([4.0]), Some((4.0, 4.0)));
        assert_eq!(min_max(std::iter::empty()), None);
    }

    #[test]
    fn finds_a_jump_and_ignores_smooth_curves() {
        let smooth: Vec<(f64, f64)> = (0..20)
            .map(|i| (i as f64, (i as f64 * 0.3).sin()))
            .collect();
        assert_eq!(jump_location(&smooth, 5.0), None);
        let mut jumpy = smooth.clone();
        for p in jumpy.iter_mut().skip(12) {
            p.1 += 10.0;
        }
        assert_eq!(jump_location(&jumpy, 5.0), Some(11.5));
        assert!((rms(&[3.0, 4.0]) - (12.5f64).sqrt()).abs() < 1e-15);
    }
}
