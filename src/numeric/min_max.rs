//! The smallest and largest of a set of values.

/// Smallest and largest of the values (None when there are none).
pub fn min_max(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |r, x| {
        Some(r.map_or((x, x), |(lo, hi): (f64, f64)| (lo.min(x), hi.max(x))))
    })
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
}
