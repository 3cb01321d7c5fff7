//! Axis calibration: the linear (or log10) map between a pixel coordinate and a data value,
//! fixed by two known points on the axis (e.g. two tick marks).

use crate::error::{GearError, Result};

/// Two known points of one axis: pixel `p1` shows value `v1` and pixel `p2` shows value `v2`.
///
/// With `log = true` the axis is logarithmic: log10 of the value is linear in the pixel, and both
/// values must be positive. Pixel coordinates are those an image viewer shows (column for the
/// x axis, row counted from the top for the y axis); fractional pixels are allowed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisCalibration {
    /// Pixel coordinate of the first known point.
    pub p1: f64,
    /// Data value at `p1`.
    pub v1: f64,
    /// Pixel coordinate of the second known point.
    pub p2: f64,
    /// Data value at `p2`.
    pub v2: f64,
    /// Logarithmic (log10) axis.
    pub log: bool,
}

impl AxisCalibration {
    /// A validated calibration (see [`AxisCalibration::validate`]).
    pub fn new(p1: f64, v1: f64, p2: f64, v2: f64, log: bool) -> Result<Self> {
        let c = AxisCalibration {
            p1,
            v1,
            p2,
            v2,
            log,
        };
        c.validate()?;
        Ok(c)
    }

    /// Checks that all four numbers are finite, the two pixels differ, the two values differ,
    /// and, on a log axis, that both values are positive.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("p1", self.p1),
            ("v1", self.v1),
            ("p2", self.p2),
            ("v2", self.v2),
        ] {
            if !v.is_finite() {
                return Err(GearError::param(
                    name,
                    v,
                    "calibration numbers must be finite",
                ));
            }
        }
        if self.p1 == self.p2 {
            return Err(GearError::param(
                "p2",
                self.p2,
                "the two calibration pixels must differ",
            ));
        }
        if self.v1 == self.v2 {
            return Err(GearError::param(
                "v2",
                self.v2,
                "the two calibration values must differ",
            ));
        }
        if self.log {
            for (name, v) in [("v1", self.v1), ("v2", self.v2)] {
                if v <= 0.0 {
                    return Err(GearError::param(
                        name,
                        v,
                        "values on a log axis must be positive",
                    ));
                }
            }
        }
        Ok(())
    }

    /// The values in the space where the axis is linear (log10 on a log axis).
    fn linear_values(&self) -> (f64, f64) {
        if self.log {
            (self.v1.log10(), self.v2.log10())
        } else {
            (self.v1, self.v2)
        }
    }

    /// Data value shown at `pixel` (linear interpolation / extrapolation through the two points,
    /// in log10 space on a log axis).
    pub fn to_value(&self, pixel: f64) -> f64 {
        let (a, b) = self.linear_values();
        let t = a + (pixel - self.p1) * (b - a) / (self.p2 - self.p1);
        if self.log {
            10f64.powf(t)
        } else {
            t
        }
    }

    /// Pixel coordinate of data value `value` (the inverse of [`AxisCalibration::to_value`]);
    /// NaN for a non-positive value on a log axis.
    pub fn to_pixel(&self, value: f64) -> f64 {
        let (a, b) = self.linear_values();
        let v = if self.log {
            if value > 0.0 {
                value.log10()
            } else {
                return f64::NAN;
            }
        } else {
            value
        };
        self.p1 + (v - a) * (self.p2 - self.p1) / (b - a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_axis_maps_both_ways() {
        // y axis: row 400 is 0, row 100 is 30 (rows grow downwards).
        let c = AxisCalibration::new(400.0, 0.0, 100.0, 30.0, false).unwrap();
        assert_eq!(c.to_value(400.0), 0.0);
        assert_eq!(c.to_value(100.0), 30.0);
        assert!((c.to_value(250.0) - 15.0).abs() < 1e-12);
        assert!((c.to_value(500.0) + 10.0).abs() < 1e-12);
        assert!((c.to_pixel(15.0) - 250.0).abs() < 1e-12);
    }

    #[test]
    fn log_axis_is_linear_in_decades() {
        let c = AxisCalibration::new(0.0, 1.0, 200.0, 100.0, true).unwrap();
        assert!((c.to_value(100.0) - 10.0).abs() < 1e-12);
        assert!((c.to_value(300.0) - 1000.0).abs() < 1e-9);
        assert!((c.to_pixel(10.0) - 100.0).abs() < 1e-12);
        assert!(c.to_pixel(-1.0).is_nan());
    }

    #[test]
    fn bad_calibrations_are_rejected() {
        let bad = [
            (1.0, 0.0, 1.0, 5.0, false),
            (1.0, 5.0, 2.0, 5.0, false),
            (1.0, 0.0, 2.0, 5.0, true),
            (1.0, -1.0, 2.0, 5.0, true),
            (f64::NAN, 0.0, 2.0, 5.0, false),
            (1.0, 0.0, 2.0, f64::INFINITY, false),
        ];
        for (p1, v1, p2, v2, log) in bad {
            assert!(AxisCalibration::new(p1, v1, p2, v2, log).is_err());
        }
    }
}
