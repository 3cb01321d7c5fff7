//! The backlash non-linearity (eq. 3c) and the impact regimes of Fig. 9.

use serde::{Deserialize, Serialize};

/// Dimensionless mesh force f(q) of eq. 3c: a dead zone of half-width 1 (the half backlash).
#[inline]
pub fn dead_zone(q: f64) -> f64 {
    if q > 1.0 {
        q - 1.0
    } else if q < -1.0 {
        q + 1.0
    } else {
        0.0
    }
}

/// The three linear regions of eq. 3c. In each the equation of motion is linear.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Region {
    /// q > 1: drive-side tooth contact, f = q - 1.
    Contact,
    /// |q| < 1: teeth separated, f = 0.
    Gap,
    /// q < -1: back-side (coast) contact, f = q + 1.
    BackContact,
}

impl Region {
    /// Stiffness multiplier of f in this region (1 in contact, 0 in the gap).
    pub fn kappa(self) -> f64 {
        match self {
            Region::Gap => 0.0,
            _ => 1.0,
        }
    }

    /// Constant c such that f(q) = kappa q - c in this region (eq. 3c).
    pub fn force_offset(self) -> f64 {
        match self {
            Region::Contact => 1.0,
            Region::Gap => 0.0,
            Region::BackContact => -1.0,
        }
    }

    /// The region a state lies in. On a boundary the direction of motion (then the acceleration
    /// sign `a`) decides, so that a trajectory leaving the boundary is assigned the region it enters.
    pub fn of_state(q: f64, v: f64, a: f64) -> Region {
        let dir = if v != 0.0 { v } else { a };
        if q > 1.0 || (q == 1.0 && dir > 0.0) {
            Region::Contact
        } else if q < -1.0 || (q == -1.0 && dir < 0.0) {
            Region::BackContact
        } else {
            Region::Gap
        }
    }
}

/// Impact regime of a steady state (Fig. 9, Sec. 4): case I, II or III of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Impact {
    /// Case I: q > 1 at all times, the teeth never separate.
    None,
    /// Case II: tooth separation (q <= 1 at some time) without back collision (q > -1 always).
    Single,
    /// Case III: back collision, q < -1 at some time.
    Double,
}

impl Impact {
    /// Classify from the extreme values of q over a steady state.
    pub fn from_range(q_min: f64) -> Impact {
        if q_min < -1.0 {
            Impact::Double
        } else if q_min <= 1.0 {
            Impact::Single
        } else {
            Impact::None
        }
    }

    /// The paper's case number (1, 2 or 3).
    pub fn case(self) -> u8 {
        match self {
            Impact::None => 1,
            Impact::Single => 2,
            Impact::Double => 3,
        }
    }

    /// The paper's case number in roman numerals, as its text and figures write it ("I", "II",
    /// "III"); [`Impact::case`] is the number for CSV and JSON.
    pub fn roman(self) -> &'static str {
        match self {
            Impact::None => "I",
            Impact::Single => "II",
            Impact::Double => "III",
        }
    }

    /// Name used in JSON and CSV outputs ("none", "single", "double").
    pub fn name(self) -> &'static str {
        match self {
            Impact::None => "none",
            Impact::Single => "single",
            Impact::Double => "double",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dead_zone_is_continuous_with_unit_slope_outside() {
        assert_eq!(dead_zone(0.3), 0.0);
        assert_eq!(dead_zone(1.0), 0.0);
        assert_eq!(dead_zone(-1.0), 0.0);
        assert!((dead_zone(1.5) - 0.5).abs() < 1e-15);
        assert!((dead_zone(-2.25) + 1.25).abs() < 1e-15);
    }

    #[test]
    fn region_matches_dead_zone() {
        for &q in &[-3.0, -1.2, -0.5, 0.0, 0.9, 1.1, 4.0] {
            let r = Region::of_state(q, 0.0, 0.0);
            assert_eq!(r.kappa() * q - r.force_offset(), dead_zone(q));
        }
        assert_eq!(Region::of_state(1.0, 0.1, 0.0), Region::Contact);
        assert_eq!(Region::of_state(1.0, -0.1, 0.0), Region::Gap);
        assert_eq!(Region::of_state(-1.0, 0.0, -1.0), Region::BackContact);
    }

    #[test]
    fn impact_regimes_follow_fig9() {
        assert_eq!(Impact::from_range(1.05), Impact::None);
        assert_eq!(Impact::from_range(0.2), Impact::Single);
        assert_eq!(Impact::from_range(-1.3), Impact::Double);
        assert_eq!(Impact::Double.case(), 3);
    }
}
