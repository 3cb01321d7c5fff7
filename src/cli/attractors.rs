//! `geardyn attractors`: every coexisting steady state from a grid of initial conditions.

use super::attractor_report;
use super::common::{
    print_json, print_text, unsettled_warning, with_omega, EscapeArgs, SolverArgs,
};
use super::geometry_excitation::ExcitationArgs;
use super::model_args::{Frequency, ModelArgs};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::sim::{find_attractors, EscapeBudget, IcGrid};
use serde_json::json;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    excitation: ExcitationArgs,
    #[command(flatten)]
    frequency: Frequency,
    /// Grid of initial conditions q(0), q'(0) (dimensionless: half backlashes): LO:HI:N (N
    /// values per axis, at most 501; LO and HI in [-1e4, 1e4]).
    #[arg(long, default_value = "-2:2:21", allow_hyphen_values = true)]
    ic_grid: String,
    #[command(flatten)]
    solver: SolverArgs,
    #[command(flatten)]
    escape: EscapeArgs,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let grid = IcGrid::parse(&a.ic_grid)?;
    let (m, omega, model) = a.model.at_frequency_with(&a.frequency, &a.excitation)?;
    let flow = a.solver.flow(&model)?;
    let mut opts = a.solver.options()?;
    opts.escape = a.escape.budget(EscapeBudget::default());
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
            .map(|at| attractor_report::entry(at, &map, &m, omega))
            .collect();
        print_json(&json!({
            "attractors": list,
            "basin": map.basin_time,
            "basin_at_periods": map.horizon,
            "grid": {"lo": grid.lo, "hi": grid.hi, "n": grid.n},
            "integrator": flow.method(),
            "parameters": with_omega(m.json(), omega),
        }))?;
    } else {
        let mut text = attractor_report::header(&map, omega);
        for (i, at) in map.attractors.iter().enumerate() {
            text.push_str(&attractor_report::line(i, at, &map, &m, omega));
        }
        print_text(&text)?;
    }
    Ok(())
}
