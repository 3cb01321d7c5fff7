//! `geardyn attractors`: every coexisting steady state from a grid of initial conditions.

use super::common::{print_json, print_text, unsettled_warning, SolverArgs};
use super::model_args::{num, Frequency, ModelArgs, SteadyInRigUnits};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::sim::{find_attractors, IcGrid};
use serde_json::json;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    frequency: Frequency,
    /// Grid of initial conditions q(0), q'(0) (dimensionless: half backlashes): LO:HI:N (N
    /// values per axis, at most 501).
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
    let m = a.model.resolve()?;
    let omega = a.frequency.omega(&m)?;
    m.print_conversion(omega);
    let model = m.at(omega)?;
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
    let mut parameters = m.json();
    parameters["omega"] = omega.into();
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
                    "rig_units": SteadyInRigUnits::json(&SteadyInRigUnits::new(&m, omega, s)),
                })
            })
            .collect();
        print_json(&json!({
            "attractors": list,
            "grid": {"lo": grid.lo, "hi": grid.hi, "n": grid.n},
            "integrator": flow.method(),
            "parameters": parameters,
        }))?;
    } else {
        let mut text = format!(
            "{} attractor(s) at Ω_h = {} from {}x{} initial conditions in [{}, {}]^2 (q and q' \
             dimensionless)\n",
            map.attractors.len(),
            num(omega),
            grid.n,
            grid.n,
            grid.lo,
            grid.hi
        );
        for (i, at) in map.attractors.iter().enumerate() {
            let s = &at.steady;
            text.push_str(&format!(
                "  #{i}: period {} ({}), impact {}, q_a {:.5}, q_m {:.5}, basin {:.1}%{}{}\n",
                s.period.map_or("none".into(), |p| p.to_string()),
                s.motion.name(),
                s.impact.name(),
                s.qa,
                s.qm,
                100.0 * at.basin_fraction,
                s.lyapunov
                    .map_or(String::new(), |l| format!(", lyapunov {l:.4}")),
                SteadyInRigUnits::new(&m, omega, s)
                    .map_or(String::new(), |r| format!("; {}", r.text(false)))
            ));
        }
        print_text(&text)?;
    }
    Ok(())
}
