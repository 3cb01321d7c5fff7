//! A profile modification given point by point on each flank (a measured deviation or a drawn
//! modification, e.g. from a profile inspection), added to the unloaded separation of the pairs
//! ([`super::ste`]) beside or instead of the analytic [`super::TipRelief`].
//!
//! A point (diameter d, relief a) of a gear with base radius r_b lies at roll distance
//! rho = sqrt((d/2)^2 - r_b^2) on its own base circle; the pair at roll distance s from T1 touches
//! the pinion at rho_1 = s and the gear at rho_2 = T1T2 - s, and its separation gains
//! a_1(rho_1) + a_2(rho_2), each linearly interpolated in rho. The relief is along the line of
//! action (the normal to the involute), positive for material removed.

use super::geometry::GearPairGeometry;
use serde::Serialize;

/// Slack in the coverage check, metres of roll distance (a diameter read to 0.01 mm).
const COVER_SLACK_M: f64 = 1e-5;

/// Why a table's points do not fit the pair: which gear, which of its points (`None`: its points
/// as a whole) and the reason, so that the caller can name the table's line.
#[derive(Clone, Debug, PartialEq)]
pub struct TableProblem {
    /// "pinion" or "gear".
    pub gear: &'static str,
    /// Index of the point among that gear's, or `None`.
    pub point: Option<usize>,
    pub reason: String,
}

impl std::fmt::Display for TableProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "profile table: {}", self.reason)
    }
}

/// Relief against roll distance on each gear, metres both.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProfileDeviation {
    /// Pinion: (rho_1, relief), rho increasing; empty for none.
    pub pinion: Vec<(f64, f64)>,
    /// Gear: (rho_2, relief), rho increasing; empty for none.
    pub gear: Vec<(f64, f64)>,
}

impl ProfileDeviation {
    /// From each gear's (diameter mm, relief um) points in increasing diameter (none: no
    /// deviation of that gear). Every point must lie outside the base circle, and a gear's
    /// points must cover the part of its flank in contact ([`TableProblem`] naming the point or
    /// the diameters otherwise).
    pub fn from_diameters(
        geo: &GearPairGeometry,
        pinion: &[(f64, f64)],
        gear: &[(f64, f64)],
    ) -> std::result::Result<Self, TableProblem> {
        let (sa, se) = (geo.start_of_contact(), geo.end_of_contact());
        let t = geo.line_of_action_length();
        let convert = |name: &'static str, rb: f64, pts: &[(f64, f64)], need: (f64, f64)| {
            let mut out = Vec::with_capacity(pts.len());
            for (i, &(d_mm, a_um)) in pts.iter().enumerate() {
                let r = d_mm * 1e-3 / 2.0;
                if !r.is_finite() || r <= rb {
                    return Err(TableProblem {
                        gear: name,
                        point: Some(i),
                        reason: format!(
                            "the {name} point at {d_mm} mm lies inside its base circle ({:.3} \
                             mm), where there is no involute",
                            2e3 * rb
                        ),
                    });
                }
                out.push(((r * r - rb * rb).sqrt(), a_um * 1e-6));
            }
            if let (Some(first), Some(last)) = (out.first(), out.last()) {
                if first.0 > need.0 + COVER_SLACK_M || last.0 < need.1 - COVER_SLACK_M {
                    let d = |rho: f64| 2e3 * (rho * rho + rb * rb).sqrt();
                    return Err(TableProblem {
                        gear: name,
                        point: None,
                        reason: format!(
                            "the {name} rows cover diameters {:.3} to {:.3} mm, but its flank is \
                             in contact from {:.3} to {:.3} mm: extend the table",
                            d(first.0),
                            d(last.0),
                            d(need.0),
                            d(need.1)
                        ),
                    });
                }
            }
            Ok(out)
        };
        Ok(ProfileDeviation {
            pinion: convert("pinion", geo.pinion.base_radius_m, pinion, (sa, se))?,
            gear: convert("gear", geo.gear.base_radius_m, gear, (t - se, t - sa))?,
        })
    }

    /// Whether no point is given.
    pub fn is_empty(&self) -> bool {
        self.pinion.is_empty() && self.gear.is_empty()
    }

    /// Separation (m) the table adds to the pair at roll distance `s` from T1.
    pub fn separation(&self, geo: &GearPairGeometry, s: f64) -> f64 {
        interpolate(&self.pinion, s) + interpolate(&self.gear, geo.line_of_action_length() - s)
    }
}

/// Linear interpolation in increasing `x` (clamped at the ends; 0 for no points).
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    match points {
        [] => 0.0,
        [only] => only.1,
        _ => {
            let i = points
                .partition_point(|p| p.0 < x)
                .clamp(1, points.len() - 1);
            let ((x0, y0), (x1, y1)) = (points[i - 1], points[i]);
            let w = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
            y0 + w * (y1 - y0)
        }
    }
}
