//! Overlay of every method (Figs 11-13): q_a and q_m versus Omega.

use super::{Comparison, Source};
use crate::model::OperatingPoint;
use crate::plot::{Marker, Series, XyPlot};
use crate::study::figures::{branch_series, panel};

/// Two panels (q_a, q_m): df-exact markers, the AFT branch (stable solid, unstable dashed),
/// sweeps up and down and every attractor (non-period-1 attractors as crosses). With the rig's
/// operating point `units`, against the pinion speed in rpm with b q_a and b q_m in µm.
pub fn compare_panels(c: &Comparison, units: Option<&OperatingPoint>) -> Vec<XyPlot> {
    let s = &c.settings;
    let torque = crate::model::GearPair::torque_caption(s.fat);
    // Four digits: F_m and F_ah of a rig come from a division and print as 0.14166321519832273.
    let short = |x: f64| crate::numeric::to_significant(x, 4);
    let caption = format!(
        "F_m = {}, F_ah = {} (F_hat = {}){torque}, ζ = {}, AFT H = {}, IC grid {}:{}:{}",
        short(s.fm),
        short(s.fah),
        short(s.fm / s.fah),
        short(s.zeta),
        s.harmonics,
        s.grid.lo,
        s.grid.hi,
        s.grid.n
    );
    let x = |omega: f64| units.map_or(omega, |op| op.speed_rpm(omega));
    let y = |v: f64| units.map_or(v, |op| op.micrometres(v));
    let make = |label: &str, pick: fn(&super::ComparePoint) -> f64| {
        let of = |src: Source, f: &dyn Fn(&super::ComparePoint) -> bool| -> Vec<(f64, f64)> {
            c.points
                .iter()
                .filter(|p| p.source == src && f(p))
                .map(|p| (x(p.omega), y(pick(p))))
                .collect()
        };
        let mut series = vec![
            Series::markers("HB df-exact", of(Source::DfExact, &|_| true))
                .with_color(7)
                .with_marker(Marker::Dot),
        ];
        let branch: Vec<(f64, f64, Option<bool>)> = c
            .points
            .iter()
            .filter(|p| p.source == Source::Aft)
            .map(|p| (x(p.omega), y(pick(p)), p.stable))
            .collect();
        series.extend(branch_series(&branch, "HB AFT", 0));
        series.push(
            Series::markers("sim sweep up", of(Source::SweepUp, &|_| true))
                .with_color(1)
                .with_marker(Marker::Triangle),
        );
        series.push(
            Series::markers("sim sweep down", of(Source::SweepDown, &|_| true))
                .with_color(2)
                .with_marker(Marker::Square),
        );
        series.push(
            Series::markers(
                "sim attractors (period 1)",
                of(Source::Attractors, &|p| p.period == Some(1)),
            )
            .with_color(3)
            .with_marker(Marker::Circle),
        );
        series.push(
            Series::markers(
                "sim attractors (not period 1)",
                of(Source::Attractors, &|p| p.period != Some(1)),
            )
            .with_color(4)
            .with_marker(Marker::Cross),
        );
        let mut p = panel(label.to_string(), caption.clone(), label, series);
        if units.is_some() {
            p.x_label = "pinion speed n (rpm)".into();
            p.y_label = format!("{label} (µm)");
        }
        match (s.omegas.first(), s.omegas.last()) {
            (Some(&lo), Some(&hi)) if hi > lo => p.with_x_range(x(lo), x(hi)),
            _ => p,
        }
    };
    vec![make("q_a", |p| p.qa), make("q_m", |p| p.qm)]
}
