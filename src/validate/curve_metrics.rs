//! Comparisons of a predicted curve with a measured one: RMS error and jump locations.

/// Root-mean-square of the differences.
pub fn rms(diffs: &[f64]) -> f64 {
    if diffs.is_empty() {
        return f64::NAN;
    }
    (diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64).sqrt()
}

/// Speed of the steepest transition of a curve (sorted by speed): the first step between
/// consecutive points that exceeds `factor` times the median step and a quarter of the largest
/// step; the midpoint speed is returned. A jump, or the steep flank of a resonance, alike: the
/// "transition frequency" of Kubo's envelope (Fig. 23), whose heavily damped response rises
/// steeply without hysteresis. [`jump_location`] is the stricter test for a jump.
pub fn transition_location(curve: &[(f64, f64)], factor: f64) -> Option<f64> {
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

/// Speed of the first jump of a curve (sorted by speed), the midpoint of the step; None when
/// the curve has none. A step d_i = y_(i+1) - y_i is a jump when
///
/// 1. it exceeds `factor` times the median of the steps before it (at least the curve's first
///    four): noise and smooth slopes stay below, and the scatter of chaotic speeds after a
///    first jump does not raise the bar for that jump, and
/// 2. the curve is smooth on one side of it and keeps its level on the other: either the two
///    steps before it are each below |d_i| / 2 and the next two points stay beyond the step's
///    midpoint (y_i + y_(i+1)) / 2 on the new side (a jump onto a new branch, smooth or not
///    after it), or the mirror image (the two steps after it small, the two points before it
///    on the old side), and
/// 3. the step is not part of a steep flank: the neighbouring step on the side that keeps its
///    level is not in the same direction with half its size or more.
///
/// A resonance peak sampled on a coarse grid has large steps too, but its flanks rise in
/// several comparable steps (3 fails) and fall back across the midpoint right after the top
/// (2 fails), so a linear, in-contact curve has no jump.
pub fn jump_location(curve: &[(f64, f64)], factor: f64) -> Option<f64> {
    if curve.len() < 4 {
        return None;
    }
    let y: Vec<f64> = curve.iter().map(|p| p.1).collect();
    let d: Vec<f64> = y.windows(2).map(|w| w[1] - w[0]).collect();
    let median_before = |i: usize| {
        let mut sizes: Vec<f64> = d[..i.max(4).min(d.len())].iter().map(|s| s.abs()).collect();
        sizes.sort_by(f64::total_cmp);
        sizes[sizes.len() / 2].max(1e-12)
    };
    let small =
        |j: Option<usize>, big: f64| j.and_then(|j| d.get(j)).is_none_or(|s| s.abs() < 0.5 * big);
    let flank = |j: Option<usize>, di: f64| {
        j.and_then(|j| d.get(j))
            .is_some_and(|s| s.signum() == di.signum() && s.abs() >= 0.5 * di.abs())
    };
    (0..d.len()).find_map(|i| {
        let di = d[i];
        if di.abs() <= factor * median_before(i) {
            return None;
        }
        let mid = 0.5 * (y[i] + y[i + 1]);
        let new_side = |v: f64| (v - mid) * di > 0.0;
        let old_side = |v: f64| (v - mid) * di < 0.0;
        // Smooth before, new level kept after (y_(i+1), y_(i+2), y_(i+3)).
        let after: Vec<f64> = y.iter().skip(i + 1).take(3).copied().collect();
        let forward = i >= 1
            && small(i.checked_sub(1), di.abs())
            && small(i.checked_sub(2), di.abs())
            && after.len() >= 2
            && after.iter().all(|&v| new_side(v))
            && !flank(Some(i + 1), di);
        // Smooth after, old level kept before (y_i, y_(i-1), y_(i-2)).
        let before: Vec<f64> = y[..=i].iter().rev().take(3).copied().collect();
        let backward = i + 1 < d.len()
            && small(Some(i + 1), di.abs())
            && small(Some(i + 2), di.abs())
            && before.len() >= 2
            && before.iter().all(|&v| old_side(v))
            && !flank(i.checked_sub(1), di);
        (forward || backward).then(|| 0.5 * (curve[i].0 + curve[i + 1].0))
    })
}

/// Speed spacing of the step of `curve` (sorted by speed) whose midpoint is `x`, as
/// [`jump_location`] and [`transition_location`] return it: a jump lies somewhere within that
/// step, so its speed is known to half of it.
fn step_width_at(curve: &[(f64, f64)], x: f64) -> Option<f64> {
    curve
        .windows(2)
        .find(|w| (0.5 * (w[0].0 + w[1].0) - x).abs() <= 1e-9 * x.abs().max(1.0))
        .map(|w| w[1].0 - w[0].0)
}

/// The model's step location `at_model` on `model` less the measured one `at_measured` on
/// `measured` (None unless both curves have one), and how finely the two grids place that
/// difference: half of each curve's speed step there.
pub fn location_error(
    (measured, at_measured): (&[(f64, f64)], Option<f64>),
    (model, at_model): (&[(f64, f64)], Option<f64>),
) -> (Option<f64>, Option<f64>) {
    let Some((m, u)) = at_measured.zip(at_model) else {
        return (None, None);
    };
    let resolution = step_width_at(measured, m)
        .zip(step_width_at(model, u))
        .map(|(a, b)| 0.5 * (a + b));
    (Some(u - m), resolution)
}

/// A location error as "8 ± 42" followed by `unit`, or without the ± when the resolution is
/// unknown.
pub fn location_error_text(error: f64, resolution: Option<f64>, unit: &str) -> String {
    match resolution {
        Some(r) => format!("{error:.0} ± {r:.0}{unit}"),
        None => format!("{error:.0}{unit}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A lightly damped linear resonance on a coarse grid (the design load of data/munro:
    /// zeta 0.0175, 50 rpm steps, peak 17 um from a 0.6 um floor) is not a jump, at any
    /// placement of the grid against the peak; the same curve with the jump of a nonlinear
    /// branch (data/munro's 1890 N curve: 17.7 -> 29.1 um, then slowly falling) is.
    #[test]
    fn a_sampled_resonance_is_not_a_jump_but_a_branch_jump_is() {
        use super::super::linear::dte_pp_um;
        for offset in [0.0, 10.0, 25.0, 40.0] {
            let curve: Vec<(f64, f64)> = (0..81)
                .map(|i| {
                    let rpm = 1000.0 + offset + 50.0 * i as f64;
                    let om = rpm * 32.0 / 60.0 / 1600.0;
                    (rpm, dte_pp_um(0.3, 0.0175, om))
                })
                .collect();
            assert_eq!(jump_location(&curve, 6.0), None, "offset {offset}");
        }
        let branch = [
            5.6, 5.7, 5.8, 6.2, 6.6, 7.1, 7.9, 8.7, 9.8, 10.9, 12.0, 14.0, 16.1, 17.7, 29.1, 27.4,
            26.4, 24.9, 23.5, 22.2, 21.3, 20.3, 19.5, 18.2,
        ];
        let curve: Vec<(f64, f64)> = branch
            .iter()
            .enumerate()
            .map(|(i, &v)| (2000.0 + 50.0 * i as f64, v))
            .collect();
        assert_eq!(jump_location(&curve, 6.0), Some(2675.0));
        // A jump down after a smooth plateau (a down-sweep leaving a branch).
        let down: Vec<(f64, f64)> = [
            9.0, 9.5, 10.0, 10.4, 10.9, 11.3, 3.1, 3.0, 2.9, 2.8, 2.7, 2.6,
        ]
        .iter()
        .enumerate()
        .map(|(i, &v)| (i as f64, v))
        .collect();
        assert_eq!(jump_location(&down, 6.0), Some(5.5));
    }

    /// A light load's curve (500 N, STE 3.5 um, made by `geardyn synth munro` with 0.1 um
    /// noise): a first jump at 1800 -> 1850 rpm (11.0 -> 18.6 um), then chaotic speeds whose
    /// points scatter by tens of um from 2700 rpm. The first jump is found, not the chaos.
    #[test]
    fn the_first_jump_is_found_before_a_chaotic_stretch() {
        let y = [
            7.85, 7.99, 8.11, 8.13, 8.19, 8.58, 8.67, 8.67, 9.11, 9.31, 9.34, 9.64, 9.83, 10.29,
            10.29, 10.73, 11.02, 18.57, 17.47, 16.61, 15.54, 14.79, 14.01, 13.44, 12.67, 12.0,
            11.3, 10.87, 13.4, 15.1, 16.02, 16.55, 17.02, 16.94, 51.24, 24.97, 65.37, 61.25, 86.28,
            85.71, 85.16, 16.43, 53.29, 86.89, 87.53, 85.57, 87.7, 83.66, 84.92, 80.5, 83.15,
            81.82, 75.15, 72.38, 99.74, 99.16, 68.41, 63.84, 96.91, 95.61, 93.48, 88.9, 89.36,
            87.12, 88.28, 89.87, 85.61, 82.39, 82.12, 81.38, 77.17, 99.32, 97.07, 75.88, 73.84,
            73.48, 63.66, 60.71, 88.93, 93.41, 60.38,
        ];
        let curve: Vec<(f64, f64)> = y
            .iter()
            .enumerate()
            .map(|(i, &v)| (1000.0 + 50.0 * i as f64, v))
            .collect();
        assert_eq!(jump_location(&curve, 6.0), Some(1825.0));
    }

    #[test]
    fn a_location_error_carries_half_of_each_grid_step() {
        let measured: Vec<(f64, f64)> = (0..10).map(|i| (1000.0 + 50.0 * i as f64, 0.0)).collect();
        let model: Vec<(f64, f64)> = (0..20).map(|i| (1000.0 + 25.0 * i as f64, 0.0)).collect();
        // Midpoints of the 1200-1250 rpm step of the data and the 1250-1275 step of the model.
        let (e, r) = location_error((&measured, Some(1225.0)), (&model, Some(1262.5)));
        assert_eq!((e, r), (Some(37.5), Some(37.5)));
        assert_eq!(location_error_text(37.5, r, " rpm"), "38 ± 38 rpm");
        // A location that is no step's midpoint has no resolution; no model location, no error.
        let (e, r) = location_error((&measured, Some(1230.0)), (&model, Some(1262.5)));
        assert_eq!((e, r), (Some(32.5), None));
        assert_eq!(
            location_error((&measured, Some(1225.0)), (&model, None)),
            (None, None)
        );
    }
}
