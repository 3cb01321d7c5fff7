//! Loaded static transmission error (STE) over one mesh period: load sharing among the tooth
//! pairs in contact, tip relief, and contact loss, solved as a compatibility problem.
//!
//! At mesh position tau in [0, p_b) the pairs on the line of action sit at roll distances
//! s_j = s_A + tau + j p_b (j = 0, 1, ... while s_j <= s_E); tau = 0 is the instant a new pair
//! enters contact at A. Pair j has stiffness k_j ([`super::tooth_stiffness`]) and an unloaded
//! separation e_j from the profile modification ([`TipRelief`]). The STE delta (approach of the
//! gears along the line of action, i.e. transmission error times the base radius) satisfies
//! compatibility and equilibrium (e.g. Harris, Proc. IMechE 172, 1958; Tavakoli & Houser, ASME J.
//! Mech. Trans. Autom. Des. 108, 1986):
//!
//! ```text
//! P_j = k_j max(0, delta - e_j),      sum_j P_j = F,
//! ```
//!
//! a pair with e_j >= delta carrying nothing (contact loss). The left side is continuous,
//! piecewise linear and increasing in delta, so the solution is found exactly by activating the
//! pairs in order of increasing e_j, at most one step per pair ([`solve_compatibility`]).
//! The loaded mesh stiffness is the tangent dF/d(delta) = sum of k_j over loaded pairs.

use super::geometry::GearPairGeometry;
use super::profile_deviation::ProfileDeviation;
use super::tooth_stiffness::StiffnessTable;
use crate::data::ProfilePoints;
use crate::error::{GearError, Result};
use crate::model::valid_load;
use serde::Serialize;

/// Shape of a tip relief over its length.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ReliefShape {
    /// Depth grows linearly from the start of relief to the amount at the tip.
    Linear,
    /// Depth grows with the square of the distance from the start of relief.
    Parabolic,
}

impl ReliefShape {
    /// Name used in outputs ("linear", "parabolic").
    pub fn name(self) -> &'static str {
        match self {
            ReliefShape::Linear => "linear",
            ReliefShape::Parabolic => "parabolic",
        }
    }
}

/// Tip relief applied alike to the pinion and the gear (Munro's gears were identical): depth
/// `amount` at the tip, over `length` of roll distance on the line of action measured from the
/// tip's end of contact (E for the pinion, A for the gear).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TipRelief {
    /// Relief depth at the tip along the line of action, metres (>= 0).
    pub amount_m: f64,
    /// Relief length along the line of action, metres (> 0).
    pub length_m: f64,
    /// Linear or parabolic.
    pub shape: ReliefShape,
}

/// Depth a tip relief stays below, metres (1 mm: a deeper one is a unit mistake).
const MAX_RELIEF_M: f64 = 1e-3;

impl TipRelief {
    /// No profile modification.
    pub fn none() -> Self {
        TipRelief {
            amount_m: 0.0,
            length_m: 1.0,
            shape: ReliefShape::Linear,
        }
    }

    /// Harris's "long" relief length: the double-contact stretch at each end of the path of
    /// contact, g_alpha - p_b = (eps_alpha - 1) p_b, metres.
    pub fn long_length(geo: &GearPairGeometry) -> f64 {
        geo.path_of_contact() - geo.base_pitch()
    }

    /// The deepest relief the model takes on `geo`'s teeth, metres: below 1 mm and at most a
    /// tenth of the module (deeper, it takes off the tip rather than modifying the profile; tip
    /// reliefs are a few hundredths of the module).
    pub fn max_amount_m(geo: &GearPairGeometry) -> f64 {
        (0.1 * geo.module_m).min(MAX_RELIEF_M)
    }

    /// Check the amount (finite, >= 0, at most [`TipRelief::max_amount_m`]) and, for a non-zero
    /// amount, the length (in (0, g_alpha / 2], so that the two tips' reliefs do not overlap).
    pub fn validate(&self, geo: &GearPairGeometry) -> Result<()> {
        if !(self.amount_m.is_finite() && (0.0..MAX_RELIEF_M).contains(&self.amount_m)) {
            return Err(GearError::param(
                "tip_relief_um",
                self.amount_m * 1e6,
                "tip relief must be a finite depth in [0, 1000) um",
            ));
        }
        if self.amount_m > Self::max_amount_m(geo) {
            return Err(GearError::param(
                "tip_relief_um",
                self.amount_m * 1e6,
                "tip relief deeper than a tenth of the module (rig.toml module_mm) takes off the \
                 tooth's tip rather than modifying its profile: not a case the tooth-contact model \
                 is built for",
            ));
        }
        let half = geo.path_of_contact() / 2.0;
        if self.amount_m > 0.0
            && !(self.length_m.is_finite() && self.length_m > 0.0 && self.length_m <= half)
        {
            return Err(GearError::param(
                "relief_length_mm",
                self.length_m * 1e3,
                "relief length must be positive and at most half the path of contact",
            ));
        }
        Ok(())
    }

    /// Depth at fraction u in [0, 1] of the relief length (0 at its start, 1 at the tip).
    fn depth(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        self.amount_m
            * match self.shape {
                ReliefShape::Linear => u,
                ReliefShape::Parabolic => u * u,
            }
    }

    /// Unloaded separation (m) of the pair in contact at roll distance s: pinion-tip relief near
    /// E plus gear-tip relief near A.
    pub fn separation(&self, geo: &GearPairGeometry, s: f64) -> f64 {
        if self.amount_m == 0.0 {
            return 0.0;
        }
        let (sa, se) = (geo.start_of_contact(), geo.end_of_contact());
        let pinion = (s - (se - self.length_m)) / self.length_m;
        let gear = (sa + self.length_m - s) / self.length_m;
        let mut e = 0.0;
        if pinion > 0.0 {
            e += self.depth(pinion);
        }
        if gear > 0.0 {
            e += self.depth(gear);
        }
        e
    }
}

/// One tooth pair at one mesh position.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PairState {
    /// Roll distance s from T1, metres.
    pub roll_m: f64,
    /// Pair stiffness k_j, N/m.
    pub stiffness_n_per_m: f64,
    /// Unloaded separation e_j (profile modification), metres.
    pub separation_m: f64,
    /// Load carried P_j, N (0 when the pair has lost contact).
    pub load_n: f64,
}

/// Solve P_j = k_j max(0, delta - e_j), sum P_j = F for delta (F > 0): pairs are activated in
/// order of increasing e_j; with the first n active, delta_n = (F + sum k_j e_j) / sum k_j, and
/// delta_n is the answer once it does not exceed the next pair's e. At most `pairs.len()` steps.
/// `pairs` holds (k_j, e_j); returns delta and the loads P_j in the input order.
pub fn solve_compatibility(pairs: &[(f64, f64)], load_n: f64) -> Result<(f64, Vec<f64>)> {
    if pairs.is_empty() || pairs.iter().any(|&(k, e)| !(k > 0.0 && e.is_finite())) {
        return Err(GearError::Numerical(
            "compatibility: no tooth pair with positive stiffness in contact".into(),
        ));
    }
    let mut order: Vec<usize> = (0..pairs.len()).collect();
    order.sort_by(|&i, &j| pairs[i].1.total_cmp(&pairs[j].1));
    let (mut sk, mut ske) = (0.0, 0.0);
    let mut delta = f64::NAN;
    for (n, &i) in order.iter().enumerate() {
        let (k, e) = pairs[i];
        sk += k;
        ske += k * e;
        delta = (load_n + ske) / sk;
        let next = order.get(n + 1).map(|&j| pairs[j].1);
        if next.is_none_or(|e_next| delta <= e_next) {
            break;
        }
    }
    let loads = pairs
        .iter()
        .map(|&(k, e)| k * (delta - e).max(0.0))
        .collect();
    Ok((delta, loads))
}

/// Loaded STE and mesh stiffness over one mesh period at one load.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SteWaveform {
    /// Transmitted load F along the line of action, N.
    pub load_n: f64,
    /// Mesh positions tau / p_b in [0, 1).
    pub position: Vec<f64>,
    /// STE delta at each position, um.
    pub ste_um: Vec<f64>,
    /// Loaded (tangent) mesh stiffness: sum of k_j over loaded pairs, N/um.
    pub stiffness_n_per_um: Vec<f64>,
    /// Stiffness of all pairs geometrically in contact (no relief, no contact loss), N/um.
    pub geometric_stiffness_n_per_um: Vec<f64>,
    /// The pairs at each position (j = 0 the pair that entered last).
    pub pairs: Vec<Vec<PairState>>,
}

impl SteWaveform {
    /// Peak-to-peak STE, um.
    pub fn ste_pp_um(&self) -> f64 {
        pp(&self.ste_um)
    }

    /// Mean of the loaded mesh stiffness over the period, N/um.
    pub fn mean_stiffness_n_per_um(&self) -> f64 {
        mean(&self.stiffness_n_per_um)
    }
}

/// max - min of a slice (0 when empty).
pub(crate) fn pp(v: &[f64]) -> f64 {
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if v.is_empty() {
        0.0
    } else {
        hi - lo
    }
}

/// Arithmetic mean (0 when empty).
pub(crate) fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// A gear pair ready for loaded contact analysis: its geometry, tabulated pair stiffness and
/// any profile modification given point by point (the tip relief is given per call).
#[derive(Clone, Debug)]
pub struct MeshModel {
    /// The geometry.
    pub geometry: GearPairGeometry,
    /// Pair stiffness along the path of contact.
    pub stiffness: StiffnessTable,
    /// Profile modification of the flanks from a table (empty: none), added to the relief's
    /// separation.
    pub deviation: ProfileDeviation,
}

/// Points of the pair-stiffness table along the path of contact.
const TABLE_POINTS: usize = 401;

impl MeshModel {
    /// Tabulate the pair stiffness of `geometry`.
    pub fn new(geometry: GearPairGeometry) -> Self {
        let stiffness = StiffnessTable::new(&geometry, TABLE_POINTS);
        MeshModel {
            geometry,
            stiffness,
            deviation: ProfileDeviation::default(),
        }
    }

    /// The pair of `geometry` with the flanks' profile table `profile` (diameters and reliefs,
    /// [`ProfileDeviation::from_diameters`]; empty: none).
    pub fn with_profile(geometry: GearPairGeometry, profile: &ProfilePoints) -> Result<Self> {
        let deviation = ProfileDeviation::from_diameters(&geometry, &profile.pinion, &profile.gear)
            .map_err(|p| profile.error_at(p.gear, p.point, p.to_string()))?;
        Ok(Self::new(geometry).with_deviation(deviation))
    }

    /// The same pair with the flanks' tabulated profile modification `deviation`.
    pub fn with_deviation(self, deviation: ProfileDeviation) -> Self {
        MeshModel { deviation, ..self }
    }

    /// Unloaded separation (m) of the pair at roll distance `s` with `relief`: the relief's
    /// and the table's.
    fn separation(&self, relief: &TipRelief, s: f64) -> f64 {
        relief.separation(&self.geometry, s) + self.deviation.separation(&self.geometry, s)
    }

    /// Roll distances of the pairs in contact at mesh position `frac` = tau / p_b in [0, 1).
    pub fn pairs_at(&self, frac: f64) -> Vec<f64> {
        let g = &self.geometry;
        let (sa, se, pb) = (g.start_of_contact(), g.end_of_contact(), g.base_pitch());
        let tol = 1e-12 * pb;
        (0..)
            .map(|j| sa + (frac + j as f64) * pb)
            .take_while(|&s| s <= se + tol)
            .collect()
    }

    /// Mesh positions tau / p_b = i / samples, i = 0..samples.
    fn positions(samples: usize) -> Vec<f64> {
        (0..samples).map(|i| i as f64 / samples as f64).collect()
    }

    /// The loaded STE over one mesh period at `load_n` (> 0) with `relief`, at `samples`
    /// (>= 8) equally spaced positions.
    pub fn waveform(&self, load_n: f64, relief: &TipRelief, samples: usize) -> Result<SteWaveform> {
        if !valid_load(load_n) {
            return Err(GearError::param(
                "load_n",
                load_n,
                "load must be in (0, 1e8] N, as every load input of geardyn",
            ));
        }
        if samples < 8 {
            return Err(GearError::param(
                "samples",
                samples as f64,
                "need at least 8 positions per mesh period",
            ));
        }
        relief.validate(&self.geometry)?;
        let position = Self::positions(samples);
        let mut out = SteWaveform {
            load_n,
            position: position.clone(),
            ste_um: Vec::with_capacity(samples),
            stiffness_n_per_um: Vec::with_capacity(samples),
            geometric_stiffness_n_per_um: Vec::with_capacity(samples),
            pairs: Vec::with_capacity(samples),
        };
        for &frac in &position {
            let rolls = self.pairs_at(frac);
            let kes: Vec<(f64, f64)> = rolls
                .iter()
                .map(|&s| (self.stiffness.at(s), self.separation(relief, s)))
                .collect();
            let (delta, loads) = solve_compatibility(&kes, load_n)?;
            let states: Vec<PairState> = rolls
                .iter()
                .zip(&kes)
                .zip(&loads)
                .map(|((&s, &(k, e)), &p)| PairState {
                    roll_m: s,
                    stiffness_n_per_m: k,
                    separation_m: e,
                    load_n: p,
                })
                .collect();
            out.ste_um.push(delta * 1e6);
            out.stiffness_n_per_um.push(
                states
                    .iter()
                    .filter(|p| p.load_n > 0.0)
                    .map(|p| p.stiffness_n_per_m)
                    .sum::<f64>()
                    * 1e-6,
            );
            out.geometric_stiffness_n_per_um
                .push(kes.iter().map(|p| p.0).sum::<f64>() * 1e-6);
            out.pairs.push(states);
        }
        Ok(out)
    }

    /// The relief's own contribution to the STE over the period, min_j e_j (um): the STE as the
    /// load tends to zero, where only the least-relieved pair touches.
    pub fn relief_profile_um(&self, relief: &TipRelief, samples: usize) -> Vec<f64> {
        Self::positions(samples.max(1))
            .into_iter()
            .map(|frac| {
                self.pairs_at(frac)
                    .iter()
                    .map(|&s| self.separation(relief, s))
                    .fold(f64::INFINITY, f64::min)
                    * 1e6
            })
            .collect()
    }

    /// Mean mesh stiffness over a period with every pair in contact (no relief), N/um: the
    /// analogue of ISO 6336-1's c_gamma times face width.
    pub fn mean_mesh_stiffness_n_per_um(&self, samples: usize) -> f64 {
        let v: Vec<f64> = Self::positions(samples.max(1))
            .into_iter()
            .map(|frac| {
                self.pairs_at(frac)
                    .iter()
                    .map(|&s| self.stiffness.at(s))
                    .sum::<f64>()
                    * 1e-6
            })
            .collect();
        mean(&v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compatibility_shares_and_drops_pairs() {
        // Two equal pairs, no separation: each carries half.
        let (d, p) = solve_compatibility(&[(2e8, 0.0), (2e8, 0.0)], 1000.0).unwrap();
        assert!((d - 1000.0 / 4e8).abs() < 1e-18);
        assert!((p[0] - 500.0).abs() < 1e-9 && (p[1] - 500.0).abs() < 1e-9);
        // A pair relieved by more than the single-pair deflection carries nothing.
        let (d, p) = solve_compatibility(&[(2e8, 10e-6), (2e8, 0.0)], 1000.0).unwrap();
        assert!((d - 5e-6).abs() < 1e-15);
        assert_eq!(p[0], 0.0);
        assert!((p[1] - 1000.0).abs() < 1e-9);
        // Partly relieved: both touch, equilibrium holds and both see the same delta.
        let (d, p) = solve_compatibility(&[(2e8, 1e-6), (1e8, 0.0)], 1000.0).unwrap();
        assert!((p[0] + p[1] - 1000.0).abs() < 1e-9);
        assert!((p[0] - 2e8 * (d - 1e-6)).abs() < 1e-6 && (p[1] - 1e8 * d).abs() < 1e-6);
    }
}
