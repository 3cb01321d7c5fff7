//! All roots of the amplitude equation along one branch of the mean balance.
//!
//! For each q_a the mean balance fixes q_m (and with it N_a), so eq. 10a becomes one scalar
//! equation R(q_a) = q_a sqrt((N_a - Omega^2)^2 + (2 zeta Omega)^2) - F_ah Omega^2 = 0. The branch
//! (q_m(q_a), N_a(q_a)) does not depend on Omega or zeta, so it is tabulated once on a log-spaced
//! q_a grid and reused for every frequency; R is then sampled on the grid, every sign change is
//! refined by Brent's method, and the candidate is kept if it satisfies its case condition.
//!
//! Resolution: two roots closer than one grid step (a ratio of e^(1/600), 0.17 %) can be missed
//! as a pair; this happens only within a hair of a fold (saddle-node) of the response curve.

use super::cases;
use super::df_solve::DfSolution;
use super::mean_balance::exact_qm;
use crate::model::Impact;
use crate::numeric::{brent, sign_changes};

/// Grid points per e-fold of q_a.
const PER_EFOLD: f64 = 600.0;

/// A one-parameter family of mean-balance states (q_m(q_a), N_a(q_a)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Branch {
    /// Exact describing functions (eq. 8): one branch for all q_a, case from the state (Fig. 9).
    Exact,
    /// Truncated case II (eq. 16-17), kept where eq. 15 holds.
    Case2,
    /// Truncated case III (eq. 19), kept where eq. 18 holds.
    Case3,
}

impl Branch {
    /// (q_m, N_a) at q_a, if the branch's formulas are defined there.
    fn state(self, fm: f64, qa: f64, hint: Option<f64>) -> Option<(f64, f64)> {
        use super::describing::{n_a, DfMethod};
        match self {
            Branch::Exact => {
                let qm = exact_qm(fm, qa, hint);
                Some((qm, n_a(qm, qa, DfMethod::Exact)))
            }
            Branch::Case2 => cases::case2_qm(fm, qa).map(|qm| (qm, cases::case2_na(qm, qa))),
            Branch::Case3 => cases::case3_qm(fm, qa).map(|qm| (qm, cases::case3_na(qm, qa))),
        }
    }

    /// The impact case of a root, or `None` if the branch's validity check rejects it.
    fn accept(self, qm: f64, qa: f64) -> Option<Impact> {
        match self {
            Branch::Exact => Some(Impact::from_range(qm - qa)),
            Branch::Case2 => cases::case2_valid(qm, qa).then_some(Impact::Single),
            Branch::Case3 => cases::case3_valid(qm, qa).then_some(Impact::Double),
        }
    }
}

/// A branch tabulated on a log-spaced q_a grid (NaN where undefined).
pub(crate) struct Table {
    branch: Branch,
    fm: f64,
    qa: Vec<f64>,
    qm: Vec<f64>,
    na: Vec<f64>,
}

/// R(q_a) of eq. 10a for a state; NaN if undefined.
fn residual(qa: f64, state: Option<(f64, f64)>, w2: f64, damp: f64, force: f64) -> f64 {
    match state {
        Some((_, na)) => qa * (na - w2).hypot(damp) - force,
        None => f64::NAN,
    }
}

impl Table {
    /// Tabulate `branch` for 0 < lo <= q_a <= hi (the grid extends one step beyond each end).
    pub(crate) fn new(branch: Branch, fm: f64, lo: f64, hi: f64) -> Table {
        let span = (hi / lo).ln().max(0.0);
        let n = (span * PER_EFOLD).ceil() as usize + 3;
        let ratio = (span / (n - 3).max(1) as f64).exp();
        let start = lo / ratio;
        let mut t = Table {
            branch,
            fm,
            qa: Vec::with_capacity(n),
            qm: Vec::with_capacity(n),
            na: Vec::with_capacity(n),
        };
        let mut hint = None;
        for i in 0..n {
            let qa = start * ratio.powi(i as i32);
            let st = branch.state(fm, qa, hint);
            hint = st.map(|s| s.0);
            let (qm, na) = st.unwrap_or((f64::NAN, f64::NAN));
            t.qa.push(qa);
            t.qm.push(qm);
            t.na.push(na);
        }
        t
    }

    /// Every accepted root of eq. 10a at Omega with q_a in [lo, hi] (bounds that must hold for
    /// any solution and lie within the table), unsorted.
    pub(crate) fn roots(
        &self,
        fah: f64,
        zeta: f64,
        omega: f64,
        lo: f64,
        hi: f64,
    ) -> Vec<DfSolution> {
        let w2 = omega * omega;
        let damp = 2.0 * zeta * omega;
        let force = fah * w2;
        // Grid slice [i0, i1] whose end points lie at or outside [lo, hi].
        let i0 = self.qa.partition_point(|&q| q <= lo).saturating_sub(1);
        let i1 = self.qa.partition_point(|&q| q < hi).min(self.qa.len() - 1);
        let r: Vec<f64> = (i0..=i1)
            .map(|i| {
                let st = self.qm[i].is_finite().then_some((self.qm[i], self.na[i]));
                residual(self.qa[i], st, w2, damp, force)
            })
            .collect();
        let mut out = Vec::new();
        for b in sign_changes(&r) {
            let i = i0 + b.lo;
            let hint = Some(self.qm[i]);
            let qa = if b.exact {
                self.qa[i]
            } else {
                let f = |q: f64| residual(q, self.branch.state(self.fm, q, hint), w2, damp, force);
                brent(f, self.qa[i], self.qa[i + 1], r[b.lo], r[b.lo + 1], 0.0)
            };
            let Some((qm, na)) = self.branch.state(self.fm, qa, hint) else {
                continue;
            };
            if !(qa.is_finite() && qm.is_finite()) {
                continue;
            }
            if let Some(case) = self.branch.accept(qm, qa) {
                out.push(DfSolution {
                    omega,
                    qa,
                    qm,
                    phase: -damp.atan2(na - w2),
                    case,
                    stable: Some(b.rising),
                });
            }
        }
        out
    }
}
