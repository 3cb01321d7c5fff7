//! Numbers rounded for printing and for grids that must hold the decimal values typed.

/// `x` rounded to `digits` significant decimal digits (through its decimal text, which is
/// exact: Rust prints and parses floats correctly rounded).
pub fn to_significant(x: f64, digits: usize) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    format!("{:.*e}", digits.saturating_sub(1), x)
        .parse()
        .unwrap_or(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_to_significant_digits() {
        assert_eq!(to_significant(1.0 / 3.0, 3), 0.333);
        assert_eq!(to_significant(-2.6e-7, 1), -3e-7);
    }
}
