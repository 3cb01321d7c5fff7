//! Shared figure pieces of the studies and of the comparison: continuation branches drawn solid
//! where stable and dashed where unstable, describing-function points by impact case, and the
//! figure/CSV containers written by [`super::write_outputs`].

use crate::model::Impact;
use crate::plot::{Marker, Series, XyPlot};

/// One figure: a grid of panels written as `name.png` and `name.svg`.
#[derive(Clone, Debug)]
pub struct Figure {
    /// File stem.
    pub name: String,
    /// Common title above the panels.
    pub title: String,
    /// The panels, row by row.
    pub panels: Vec<XyPlot>,
    /// Panels per row.
    pub cols: usize,
}

/// A branch traced in order, as (Omega, value, stability): runs of equal stability become
/// separate series, solid when stable (or unknown) and dashed when unstable; only the first run
/// of each kind carries a legend label (none when `label` is empty).
pub fn branch_series(
    points: &[(f64, f64, Option<bool>)],
    label: &str,
    color: usize,
) -> Vec<Series> {
    let mut out = Vec::new();
    let (mut seen_stable, mut seen_unstable) = (false, false);
    let mut start = 0;
    while start < points.len() {
        let unstable = points[start].2 == Some(false);
        let mut end = start + 1;
        while end < points.len() && (points[end].2 == Some(false)) == unstable {
            end += 1;
        }
        // Include the next point so that consecutive runs join.
        let stop = (end + 1).min(points.len());
        let pts: Vec<(f64, f64)> = points[start..stop].iter().map(|p| (p.0, p.1)).collect();
        let name = if label.is_empty() {
            String::new()
        } else if unstable && !seen_unstable {
            seen_unstable = true;
            format!("{label} (unstable)")
        } else if !unstable && !seen_stable {
            seen_stable = true;
            label.to_string()
        } else {
            String::new()
        };
        let s = if unstable {
            Series::dashed(name, pts)
        } else {
            Series::line(name, pts)
        };
        out.push(s.with_color(color));
        start = end;
    }
    out
}

/// Describing-function (or any multi-valued) points as markers, one series per impact case
/// (Fig. 10): `rows` are (Omega, value, case, stable); unstable points get crosses.
pub fn case_markers(rows: &[(f64, f64, Impact, Option<bool>)], prefix: &str) -> Vec<Series> {
    let mut out: Vec<Series> = [Impact::None, Impact::Single, Impact::Double]
        .iter()
        .enumerate()
        .map(|(i, &imp)| {
            let pts = rows
                .iter()
                .filter(|r| r.2 == imp && r.3 != Some(false))
                .map(|r| (r.0, r.1))
                .collect();
            Series::markers(format!("{prefix}case {}", imp.roman()), pts)
                .with_color(i)
                .with_marker([Marker::Square, Marker::Triangle, Marker::Circle][i])
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    let unstable: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.3 == Some(false))
        .map(|r| (r.0, r.1))
        .collect();
    if !unstable.is_empty() {
        out.push(
            Series::markers(format!("{prefix}unstable"), unstable)
                .with_color(7)
                .with_marker(Marker::Cross),
        );
    }
    out
}

/// A panel with the given series against Omega_h; `y_label` names a dimensionless quantity.
pub fn panel(title: String, caption: String, y_label: &str, series: Vec<Series>) -> XyPlot {
    XyPlot {
        title,
        caption: Some(caption),
        x_label: "Ω_h (dimensionless)".into(),
        y_label: format!("{y_label} (dimensionless)"),
        series,
        ..XyPlot::default()
    }
}
