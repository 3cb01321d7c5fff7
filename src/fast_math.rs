//! sin and cos together for the moderate arguments of the simulation.
//!
//! The exact solver evaluates e^{-zeta tau}(a cos w_d tau + b sin w_d tau) and the harmonics of
//! the forcing at local times within one forcing period, so its arguments stay below a few
//! hundred radians; glibc's `sincos` spends much of its time on checks and general paths such
//! arguments never need, and it was a third of the instructions of a steady-state computation.
//! (An fdlibm `exp` was tried too: glibc's table-driven `exp` is as cheap, so it stays.) The
//! model's own e(t) and k(t) ([`crate::model::GearPair::ste_over_b`], `stiffness_at`), which
//! the response's extrema evaluate hundreds of times a period, use it too: glibc's `sin` (with
//! its rounding-mode save and restore) was 6% of an eps 0.2 `discover` in perf, although
//! back-to-back runs could not resolve a saving from the switch (docs/performance.md).
//!
//! sin/cos (fdlibm, Sun Microsystems 1993, `k_sin.c`, `k_cos.c`, `e_rem_pio2.c`): Cody-Waite
//! reduction x = k pi/2 + r with pi/2 split in a 33-bit head and a tail (k pi/2 head exact for
//! |k| < 2^20), then the fdlibm minimax polynomials on |r| <= pi/4 (error below 2^-58 before
//! rounding). Arguments beyond [`REDUCTION_LIMIT`] or non-finite go to the standard library.

// The constants are fdlibm's published decimal digits, kept verbatim so they can be checked
// against the source; they round to the intended doubles.
#![allow(clippy::excessive_precision)]

/// Largest |x| reduced here; k = round(x 2/pi) < 2^17, so k times the 33-bit head of pi/2 is
/// exact and the reduction error stays below 1e-16 relative to r's scale.
const REDUCTION_LIMIT: f64 = 1.0e5;

/// 1.5 * 2^52: adding and subtracting it rounds to the nearest integer.
const ROUND_SHIFT: f64 = 6_755_399_441_055_744.0;
const FRAC_2_PI: f64 = std::f64::consts::FRAC_2_PI;
/// First 33 bits of pi/2.
const PIO2_HEAD: f64 = 1.570_796_326_734_125_614_17e0;
/// pi/2 - PIO2_HEAD.
const PIO2_TAIL: f64 = 6.077_100_506_506_192_249_32e-11;

const S1: f64 = -1.666_666_666_666_663_243_48e-1;
const S2: f64 = 8.333_333_333_322_489_461_24e-3;
const S3: f64 = -1.984_126_982_985_794_931_34e-4;
const S4: f64 = 2.755_731_370_707_006_767_89e-6;
const S5: f64 = -2.505_076_025_340_686_341_95e-8;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-2;
const C2: f64 = -1.388_888_888_887_410_957_49e-3;
const C3: f64 = 2.480_158_728_947_672_941_78e-5;
const C4: f64 = -2.755_731_435_139_066_330_35e-7;
const C5: f64 = 2.087_572_321_298_174_827_90e-9;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// sin(r) for |r| <= pi/4 (fdlibm `__kernel_sin` with no tail).
#[inline(always)]
fn kernel_sin(r: f64) -> f64 {
    let z = r * r;
    let p = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    r + r * z * (S1 + z * p)
}

/// cos(r) for |r| <= pi/4 (fdlibm `__kernel_cos`, with its compensated 1 - z/2).
#[inline(always)]
fn kernel_cos(r: f64) -> f64 {
    let z = r * r;
    let p = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * p)
}

/// (sin x, cos x), accurate to about one unit in the last place for |x| <= 1e5.
#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > REDUCTION_LIMIT {
        return x.sin_cos();
    }
    // Round to nearest by the 1.5 * 2^52 shift (exact for |y| < 2^51): `f64::round` is a
    // software routine on the baseline x86-64 target and cost as much as the polynomials.
    let k = (x * FRAC_2_PI + ROUND_SHIFT) - ROUND_SHIFT;
    let r = (x - k * PIO2_HEAD) - k * PIO2_TAIL;
    let (s, c) = (kernel_sin(r), kernel_cos(r));
    // quadrant = k mod 4; k is an integer-valued f64 of magnitude < 2^17
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// (sin x, cos x) for |x| <= pi/4, where no reduction is needed: the fdlibm kernels alone.
#[inline(always)]
pub(crate) fn sin_cos_small(x: f64) -> (f64, f64) {
    debug_assert!(x.abs() <= std::f64::consts::FRAC_PI_4 * (1.0 + 1e-12));
    (kernel_sin(x), kernel_cos(x))
}

/// Largest |x| for [`exp_small`]: its degree-9 Taylor polynomial is then exact to
/// |x|^10 / 10! < 2.7e-19, below half an ulp of the result.
pub(crate) const EXP_SMALL_LIMIT: f64 = 1.0 / 16.0;

/// e^x for |x| <= [`EXP_SMALL_LIMIT`] by its Taylor polynomial (Horner; no call, no table).
#[inline(always)]
pub(crate) fn exp_small(x: f64) -> f64 {
    debug_assert!(x.abs() <= EXP_SMALL_LIMIT * (1.0 + 1e-12));
    const C: [f64; 10] = [
        1.0,
        1.0,
        1.0 / 2.0,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5040.0,
        1.0 / 40320.0,
        1.0 / 362_880.0,
    ];
    let mut p = C[9];
    for &c in C[..9].iter().rev() {
        p = p * x + c;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the standard library over the solver's range and beyond: the absolute difference
    /// stays within 2 ulp of 1 (4.4e-16) below |x| = 1e3 and grows only with the reduction
    /// error k * 2^-86 ulp-scale beyond; fdlibm's bound is 1 ulp for each.
    #[test]
    fn matches_std_sin_cos() {
        let mut worst: f64 = 0.0;
        let n = 200_000;
        for i in 0..=n {
            let x = -1.0e3 + 2.0e3 * i as f64 / n as f64 + 1e-7 * (i % 7) as f64;
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 4.5e-16, "{worst:e}");
        for x in [9.9e4, -7.3e4, 5.0e4 + 0.3] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() < 1e-14 && (c - c0).abs() < 1e-14, "{x}");
        }
    }

    /// The reduction-free kernels and the short exp series against the standard library over
    /// their whole ranges: within an ulp or two.
    #[test]
    fn small_argument_kernels_match_std() {
        for i in -2000..=2000 {
            let x = EXP_SMALL_LIMIT * i as f64 / 2000.0;
            let (e, e0) = (exp_small(x), x.exp());
            assert!((e - e0).abs() <= 2.0 * f64::EPSILON * e0, "exp {x}");
            let y = std::f64::consts::FRAC_PI_4 * i as f64 / 2000.0;
            let ((s, c), (s0, c0)) = (sin_cos_small(y), y.sin_cos());
            assert!(
                (s - s0).abs() <= 2.3e-16 && (c - c0).abs() <= 2.3e-16,
                "sin_cos {y}"
            );
        }
    }

    /// Quadrant boundaries, zero, and the fallback for large and non-finite arguments.
    #[test]
    fn edges_and_fallback() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        for k in -8..=8 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2;
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() < 1e-15 && (c - c0).abs() < 1e-15, "{k}");
        }
        assert_eq!(sin_cos(1e9), 1e9_f64.sin_cos());
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
        let (s, _) = sin_cos(f64::INFINITY);
        assert!(s.is_nan());
    }
}
