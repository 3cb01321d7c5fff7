//! Scalar root finding: Brent's method on a bracket, and bracketing of every sign change of a
//! function sampled on a grid.

/// Brent's method (inverse quadratic interpolation, secant, bisection) for a root of `f` in
/// [a, b], given f(a) = fa and f(b) = fb of opposite signs (or one of them zero). Stops when the
/// bracket is below `tol` (absolute) plus 4 ulp of the iterate. Returns the best iterate.
pub(crate) fn brent(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    tol: f64,
) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            let min1 = 3.0 * xm * q - (tol1 * q).abs();
            let min2 = (e * q).abs();
            if 2.0 * p < min1.min(min2) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}

/// A root of a sampled function located between grid points `lo` and `lo + 1` (or exactly at
/// `lo` when `exact`), with the direction of the sign change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bracket {
    /// Index of the left grid point.
    pub lo: usize,
    /// The sample at `lo` is itself zero.
    pub exact: bool,
    /// The function increases through the root (negative on the left).
    pub rising: bool,
}

/// Every sign change of consecutive finite samples `v` (NaN marks "undefined here" and breaks
/// brackets). A zero sample is reported once, as an exact root, with the direction taken from
/// its finite neighbours (a zero touched without a sign change is reported with the direction of
/// the left neighbour).
pub(crate) fn sign_changes(v: &[f64]) -> Vec<Bracket> {
    let mut out = Vec::new();
    for i in 0..v.len() {
        let x = v[i];
        if x == 0.0 {
            let left = if i > 0 { v[i - 1] } else { f64::NAN };
            let right = v.get(i + 1).copied().unwrap_or(f64::NAN);
            let rising = if left.is_finite() && left != 0.0 {
                left < 0.0
            } else {
                right > 0.0
            };
            out.push(Bracket {
                lo: i,
                exact: true,
                rising,
            });
            continue;
        }
        let Some(&y) = v.get(i + 1) else { break };
        if x.is_finite() && y.is_finite() && y != 0.0 && (x < 0.0) != (y < 0.0) {
            out.push(Bracket {
                lo: i,
                exact: false,
                rising: x < 0.0,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_roots_to_tolerance() {
        // cos x = x has the root 0.7390851332151607 (Dottie number, 16 digits).
        let f = |x: f64| x.cos() - x;
        let r = brent(f, 0.0, 1.0, f(0.0), f(1.0), 1e-15);
        assert!((r - 0.739_085_133_215_160_7).abs() < 1e-14);
        // A kinked function: root at 0.3 exactly representable up to rounding.
        let g = |x: f64| if x < 0.3 { (x - 0.3) * 10.0 } else { x - 0.3 };
        let r = brent(g, -1.0, 2.0, g(-1.0), g(2.0), 1e-15);
        assert!((r - 0.3).abs() < 1e-14);
    }

    #[test]
    fn sign_changes_reports_each_crossing_once() {
        let v = [-1.0, 1.0, 0.0, -2.0, f64::NAN, 3.0, -1.0, -1.0];
        let b = sign_changes(&v);
        assert_eq!(b.len(), 3);
        assert_eq!((b[0].lo, b[0].exact, b[0].rising), (0, false, true));
        assert_eq!((b[1].lo, b[1].exact, b[1].rising), (2, true, false));
        assert_eq!((b[2].lo, b[2].exact, b[2].rising), (5, false, false));
    }
}
