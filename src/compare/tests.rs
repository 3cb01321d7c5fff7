//! Matching logic on hand-made points.

use super::*;
use crate::sim::Motion;

fn sim(source: Source, omega: f64, qa: f64, period: Option<u32>) -> ComparePoint {
    ComparePoint {
        source,
        omega,
        qa,
        qm: 1.0,
        case: Impact::None,
        stable: Some(true),
        period,
        motion: Some(if period.is_some() {
            Motion::Periodic
        } else {
            Motion::Chaotic
        }),
        basin_fraction: None,
    }
}

fn aft(omega: f64, qa: f64, stable: bool) -> ComparePoint {
    ComparePoint::hb(Source::AftGrid, omega, qa, 1.0, Some(stable))
}

#[test]
fn matches_within_tolerance_and_reports_both_sides() {
    let pts = vec![
        aft(0.7, 0.10, true),
        aft(0.7, 0.30, false),
        aft(0.7, 0.50, true),
        sim(Source::SweepUp, 0.7, 0.1005, Some(1)),
        sim(Source::Attractors, 0.7, 0.1005, Some(1)),
        // 0.8% above the upper stable branch: matched at 1%.
        sim(Source::SweepDown, 0.7, 0.504, Some(1)),
        // No AFT point at 0.8: unmatched; the stable AFT 0.9 point has no simulation.
        sim(Source::Attractors, 0.8, 0.2, Some(1)),
        aft(0.9, 0.4, true),
        // Within 1% of an unstable AFT point only: a simulation attractor is matched by any AFT
        // point, so not a gap.
        sim(Source::Attractors, 0.7, 0.301, Some(1)),
        sim(Source::Attractors, 0.9, 0.6, Some(2)),
        sim(Source::Attractors, 0.9, 0.7, None),
        // df points take no part in the matching.
        ComparePoint::hb(Source::DfExact, 0.8, 0.2, 1.0, Some(true)),
    ];
    let g = gaps(&pts, 0.01);
    assert_eq!(g.matched.len(), 2);
    assert!(g.matched.iter().all(|m| m.rel <= 0.01));
    assert_eq!(g.sim_unmatched.len(), 1);
    assert_eq!(g.sim_unmatched[0].omega, 0.8);
    assert_eq!(g.sim_unmatched[0].nearest_rel, None);
    assert_eq!(g.aft_unreached.len(), 1);
    assert_eq!(g.aft_unreached[0].omega, 0.9);
    // The period-1 simulation at 0.9 does not exist; the period-2 and chaotic ones are reported.
    assert_eq!(g.non_period1.len(), 2);
    let lines = g.summary_lines();
    assert_eq!(lines.len(), 4);
    assert!(lines[1].contains("0.800"));
}

#[test]
fn duplicate_simulation_points_are_merged_with_their_sources() {
    let pts = vec![
        sim(Source::SweepUp, 0.5, 0.2, Some(1)),
        sim(Source::Attractors, 0.5, 0.2 + 1e-9, Some(1)),
    ];
    let g = gaps(&pts, 0.01);
    assert_eq!(g.sim_unmatched.len(), 1);
    assert_eq!(
        g.sim_unmatched[0].sources,
        vec![Source::SweepUp, Source::Attractors]
    );
}

#[test]
fn just_outside_tolerance_is_a_gap() {
    let pts = vec![
        aft(1.0, 1.0, true),
        sim(Source::Attractors, 1.0, 1.0102, Some(1)),
    ];
    let g = gaps(&pts, 0.01);
    assert!(g.matched.is_empty());
    assert_eq!(g.sim_unmatched.len(), 1);
    assert_eq!(g.aft_unreached.len(), 1);
    let r = g.sim_unmatched[0].nearest_rel.unwrap_or(0.0);
    assert!((r - 0.0102 / 1.0102).abs() < 1e-12);
}
