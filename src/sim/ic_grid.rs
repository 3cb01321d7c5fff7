//! Grids of initial conditions (q(0), q'(0)) searched for coexisting steady states (Sec. 3, 5).

use super::flow::State;
use crate::error::{GearError, Result};
use serde::Serialize;

/// Largest number of grid values per axis: 501 x 501 = 251001 initial conditions, about two
/// minutes on two cores when every one is periodic, longer where the motion is chaotic.
pub const MAX_GRID_N: usize = 501;

/// A square grid of initial conditions: q0 and v0 each take `n` equally spaced values in
/// [lo, hi] (the paper searches -2 < q(0), q'(0) < 2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct IcGrid {
    /// Lowest value of q0 and v0.
    pub lo: f64,
    /// Highest value of q0 and v0.
    pub hi: f64,
    /// Number of values per axis (>= 1; with 1 the single value is the midpoint).
    pub n: usize,
}

/// Largest |q0| or |v0| of a grid of initial conditions.
const MAX_IC: f64 = 1e4;

impl IcGrid {
    /// Validated grid.
    pub fn new(lo: f64, hi: f64, n: usize) -> Result<Self> {
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(GearError::param(
                "ic-grid",
                if lo.is_finite() { hi } else { lo },
                "grid bounds must be finite",
            ));
        }
        if lo.abs().max(hi.abs()) > MAX_IC {
            return Err(GearError::param(
                "ic-grid",
                if lo.abs() > MAX_IC { lo } else { hi },
                "initial conditions (q0 in half backlashes, v0 in its rate) must lie in \
                 [-10000, 10000]: further out no gear moves, and the solvers' bounds overflow",
            ));
        }
        if hi < lo {
            return Err(GearError::param(
                "ic-grid",
                hi,
                "upper bound must be >= lower bound",
            ));
        }
        if n == 0 {
            return Err(GearError::param(
                "ic-grid",
                0.0,
                "the grid needs at least 1 point per axis",
            ));
        }
        if n > MAX_GRID_N {
            return Err(GearError::param(
                "ic-grid",
                n as f64,
                "at most 501 points per axis (251001 initial conditions)",
            ));
        }
        Ok(IcGrid { lo, hi, n })
    }

    /// Parse "LO:HI:N" as used on the command line.
    pub fn parse(text: &str) -> Result<Self> {
        let parts: Vec<&str> = text.split(':').collect();
        let bad = |what: &'static str| {
            GearError::Unsupported(format!(
                "--ic-grid '{text}': {what}; expected LO:HI:N, e.g. -2:2:21"
            ))
        };
        if parts.len() != 3 {
            return Err(bad("three fields separated by ':' are required"));
        }
        let lo: f64 = parts[0]
            .trim()
            .parse()
            .map_err(|_| bad("LO is not a number"))?;
        let hi: f64 = parts[1]
            .trim()
            .parse()
            .map_err(|_| bad("HI is not a number"))?;
        let n: usize = parts[2]
            .trim()
            .parse()
            .map_err(|_| bad("N is not a whole number >= 1"))?;
        if n > 1 && hi <= lo {
            return Err(bad("HI must exceed LO when N > 1 (N values from LO to HI)"));
        }
        IcGrid::new(lo, hi, n).map_err(|e| match e {
            GearError::InvalidParameter { value, reason, .. } => GearError::Unsupported(format!(
                "--ic-grid '{text}': {} is refused: {reason}",
                crate::error::readable(value)
            )),
            other => other,
        })
    }

    /// The values along one axis.
    pub fn axis(&self) -> Vec<f64> {
        if self.n == 1 {
            return vec![0.5 * (self.lo + self.hi)];
        }
        let h = (self.hi - self.lo) / (self.n - 1) as f64;
        (0..self.n).map(|i| self.lo + i as f64 * h).collect()
    }

    /// All grid points, v0 outer and q0 inner (row 0 = lowest v0), as in the basin maps.
    pub fn points(&self) -> Vec<State> {
        let ax = self.axis();
        ax.iter()
            .flat_map(|&v| ax.iter().map(move |&q| [q, v]))
            .collect()
    }

    /// Indices of a coarse sub-grid of about `per_axis` points per axis (used to seed attractors).
    pub fn coarse_indices(&self, per_axis: usize) -> Vec<usize> {
        let stride = self.n.div_ceil(per_axis.max(1)).max(1);
        let idx: Vec<usize> = (0..self.n).step_by(stride).collect();
        idx.iter()
            .flat_map(|&j| idx.iter().map(move |&i| j * self.n + i))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_reject() {
        let g = IcGrid::parse("-2:2:5").unwrap();
        assert_eq!(g.axis(), vec![-2.0, -1.0, 0.0, 1.0, 2.0]);
        assert_eq!(g.points().len(), 25);
        assert_eq!(g.points()[1], [-1.0, -2.0]);
        assert!(IcGrid::parse("-2:2:0").is_err());
        assert!(IcGrid::parse("-2:2").is_err());
        assert!(IcGrid::parse("a:2:3").is_err());
        assert!(IcGrid::parse("2:-2:3").is_err());
        assert!(IcGrid::parse("nan:2:3").is_err());
        // N equal values would be one point drawn N times (a basin map cannot be drawn).
        assert!(IcGrid::parse("1:1:11").is_err());
        assert!(IcGrid::parse("1:1:1").is_ok());
    }
}
