//! The bifurcation diagram drawn (attractors, chaotic attractors, chaotic transients and the
//! carried sweep as separate series; folds and period doublings as marked vertical lines) and
//! its CSV.

use super::{Bifurcation, BifurcationPoint, Parameter, Source};
use crate::plot::{Marker, Series, XyPlot};
use crate::sim::SetKind;

/// Which series a point belongs to (drawn in this order: the carried sweep underneath).
fn series_of(p: &BifurcationPoint) -> usize {
    match (p.source, p.kind, p.period) {
        (Source::Carried, _, _) => 0,
        (Source::Grid, SetKind::Attractor, Some(_)) => 1,
        (Source::Grid, SetKind::Attractor, None) => 2,
        (Source::Grid, _, _) => 3,
    }
}

/// Label, marker and palette colour of each series: grey crosses for the carried sweep, blue
/// circles for periodic attractors, black dots for chaotic attractors, vermillion dots for
/// chaotic transients.
const STYLE: [(&str, Marker, usize); 4] = [
    ("carried sweep", Marker::Cross, 9),
    ("periodic attractor", Marker::Circle, 0),
    ("chaotic attractor", Marker::Dot, 6),
    ("chaotic transient (trajectories escape)", Marker::Dot, 1),
];

/// The diagram: q at forcing phase 0 against the parameter.
pub fn bifurcation_figure(b: &Bifurcation, title: &str, caption: &str) -> XyPlot {
    let mut groups: [Vec<(f64, f64)>; 4] = Default::default();
    for p in &b.points {
        groups[series_of(p)].push((p.value, p.state[0]));
    }
    let series = groups
        .into_iter()
        .zip(STYLE)
        .filter(|(pts, _)| !pts.is_empty())
        .map(|(pts, (label, marker, color))| {
            Series::markers(label, pts)
                .with_marker(marker)
                .with_color(color)
        })
        .collect();
    let vlines = b
        .marks
        .iter()
        .map(|m| {
            let short = match m.what.as_str() {
                "fold" => "F",
                "period doubling" => "PD",
                "jump" => "J",
                _ => "P",
            };
            (
                m.value,
                format!("{short}{}", if m.source == "aft" { "" } else { "*" }),
            )
        })
        .collect();
    XyPlot {
        title: title.into(),
        caption: Some(if b.marks.is_empty() {
            caption.to_string()
        } else {
            format!(
                "{caption}; F, PD: AFT fold, period doubling; J*, PD*, P*: carried jump, doubling, period change"
            )
        }),
        x_label: format!("{} (dimensionless)", b.parameter.label()),
        y_label: "q at forcing phase 0 (Poincaré section)".into(),
        series,
        vlines,
        ..XyPlot::default()
    }
}

/// Two CSV tables: the points (`parameter,value,q,v,source,set,kind,period,impact,motion`) and
/// the marks (`parameter,value,what,source`).
pub fn bifurcation_csv(b: &Bifurcation) -> (String, String) {
    let name = match b.parameter {
        Parameter::Omega => "omega",
        Parameter::Fhat => "fhat",
        Parameter::Zeta => "zeta",
    };
    let mut points = String::from("parameter,value,q,v,source,set,kind,period,impact,motion\n");
    for p in &b.points {
        points.push_str(&format!(
            "{name},{},{:.10},{:.10},{},{},{},{},{},{}\n",
            p.value,
            p.state[0],
            p.state[1],
            match p.source {
                Source::Grid => "grid",
                Source::Carried => "carried",
            },
            p.set,
            p.kind.name(),
            p.period.map_or(String::new(), |k| k.to_string()),
            p.impact.name(),
            p.motion.name(),
        ));
    }
    let mut marks = String::from("parameter,value,what,source\n");
    for m in &b.marks {
        // A simulation's mark is the midpoint of two grid values, an AFT mark where the
        // continuation located it: ten digits say where without the rounding noise of a
        // midpoint (1.2350000000000001).
        let value = crate::numeric::to_significant(m.value, 10);
        marks.push_str(&format!("{name},{value},{},{}\n", m.what, m.source));
    }
    (points, marks)
}
