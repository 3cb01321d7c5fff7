//! When two significant candidates are "ambiguous" (issue 5: nearly collinear sensitivities on
//! the measured grid are reported rather than forced into a name).

use nalgebra::DVector;

/// chi2(0.95; 1): two nested refits whose residual sums of squares differ by less than this
/// (in sigma^2) are not distinguishable by a likelihood-ratio comparison at 5%.
pub const CHI2_95_1DF: f64 = 3.84;

/// Extra allowance, as a share of the leading drop, for collinear candidates: collinear
/// directions make equal fits up to second-order terms that grow with the effect's size.
const COLLINEAR_SLACK: f64 = 0.005;

/// A refitted significant candidate: its index, the drop in residual sum of squares its refit
/// achieves over M0 (sigma^2 units), and its probe direction on the measured grid (residual
/// change projected off the nuisance parameters).
#[derive(Clone, Copy, Debug)]
pub struct Contender<'a> {
    pub index: usize,
    pub drop: f64,
    pub direction: &'a DVector<f64>,
}

/// The contenders that the data cannot tell apart from `best` (the largest drop): a drop within
/// [`CHI2_95_1DF`] of the best one, or a direction with |cos| above `collinear_cos` and a drop
/// within chi2 + 0.5% of the best drop. A clear difference in fit overrules first-order
/// collinearity of the probes.
pub fn ambiguous_with(best: &Contender, others: &[Contender], collinear_cos: f64) -> Vec<usize> {
    others
        .iter()
        .filter(|o| o.index != best.index)
        .filter(|o| {
            let (a, b) = (best.direction, o.direction);
            let cos = a.dot(b) / (a.norm() * b.norm()).max(1e-300);
            let diff = best.drop - o.drop;
            diff < CHI2_95_1DF
                || (cos.abs() > collinear_cos && diff < CHI2_95_1DF + COLLINEAR_SLACK * best.drop)
        })
        .map(|o| o.index)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: &[f64]) -> DVector<f64> {
        DVector::from_row_slice(x)
    }

    fn c(index: usize, drop: f64, direction: &DVector<f64>) -> Contender<'_> {
        Contender {
            index,
            drop,
            direction,
        }
    }

    /// Two candidates whose refits fit equally well (drops 3 sigma^2 apart) are ambiguous
    /// whatever their directions; 10 sigma^2 apart and orthogonal, the better one is named.
    #[test]
    fn equal_fits_are_ambiguous_distinct_fits_are_not() {
        let (a, b) = (v(&[1.0, 0.0, 0.0]), v(&[0.0, 1.0, 0.0]));
        let best = c(0, 100.0, &a);
        assert_eq!(
            ambiguous_with(&best, &[best, c(1, 97.0, &b)], 0.95),
            vec![1]
        );
        assert!(ambiguous_with(&best, &[best, c(1, 90.0, &b)], 0.95).is_empty());
    }

    /// Nearly collinear directions (cos 0.995) with drops 4.2 sigma^2 apart out of 100 (inside
    /// 3.84 + 0.5 = 4.34) are ambiguous; the same drops with cos 0.6 are not, and collinear
    /// directions with a clearly better fit (drops 20 apart) are not either. A sign flip of the
    /// direction is still collinear (|cos|).
    #[test]
    fn collinear_directions_with_near_equal_fits_are_ambiguous() {
        let a = v(&[1.0, 0.1, 0.0]);
        let collinear = v(&[-1.0, -0.0, -0.0]);
        let oblique = v(&[0.6, 0.8, 0.0]);
        let cos = a.dot(&collinear).abs() / (a.norm() * collinear.norm());
        assert!(cos > 0.99 && cos < 0.999, "{cos}");
        let best = c(2, 100.0, &a);
        assert_eq!(
            ambiguous_with(&best, &[c(4, 95.8, &collinear)], 0.99),
            vec![4]
        );
        assert!(ambiguous_with(&best, &[c(4, 95.8, &oblique)], 0.99).is_empty());
        assert!(ambiguous_with(&best, &[c(4, 80.0, &collinear)], 0.99).is_empty());
    }
}
