//! `geardyn attractors`: every coexisting steady state from a grid of initial conditions.

use super::common::{print_json, print_text, unsettled_warning, ModelArgs, SolverArgs};
use super::limits::{real, OMEGA};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::sim::{find_attractors, IcGrid};
use serde_json::json;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Mesh (excitation) frequency Omega_h, in [0.001, 100].
    #[arg(long, allow_hyphen_values = true, value_parser = real(OMEGA.0, OMEGA.1, false))]
    omega: f64,
    /// Grid of initial conditions q(0), q'(0): LO:HI:N (N values per axis, at most 501).
    #[arg(long, default_value = "-2:2:21", allow_hyphen_values = true)]
    ic_grid: String,
    #[command(flatten)]
    solver: SolverArgs,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let grid = IcGrid::parse(&a.ic_grid)?;
    let model = a.model.model(a.omega)?;
    let flow = a.solver.flow(&model)?;
    let opts = a.solver.options()?;
    let map = find_attractors(flow.as_ref(), &grid, &opts, &Bar::new())?;
    if let Some(u) = map.attractors.iter().find(|at| !at.steady.settled) {
        eprintln!(
            "{} ({:.1}% of the initial conditions)",
            unsettled_warning(u.steady.transient_periods),
            100.0 * u.basin_fraction
        );
    }
    if a.json {
        let list: Vec<_> = map
            .attractors
            .iter()
            .map(|at| {
                let s = &at.steady;
                json!({
                    "period": s.period, "settled": s.settled, "motion": s.motion, "impact": s.impact, "case": s.impact.case(),
                    "qa": s.qa, "qm": s.qm, "q_min": s.q_min, "q_max": s.q_max, "dte_pp": s.dte_pp,
                    "dl_max": s.dl_max, "lyapunov": s.lyapunov, "floquet": s.floquet,
                    "basin_fraction": at.basin_fraction, "basin_count": at.basin_count,
                    "example_ic": at.example_ic, "poincare": s.poincare,
                })
            })
            .collect();
        print_json(&json!({
            "attractors": list,
            "grid": {"lo": grid.lo, "hi": grid.hi, "n": grid.n},
            "integrator": flow.method(),
            "parameters": {"fm": a.model.fm, "fah": a.model.fah, "zeta": a.model.zeta, "omega": a.omega},
        }))?;
    } else {
        let mut text = format!(
            "{} attractor(s) from {}x{} initial conditions in [{}, {}]^2\n",
            map.attractors.len(),
            grid.n,
            grid.n,
            grid.lo,
            grid.hi
        );
        for (i, at) in map.attractors.iter().enumerate() {
            let s = &at.steady;
            text.push_str(&format!(
                "  #{i}: period {} ({:?}), impact {}, qa {:.5}, qm {:.5}, basin {:.1}%{}\n",
                s.period.map_or("none".into(), |p| p.to_string()),
                s.motion,
                s.impact.name(),
                s.qa,
                s.qm,
                100.0 * at.basin_fraction,
                s.lyapunov
                    .map_or(String::new(), |l| format!(", lyapunov {l:.4}"))
            ));
        }
        print_text(&text)?;
    }
    Ok(())
}
