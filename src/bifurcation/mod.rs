//! Bifurcation diagrams (issue 23): Poincare points (q at phase 0) against Omega, F_hat or zeta,
//! from every attractor of an initial-condition grid at each value (brute force, each
//! non-periodic set followed to tell chaotic attractors from chaotic transients, which are drawn
//! apart) and from a sweep carrying the last state. Folds and period doublings are marked: from
//! the AFT continuation of the period-1 branches (Floquet multipliers) when Omega varies, and
//! where the carried simulation changes period or jumps otherwise.

mod figure;

pub use figure::{bifurcation_csv, bifurcation_figure};

use crate::error::{GearError, Result};
use crate::hb::{branches_covering, AftOptions, ContinuationOptions};
use crate::model::{GearPair, Impact};
use crate::progress::Progress;
use crate::sim::{
    carry, find_attractors, FlowFactory, IcGrid, Motion, SetKind, State, SteadyOptions, SteadyState,
};
use serde::Serialize;

/// The parameter varied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Parameter {
    /// Mesh frequency Omega_h.
    Omega,
    /// Force ratio F_hat = F_m / F_ah, varied through F_m at fixed F_ah (as Fig. 7).
    Fhat,
    /// Damping ratio zeta (as Fig. 8).
    Zeta,
}

impl Parameter {
    /// Axis label with Unicode symbols.
    pub fn label(self) -> &'static str {
        match self {
            Parameter::Omega => "Ω",
            Parameter::Fhat => "F_hat = F_m / F_ah",
            Parameter::Zeta => "ζ",
        }
    }
}

/// The base point and what is varied.
#[derive(Clone, Debug)]
pub struct BifurcationOptions {
    /// Mean load F_m (ignored when F_hat varies: F_m = F_hat F_ah).
    pub fm: f64,
    /// STE amplitude F_ah.
    pub fah: f64,
    /// Damping ratio (ignored when zeta varies).
    pub zeta: f64,
    /// Mesh frequency (ignored when Omega varies).
    pub omega: f64,
    /// The parameter varied and its values.
    pub parameter: Parameter,
    /// Values of the parameter, increasing.
    pub values: Vec<f64>,
    /// Initial conditions of the brute-force search at every value (`None`: carried sweep only).
    pub grid: Option<IcGrid>,
    /// Also sweep carrying the last steady state (up the values).
    pub carried: bool,
    /// Steady-state and escape options.
    pub steady: SteadyOptions,
    /// Poincare points drawn per non-periodic set at most.
    pub cloud_points: usize,
}

impl BifurcationOptions {
    /// The model at value `v` of the parameter.
    pub fn model(&self, v: f64) -> Result<GearPair> {
        match self.parameter {
            Parameter::Omega => GearPair::paper(self.fm, self.fah, self.zeta, v),
            Parameter::Fhat => GearPair::paper(v * self.fah, self.fah, self.zeta, self.omega),
            Parameter::Zeta => GearPair::paper(self.fm, self.fah, v, self.omega),
        }
    }
}

/// Where a Poincare point comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    /// An attractor (or transient set) of the initial-condition grid.
    Grid,
    /// The sweep carrying the last state.
    Carried,
}

/// One Poincare point of the diagram.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BifurcationPoint {
    /// Value of the parameter.
    pub value: f64,
    /// Section point (q, q') at forcing phase 0.
    pub state: State,
    /// Grid or carried sweep.
    pub source: Source,
    /// Index of the set among those found at this value (grid), 0 for the carried sweep.
    pub set: usize,
    /// Attractor or transient (the carried sweep's motions are not followed: attractor).
    pub kind: SetKind,
    /// Period p, `None` for non-periodic motion.
    pub period: Option<u32>,
    /// Impact regime.
    pub impact: Impact,
    /// Kind of motion.
    pub motion: Motion,
}

/// A bifurcation marked on the diagram.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BifurcationMark {
    /// Value of the parameter.
    pub value: f64,
    /// "fold" or "period doubling" (AFT), "period change" or "jump" (carried simulation).
    pub what: String,
    /// "aft" or "simulation".
    pub source: String,
}

/// A computed diagram.
#[derive(Clone, Debug, Serialize)]
pub struct Bifurcation {
    /// The parameter varied.
    pub parameter: Parameter,
    /// Every Poincare point.
    pub points: Vec<BifurcationPoint>,
    /// Folds and period doublings.
    pub marks: Vec<BifurcationMark>,
}

/// Largest number of parameter values.
pub const MAX_VALUES: usize = 2001;
/// Largest number of initial conditions over all values (about 10 minutes on two cores where
/// the motion is periodic).
pub const MAX_ICS: usize = 2_000_000;
/// Relative change of q_a between consecutive carried states read as a jump.
const JUMP: f64 = 0.2;

/// Compute the diagram.
pub fn bifurcation(
    opts: &BifurcationOptions,
    factory: FlowFactory<'_>,
    progress: &dyn Progress,
) -> Result<Bifurcation> {
    check(opts)?;
    let models = opts
        .values
        .iter()
        .map(|&v| opts.model(v))
        .collect::<Result<Vec<_>>>()?;
    let mut points = Vec::new();
    if let Some(grid) = &opts.grid {
        for (&v, m) in opts.values.iter().zip(&models) {
            let flow = factory(m)?;
            let map = find_attractors(flow.as_ref(), grid, &opts.steady, progress)?;
            for (i, a) in map.attractors.iter().enumerate() {
                points.extend(section(v, &a.steady, Source::Grid, i, a.kind, opts));
            }
        }
    }
    let mut marks = Vec::new();
    if opts.carried {
        let m0 = &models[0];
        let states = carry(
            factory,
            &models,
            [1.0 + m0.mean_force, 0.0],
            &opts.steady,
            progress,
        )?;
        // A fifth of the points per non-periodic state: the carried sweep is drawn underneath
        // the grid's sets, not over them.
        let sparse = BifurcationOptions {
            cloud_points: (opts.cloud_points / 5).max(1),
            ..opts.clone()
        };
        for (&v, s) in opts.values.iter().zip(&states) {
            points.extend(section(
                v,
                s,
                Source::Carried,
                0,
                SetKind::Attractor,
                &sparse,
            ));
        }
        marks.extend(carried_marks(&opts.values, &states));
    }
    if opts.parameter == Parameter::Omega {
        marks.extend(aft_marks(opts)?);
    }
    marks.sort_by(|a, b| a.value.total_cmp(&b.value));
    // The continuation may insert several points at one fold (or the branches meet there):
    // one mark per kind within a thousandth of the range.
    let span = opts.values[opts.values.len() - 1] - opts.values[0];
    let mut kept: Vec<BifurcationMark> = Vec::new();
    for m in marks {
        let dup = kept.iter().any(|k| {
            k.what == m.what && k.source == m.source && (k.value - m.value).abs() <= 1e-3 * span
        });
        if !dup {
            kept.push(m);
        }
    }
    let marks = kept;
    Ok(Bifurcation {
        parameter: opts.parameter,
        points,
        marks,
    })
}

fn check(opts: &BifurcationOptions) -> Result<()> {
    let n = opts.values.len();
    if n == 0 || n > MAX_VALUES {
        return Err(GearError::param(
            "values",
            n as f64,
            "between 1 and 2001 parameter values",
        ));
    }
    if opts.values.windows(2).any(|w| w[1] <= w[0]) {
        return Err(GearError::param(
            "values",
            n as f64,
            "the parameter values must increase",
        ));
    }
    if let Some(g) = &opts.grid {
        if n * g.n * g.n > MAX_ICS {
            return Err(GearError::param(
                "ic-grid",
                (n * g.n * g.n) as f64,
                "at most 2000000 initial conditions over all values; use fewer values or a coarser grid",
            ));
        }
    }
    if opts.grid.is_none() && !opts.carried {
        return Err(GearError::param(
            "mode",
            0.0,
            "nothing to compute: neither a grid search nor a carried sweep",
        ));
    }
    opts.steady.validate()?;
    opts.steady.escape.validate()
}

/// The Poincare points of one steady state: a periodic orbit's p points, or up to
/// `cloud_points` of a non-periodic motion's section cloud.
fn section(
    value: f64,
    s: &SteadyState,
    source: Source,
    set: usize,
    kind: SetKind,
    opts: &BifurcationOptions,
) -> Vec<BifurcationPoint> {
    let cloud = if s.period.is_none() && !s.cloud.is_empty() {
        &s.cloud
    } else {
        &s.poincare
    };
    let step = (cloud.len() / opts.cloud_points.max(1)).max(1);
    cloud
        .iter()
        .step_by(step)
        .map(|&state| BifurcationPoint {
            value,
            state,
            source,
            set,
            kind,
            period: s.period,
            impact: s.impact,
            motion: s.motion,
        })
        .collect()
}

/// Period changes (doublings and others) and amplitude jumps along the carried sweep.
fn carried_marks(values: &[f64], states: &[SteadyState]) -> Vec<BifurcationMark> {
    let mut out = Vec::new();
    for (w, v) in states.windows(2).zip(values.windows(2)) {
        let mid = 0.5 * (v[0] + v[1]);
        let (a, b) = (&w[0], &w[1]);
        if a.period != b.period {
            let what = match (a.period, b.period) {
                (Some(p), Some(q)) if q == 2 * p || p == 2 * q => "period doubling",
                _ => "period change",
            };
            out.push(BifurcationMark {
                value: mid,
                what: what.into(),
                source: "simulation".into(),
            });
        } else if (b.qa - a.qa).abs() > JUMP * a.qa.abs().max(b.qa.abs()) {
            out.push(BifurcationMark {
                value: mid,
                what: "jump".into(),
                source: "simulation".into(),
            });
        }
    }
    out
}

/// Folds and period doublings of the period-1 AFT branches (H 15, Floquet stability) over the
/// Omega range.
fn aft_marks(opts: &BifurcationOptions) -> Result<Vec<BifurcationMark>> {
    let (lo, hi) = (opts.values[0], opts.values[opts.values.len() - 1]);
    if hi <= lo {
        return Ok(Vec::new());
    }
    let model = opts.model(lo)?;
    let aft = AftOptions {
        harmonics: 15,
        stability: true,
        ..AftOptions::default()
    };
    // A branch that cannot be continued (no contact-only start and no simulated seed) gives no
    // marks rather than no diagram.
    let Ok(branches) = branches_covering(&model, lo, hi, &aft, &ContinuationOptions::default())
    else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for p in branches.iter().flatten() {
        if p.fold {
            out.push(BifurcationMark {
                value: p.omega,
                what: "fold".into(),
                source: "aft".into(),
            });
        }
        if p.period_doubling {
            out.push(BifurcationMark {
                value: p.omega,
                what: "period doubling".into(),
                source: "aft".into(),
            });
        }
    }
    Ok(out)
}
