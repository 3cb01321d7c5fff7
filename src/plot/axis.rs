//! Linear axes with our own tick placement and labels. Plotters' f64 axis collapses to a single
//! tick when the span is below machine epsilon (e.g. residuals of 1e-18), so figures use
//! [`LinAxis`] instead.

use std::ops::Range;

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, TextStyle};

use super::output::msg;

/// At most `max_n` ticks at multiples of 1, 2 or 5 times a power of ten inside `[lo, hi]`.
pub(crate) fn nice_ticks(lo: f64, hi: f64, max_n: usize) -> Vec<f64> {
    let span = hi - lo;
    if max_n == 0 || !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    let base = 10f64.powf((span / max_n as f64).log10().floor());
    for step in [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0].map(|m| m * base) {
        // The tolerance keeps ticks that sit on the ends up to rounding (-0.3 / 0.1 > -3).
        let (first, last) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
        if !(first.is_finite() && last.is_finite()) {
            break;
        }
        if last - first + 1.0 <= max_n as f64 {
            let count = (last - first).max(-1.0) as i64 + 1;
            return (0..count).map(|k| (first + k as f64) * step).collect();
        }
    }
    vec![lo, hi]
}

/// Formats tick values: a fixed number of decimals suited to the tick spacing, or scientific
/// notation for very large or very small values.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TickFormat {
    decimals: usize,
    scientific: bool,
    zero: f64,
}

impl TickFormat {
    /// Format for the ticks of `range` with spacing `step`.
    fn new(range: (f64, f64), step: f64) -> Self {
        let mag = range.0.abs().max(range.1.abs());
        // Steps are 1, 2 or 5 times a power of ten; the nudge absorbs rounding in the log.
        let exp = |v: f64| {
            if v > 0.0 {
                (v.log10() + 1e-9).floor()
            } else {
                0.0
            }
        };
        let scientific = mag >= 1e5 || (mag > 0.0 && mag < 1e-3);
        let decimals = if scientific {
            exp(mag) - exp(step)
        } else {
            -exp(step)
        };
        TickFormat {
            decimals: decimals.clamp(0.0, 15.0) as usize,
            scientific,
            zero: step * 1e-6,
        }
    }

    /// The same format with one more decimal, for values between ticks (legend notes).
    fn finer(self) -> Self {
        TickFormat {
            decimals: (self.decimals + 1).min(15),
            ..self
        }
    }

    pub fn format(&self, v: f64) -> String {
        let v = if v.abs() < self.zero { 0.0 } else { v };
        match (self.scientific, v == 0.0) {
            (true, true) => "0".to_string(),
            (true, false) => format!("{:.*e}", self.decimals, v),
            (false, _) => format!("{:.*}", self.decimals, v),
        }
    }
}

/// A linear axis over `[lo, hi]` whose labels are formatted for about `n` ticks.
#[derive(Debug, Clone)]
pub(crate) struct LinAxis {
    lo: f64,
    hi: f64,
    n: usize,
    fmt: TickFormat,
}

impl LinAxis {
    /// Axis over `range` (lo < hi) labelled with at most `n` ticks.
    pub fn new(range: (f64, f64), n: usize) -> Self {
        let ticks = nice_ticks(range.0, range.1, n);
        let step = match ticks.as_slice() {
            [a, b, ..] => b - a,
            _ => (range.1 - range.0) / n.max(1) as f64,
        };
        LinAxis {
            lo: range.0,
            hi: range.1,
            n,
            fmt: TickFormat::new(range, step.abs()),
        }
    }

    /// `v` formatted like the tick labels with one more decimal, its trailing zeros dropped
    /// (a speed on a 100 rpm grid reads "2600", not "2600.0").
    pub fn format_between(&self, v: f64) -> String {
        let fmt = self.fmt.finer();
        let s = fmt.format(v);
        if fmt.scientific || !s.contains('.') {
            return s;
        }
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }

    /// Pixel width of the widest tick label in `style`.
    pub fn widest_label<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        style: &TextStyle,
    ) -> Result<u32, String> {
        let mut w = 0;
        for v in nice_ticks(self.lo, self.hi, self.n) {
            w = w.max(
                area.estimate_text_size(&self.fmt.format(v), style)
                    .map_err(msg)?
                    .0,
            );
        }
        Ok(w)
    }
}

impl Ranged for LinAxis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        let px = f64::from(limit.0) + t * f64::from(limit.1 - limit.0);
        if px.is_nan() {
            return limit.0;
        }
        // Far-off values are clamped so the pixel arithmetic of plotters cannot overflow.
        px.round().clamp(-1e8, 1e8) as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        nice_ticks(self.lo, self.hi, hint.max_num_points())
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for LinAxis {
    fn format_ext(&self, v: &f64) -> String {
        self.fmt.format(*v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(range: (f64, f64), n: usize) -> Vec<String> {
        let axis = LinAxis::new(range, n);
        nice_ticks(range.0, range.1, n)
            .iter()
            .map(|v| axis.format_ext(v))
            .collect()
    }

    #[test]
    fn ticks_are_round_and_few() {
        assert_eq!(labels((0.0, 2.0), 5), ["0.0", "0.5", "1.0", "1.5", "2.0"]);
        assert_eq!(
            labels((-0.3, 0.3), 9),
            ["-0.3", "-0.2", "-0.1", "0.0", "0.1", "0.2", "0.3"]
        );
        assert_eq!(
            labels((0.0, 100.0), 8),
            ["0", "20", "40", "60", "80", "100"]
        );
        assert_eq!(labels((0.0, 3e-5), 6), ["0", "1e-5", "2e-5", "3e-5"]);
        assert_eq!(labels((0.0, 2e6), 3), ["0", "1e6", "2e6"]);
        assert_eq!(labels((-1e-20, 1e-19), 6)[0], "0");
        assert!(nice_ticks(0.0, 1e-19, 6).len() >= 3);
        assert!(nice_ticks(-1e307, 1e307, 8).len() <= 8);
        assert!(nice_ticks(1.0, 1.0, 8).is_empty());
    }

    /// Values between ticks carry one decimal more than the ticks, and no trailing zeros.
    #[test]
    fn values_between_ticks() {
        let rpm = LinAxis::new((1000.0, 5000.0), 8);
        assert_eq!(rpm.format_between(2600.0), "2600");
        assert_eq!(rpm.format_between(2650.25), "2650.2");
        let omega = LinAxis::new((0.0, 2.0), 5);
        assert_eq!(omega.format_between(1.5), "1.5");
        assert_eq!(omega.format_between(1.234), "1.23");
        assert_eq!(omega.format_between(1.0), "1");
    }
}
