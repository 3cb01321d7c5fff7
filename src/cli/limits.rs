//! Plausible ranges of the numeric options, checked by clap before any work starts: the error
//! names the option (`invalid value '-5' for '--periods <N>': ...`) and `--help` shows each range.
//! The ranges keep time and memory bounded (grid sizes, kept periods, harmonics, points); the
//! library checks the same limits for its own callers.

use std::ops::RangeInclusive;

/// A value parser for an `f64` option in `[lo, hi]` (`lo_open`: `lo` itself excluded).
pub fn real(
    lo: f64,
    hi: f64,
    lo_open: bool,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a number"))?;
        let low = if lo_open { v <= lo } else { v < lo };
        if !v.is_finite() || low || v > hi {
            let open = if lo_open { "(" } else { "[" };
            return Err(format!("must be a finite number in {open}{lo}, {hi}]"));
        }
        Ok(v)
    }
}

/// A value parser for a whole-number option in `range` (`1e3` is accepted as 1000).
pub fn whole(
    range: RangeInclusive<usize>,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let (lo, hi) = (*range.start(), *range.end());
        let msg = || format!("must be a whole number in [{lo}, {hi}]");
        let v: f64 = s.trim().parse().map_err(|_| msg())?;
        if !(v.is_finite() && v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64) {
            return Err(msg());
        }
        Ok(v as usize)
    }
}

/// Dimensionless mean load F_m.
pub const FM: (f64, f64) = (0.0, 1e4);
/// Dimensionless STE amplitude F_ah.
pub const FAH: (f64, f64) = (0.0, 1e3);
/// Damping ratio zeta: below 1e-3 the transient needs more than the budget of 20000 periods.
pub const ZETA: (f64, f64) = (1e-3, 0.9);
/// Mesh frequency over the natural frequency (the paper: 0.1 to 3).
pub const OMEGA: (f64, f64) = (1e-3, 100.0);
/// Initial displacement and velocity (half backlashes, per unit time).
pub const STATE: f64 = 1e6;
/// DOP853 relative tolerance.
pub const RTOL: (f64, f64) = (1e-14, 1e-2);

/// Parse an `f64` as in [`real`] for a value given inside a compound option (START:STOP:STEP).
pub fn check_range(flag: &str, what: &str, v: f64, (lo, hi): (f64, f64)) -> anyhow::Result<()> {
    if !(v.is_finite() && v >= lo && v <= hi) {
        anyhow::bail!("{flag}: {what} {v} must be a finite number in [{lo}, {hi}]");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers_check_ranges() {
        let p = real(0.0, 1.0, true);
        assert!(p("0").is_err() && p("nan").is_err() && p("1.5").is_err() && p("x").is_err());
        assert_eq!(p("0.5"), Ok(0.5));
        let w = whole(1..=10);
        assert_eq!(w("1e1"), Ok(10));
        assert!(w("-5").is_err() && w("1e12").is_err() && w("2.5").is_err() && w("0").is_err());
    }
}
