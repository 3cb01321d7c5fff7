//! Frequency ranges read off a describing-function response (Sec. 6): where several solutions
//! coexist (the dual-valued region between the jump frequencies) and where each impact case
//! exists.

use super::df_solve::DfSolution;
use crate::model::Impact;

/// Ranges of a response over a frequency grid; `None` where nothing qualifies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResponseRanges {
    /// First and last grid frequency with more than one solution.
    pub multivalued: Option<(f64, f64)>,
    /// First and last frequency with a case I (no impact) solution.
    pub case_i: Option<(f64, f64)>,
    /// First and last frequency with a case II (single-sided impact) solution.
    pub case_ii: Option<(f64, f64)>,
    /// First and last frequency with a case III (double-sided impact) solution.
    pub case_iii: Option<(f64, f64)>,
    /// Largest number of solutions at one frequency.
    pub max_solutions: usize,
}

/// The ranges of `sols`, solved on the frequencies `omegas`.
pub fn response_ranges(sols: &[DfSolution], omegas: &[f64]) -> ResponseRanges {
    let per_omega = |w: f64| sols.iter().filter(|s| s.omega == w).count();
    let first_last = |ws: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = ws.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), w| {
            (l.min(w), h.max(w))
        });
        (lo <= hi).then_some((lo, hi))
    };
    let span =
        |imp: Impact| first_last(&mut sols.iter().filter(move |s| s.case == imp).map(|s| s.omega));
    ResponseRanges {
        multivalued: first_last(&mut omegas.iter().copied().filter(|&w| per_omega(w) > 1)),
        case_i: span(Impact::None),
        case_ii: span(Impact::Single),
        case_iii: span(Impact::Double),
        max_solutions: omegas.iter().map(|&w| per_omega(w)).max().unwrap_or(0),
    }
}
