//! Every single-harmonic (describing-function) solution of eq. 5 at a frequency, and the
//! frequency response (eq. 10, Sec. 4).
//!
//! The ansatz q = q_m + q_a sin(Omega t + phase) in eq. 5 with the describing functions of eq. 7-8
//! gives the mean balance N_m q_m = F_m (eq. 10b) and the amplitude equation
//! q_a = F_ah Omega^2 / sqrt((N_a - Omega^2)^2 + (2 zeta Omega)^2) (eq. 10a), with the phase of
//! eq. 10c. All solutions are found, not only the one an iteration from a guess converges to:
//!
//! 1. Since 0 <= N_a <= 1, any solution has q_a between F_ah Omega^2 / sqrt(max(Omega^2,
//!    |1 - Omega^2|)^2 + (2 zeta Omega)^2) and F_ah Omega^2 / sqrt(dist(Omega^2, [0, 1])^2 +
//!    (2 zeta Omega)^2).
//! 2. For each q_a the mean balance has a unique q_m (see `mean_balance`), so eq. 10a is one
//!    equation R(q_a) = 0, scanned on a fine log grid over those bounds; every sign change is
//!    refined with Brent's method.
//!
//! With `DfMethod::Exact` the impact case follows from the state; with `DfMethod::Truncated` the
//! paper's per-case formulas are solved separately and each candidate is kept only if it meets
//! its case condition (see `cases`).
//!
//! Stability (optional in the paper, which does not treat it): `stable` is the slope criterion
//! of the averaged amplitude equation with the mean adapting quasi-statically: a root where R
//! increases through zero is stable, one where it decreases (the middle branch between two folds)
//! is a saddle. This ignores any instability the neglected higher harmonics or the mean dynamics
//! could bring; verify with the simulator where it matters.

use super::cases;
use super::describing::DfMethod;
use super::scan::{Branch, Table};
use crate::error::{GearError, Result};
use crate::model::Impact;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One describing-function solution q = q_m + q_a sin(Omega t + phase) of eq. 5 (eq. 10).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DfSolution {
    /// Excitation frequency Omega_h.
    pub omega: f64,
    /// Alternating amplitude q_a (eq. 10a), >= 0.
    pub qa: f64,
    /// Mean q_m (eq. 10b).
    pub qm: f64,
    /// Response phase phi_r of eq. 10c for phi_h = 0: -atan2(2 zeta Omega, N_a - Omega^2), in
    /// (-pi, 0).
    pub phase: f64,
    /// Impact case (Fig. 9): I none (q_m - q_a > 1), II single-sided, III double-sided
    /// (q_m - q_a < -1).
    pub case: Impact,
    /// Slope criterion: `Some(true)` where R(q_a) of eq. 10a rises through zero, `Some(false)`
    /// on a middle (saddle) branch; `None` when not determined.
    pub stable: Option<bool>,
}

fn check(name: &'static str, v: f64, ok: bool, reason: &'static str) -> Result<()> {
    if v.is_finite() && ok {
        Ok(())
    } else {
        Err(GearError::param(name, v, reason))
    }
}

/// Validate F_m > 0, F_ah >= 0, 0 < zeta < 1 (all finite).
pub(crate) fn validate(fm: f64, fah: f64, zeta: f64) -> Result<()> {
    check(
        "F_m",
        fm,
        fm > 0.0,
        "mean load must be finite and > 0 for the describing-function solution (hbm starts \
         every method from it; at F_m = 0 use the simulation: sweep, simulate)",
    )?;
    check(
        "F_ah",
        fah,
        fah >= 0.0,
        "STE amplitude must be finite and >= 0",
    )?;
    check(
        "zeta",
        zeta,
        zeta > 0.0 && zeta < 1.0,
        "damping ratio must satisfy 0 < zeta < 1",
    )
}

fn validate_omega(omega: f64) -> Result<()> {
    check(
        "omega",
        omega,
        omega > 0.0,
        "excitation frequency must be finite and > 0",
    )
}

/// Largest ln(hi / lo) of the q_a range searched (about 600 * 200 grid points).
const MAX_LOG_SPAN: f64 = 200.0;

/// Relative widening of the q_a bounds, far above rounding.
const BOUND_PAD: f64 = 1e-9;

/// Bounds on q_a of any solution at Omega, from 0 <= N_a <= 1 in eq. 10a, widened by
/// [`BOUND_PAD`] so that a root on a bound lies strictly inside: for Omega^2 <= 1/2 the case I root
/// (N_a = 1) is exactly the lower bound.
fn qa_bounds(fah: f64, zeta: f64, omega: f64) -> (f64, f64) {
    let w2 = omega * omega;
    let damp = 2.0 * zeta * omega;
    let far = w2.max((1.0 - w2).abs());
    let near = (w2 - 1.0).max(0.0);
    (
        fah * w2 / far.hypot(damp) * (1.0 - BOUND_PAD),
        fah * w2 / near.hypot(damp) * (1.0 + BOUND_PAD),
    )
}

/// The branches solved for a method, tabulated over q_a in [lo, hi].
struct Solver {
    method: DfMethod,
    fm: f64,
    zeta: f64,
    tables: Vec<Table>,
}

impl Solver {
    fn new(fm: f64, fah: f64, zeta: f64, method: DfMethod, lo: f64, hi: f64) -> Result<Solver> {
        if fah > 0.0 && !(lo > 0.0 && hi.is_finite() && (hi / lo).ln() <= MAX_LOG_SPAN) {
            return Err(GearError::Numerical(format!(
                "q_a search range [{lo:e}, {hi:e}] is empty, infinite or wider than e^{MAX_LOG_SPAN} \
                 (extreme F_ah, zeta or Omega)"
            )));
        }
        let branches: &[Branch] = if fah == 0.0 {
            &[]
        } else {
            match method {
                DfMethod::Exact => &[Branch::Exact],
                DfMethod::Truncated => &[Branch::Case2, Branch::Case3],
            }
        };
        Ok(Solver {
            method,
            fm,
            zeta,
            tables: branches
                .iter()
                .map(|&b| Table::new(b, fm, lo, hi))
                .collect(),
        })
    }

    /// Every solution at `omega` for the STE amplitude `fah` (eq. 10).
    fn at(&self, omega: f64, fah: f64) -> Vec<DfSolution> {
        let (qa1, qm1) = cases::case1(self.fm, fah, self.zeta, omega);
        let case1 = DfSolution {
            omega,
            qa: qa1,
            qm: qm1,
            phase: -(2.0 * self.zeta * omega).atan2(1.0 - omega * omega),
            case: Impact::None,
            stable: Some(true),
        };
        if fah == 0.0 {
            // q_a = 0: the static equilibrium q = F_m + 1, case I, for either method.
            return vec![case1];
        }
        let (lo, hi) = qa_bounds(fah, self.zeta, omega);
        let mut out: Vec<DfSolution> = self
            .tables
            .iter()
            .flat_map(|t| t.roots(fah, self.zeta, omega, lo, hi))
            .collect();
        if self.method == DfMethod::Truncated && cases::case1_valid(qm1, qa1) {
            out.push(case1);
        }
        out.sort_by(|a, b| a.qa.total_cmp(&b.qa));
        out
    }
}

/// All describing-function solutions of eq. 5 at one frequency (eq. 10 with eq. 8 or eq. 9),
/// sorted by q_a.
///
/// Errors: `InvalidParameter` unless F_m > 0, F_ah >= 0, 0 < zeta < 1 and Omega > 0, all finite.
pub fn df_solutions(
    fm: f64,
    fah: f64,
    zeta: f64,
    omega: f64,
    method: DfMethod,
) -> Result<Vec<DfSolution>> {
    validate(fm, fah, zeta)?;
    validate_omega(omega)?;
    let (lo, hi) = qa_bounds(fah, zeta, omega);
    Ok(Solver::new(fm, fah, zeta, method, lo, hi)?.at(omega, fah))
}

/// The forcing of the describing-function solution: the STE excitation of eq. 5 (force
/// F_ah Omega^2 sin(Omega t)) and an external torque of eq. 4 at the same frequency and phase
/// (force F_aT sin(Omega t)). Their sum is one sinusoid, so the ansatz and eq. 10 are those of
/// eq. 5 with the STE amplitude F_ah + F_aT / Omega^2.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DfForcing {
    /// STE amplitude F_ah (eq. 5).
    pub ste: f64,
    /// Torque amplitude F_aT (eq. 4).
    pub torque: f64,
}

impl DfForcing {
    /// The STE excitation of eq. 5 alone.
    pub fn ste(fah: f64) -> Self {
        DfForcing {
            ste: fah,
            torque: 0.0,
        }
    }

    /// The external torque of eq. 4 alone.
    pub fn torque(fat: f64) -> Self {
        DfForcing {
            ste: 0.0,
            torque: fat,
        }
    }

    /// The STE amplitude of eq. 10 that gives this forcing's force amplitude at `omega`.
    pub fn ste_amplitude(self, omega: f64) -> f64 {
        self.ste + self.torque / (omega * omega)
    }

    /// Force amplitude F_ah Omega^2 + F_aT at `omega`.
    pub fn force(self, omega: f64) -> f64 {
        self.ste * omega * omega + self.torque
    }
}

/// The describing-function frequency response (Fig. 10, 15-18): every solution at every Omega of
/// `omegas`, in the order of `omegas` and by q_a within one Omega (several rows per Omega where
/// solutions coexist). Frequencies are solved in parallel; the q_m(q_a) branch is tabulated once.
///
/// Errors: as [`df_solutions`], for any entry of `omegas`.
pub fn df_response(
    fm: f64,
    fah: f64,
    zeta: f64,
    omegas: &[f64],
    method: DfMethod,
) -> Result<Vec<DfSolution>> {
    df_response_forced(fm, DfForcing::ste(fah), zeta, omegas, method)
}

/// [`df_response`] for the STE excitation of eq. 5, an external torque of eq. 4, or both.
///
/// Errors: as [`df_solutions`] (F_aT like F_ah), for any entry of `omegas`.
pub fn df_response_forced(
    fm: f64,
    forcing: DfForcing,
    zeta: f64,
    omegas: &[f64],
    method: DfMethod,
) -> Result<Vec<DfSolution>> {
    validate(fm, forcing.ste, zeta)?;
    check(
        "F_aT",
        forcing.torque,
        forcing.torque >= 0.0,
        "torque amplitude must be finite and >= 0",
    )?;
    for &w in omegas {
        validate_omega(w)?;
    }
    let (lo, hi) = omegas
        .iter()
        .map(|&w| qa_bounds(forcing.ste_amplitude(w), zeta, w))
        .fold((f64::INFINITY, 0.0f64), |(l, h), (a, b)| {
            (l.min(a), h.max(b))
        });
    if omegas.is_empty() {
        return Ok(Vec::new());
    }
    let amp = forcing.ste.max(forcing.torque);
    let solver = Solver::new(fm, amp, zeta, method, lo, hi)?;
    let per_omega: Vec<Vec<DfSolution>> = omegas
        .par_iter()
        .map(|&w| solver.at(w, forcing.ste_amplitude(w)))
        .collect();
    Ok(per_omega.into_iter().flatten().collect())
}
