//! Harris map (Harris, "Dynamic loads on the teeth of spur gears", Proc. IMechE 172, 1958): the
//! peak-to-peak STE against load for a given profile modification, and the sizing of a tip
//! relief by Harris's design rule, "the relief that gives minimum STE peak-to-peak at the
//! design load" (the rule Munro's gears followed, Kahraman & Singh 1990 Sec. 7).
//!
//! The design search scans the relief amount on a grid from 0 to three times the largest
//! no-relief STE at the design load, then refines the best grid cell by golden-section search
//! (the STE pp is continuous in the amount; the grid guards against a local minimum).

use super::ste::{MeshModel, TipRelief};
use crate::error::{GearError, Result};
use serde::Serialize;

/// One point of a Harris map.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HarrisPoint {
    /// Load, N.
    pub load_n: f64,
    /// Peak-to-peak STE over a mesh period, um.
    pub ste_pp_um: f64,
}

/// STE peak-to-peak at each load of `loads` for `relief`, with `samples` positions a period.
pub fn harris_map(
    model: &MeshModel,
    relief: &TipRelief,
    loads: &[f64],
    samples: usize,
) -> Result<Vec<HarrisPoint>> {
    loads
        .iter()
        .map(|&load_n| {
            Ok(HarrisPoint {
                load_n,
                ste_pp_um: model.waveform(load_n, relief, samples)?.ste_pp_um(),
            })
        })
        .collect()
}

/// Grid points of the amount scan, and golden-section steps of the refinement.
const GRID: usize = 60;
const GOLDEN_STEPS: usize = 60;

/// The relief amount (m) with `length_m` and `shape` of `template` that minimises the STE pp
/// at `design_load_n` (Harris's rule); returns the relief and its STE pp (um).
pub fn design_relief(
    model: &MeshModel,
    template: &TipRelief,
    design_load_n: f64,
    samples: usize,
) -> Result<(TipRelief, f64)> {
    if !(design_load_n.is_finite() && design_load_n > 0.0) {
        return Err(GearError::param(
            "tip_relief_design_load_n",
            design_load_n,
            "design load must be a positive finite number of newtons",
        ));
    }
    let with = |a: f64| TipRelief {
        amount_m: a,
        ..*template
    };
    let pp = |a: f64| -> Result<f64> {
        Ok(model
            .waveform(design_load_n, &with(a), samples)?
            .ste_pp_um())
    };
    let bare = model.waveform(design_load_n, &TipRelief::none(), samples)?;
    let deflection = 1e-6 * bare.ste_um.iter().fold(0.0_f64, |m, &x| m.max(x));
    let deepest = TipRelief::max_amount_m(&model.geometry);
    if deflection > deepest {
        return Err(GearError::param(
            "tip_relief_design_load_n",
            design_load_n,
            "deflects the teeth further than a tip relief can be deep (a tenth of the module, at \
             most 1000 um): the load is too large for these teeth (rig.toml face_width_mm, \
             module_mm)",
        ));
    }
    // The best relief is about the deflection; the search looks up to three times further.
    let top = (3.0 * deflection).min(deepest);
    let grid: Vec<f64> = (0..=GRID).map(|i| top * i as f64 / GRID as f64).collect();
    let values = grid.iter().map(|&a| pp(a)).collect::<Result<Vec<_>>>()?;
    let best = (0..values.len())
        .min_by(|&i, &j| values[i].total_cmp(&values[j]))
        .unwrap_or(0);
    let (mut lo, mut hi) = (
        grid[best.saturating_sub(1)],
        grid[(best + 1).min(grid.len() - 1)],
    );
    let r = (5.0_f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut f1, mut f2) = (pp(x1)?, pp(x2)?);
    for _ in 0..GOLDEN_STEPS {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - r * (hi - lo);
            f1 = pp(x1)?;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + r * (hi - lo);
            f2 = pp(x2)?;
        }
    }
    let (a, f) = [(x1, f1), (x2, f2), (grid[best], values[best])]
        .into_iter()
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap_or((grid[best], values[best]));
    Ok((with(a), f))
}
