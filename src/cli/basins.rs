//! `geardyn basins`: the map of which steady state each initial condition reaches (Figs 3, 6, 14).

use super::attractor_report;
use super::common::{
    check_out_dir, commit, print_text, stage, unsettled_warning, with_omega, write_text,
    EscapeArgs, SolverArgs,
};
use super::geometry_excitation::ExcitationArgs;
use super::model_args::{num, Frequency, ModelArgs, SteadyInRigUnits};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::plot::{write_category_map, CategoryMap};
use geardyn::reproduce::describe_attractor;
use geardyn::sim::{find_attractors, EscapeBudget, IcGrid};
use serde_json::json;
use std::path::PathBuf;

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
    #[arg(long, default_value = "-2:2:101", allow_hyphen_values = true)]
    ic_grid: String,
    #[command(flatten)]
    solver: SolverArgs,
    #[command(flatten)]
    escape: EscapeArgs,
    /// Output folder for basins.csv, attractors.json and the basin map (PNG + SVG).
    #[arg(long)]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let grid = IcGrid::parse(&a.ic_grid)?;
    if grid.n < 2 {
        // One initial condition would paint the whole square its attractor's colour.
        anyhow::bail!(
            "--ic-grid {}: a basin map needs at least 2 values per axis",
            a.ic_grid
        );
    }
    let (m, omega, model) = a.model.at_frequency_with(&a.frequency, &a.excitation)?;
    let flow = a.solver.flow(&model)?;
    let mut opts = a.solver.options()?;
    opts.escape = a.escape.budget(EscapeBudget::default());
    let map = find_attractors(flow.as_ref(), &grid, &opts, &Bar::new())?;

    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "q0",
        "v0",
        "attractor",
        "period",
        "impact",
        "motion",
        "qa",
        "qm",
    ])?;
    for (x, &l) in grid.points().iter().zip(&map.labels) {
        let s = &map.attractors[l].steady;
        w.write_record([
            format!("{}", x[0]),
            format!("{}", x[1]),
            l.to_string(),
            s.period.map_or(String::new(), |p| p.to_string()),
            s.impact.name().to_string(),
            s.motion.name().to_string(),
            format!("{:.8}", s.qa),
            format!("{:.8}", s.qm),
        ])?;
    }
    let csv_text = String::from_utf8(w.into_inner()?)?;
    let legend: Vec<String> = map
        .attractors
        .iter()
        .enumerate()
        .map(|(i, at)| {
            let units = SteadyInRigUnits::new(&m, omega, &at.steady)
                .map_or(String::new(), |r| format!(" [{}]", r.text(false)));
            format!("#{i} {}{units}", describe_attractor(at))
        })
        .collect();
    let summary = json!({
        "attractors": map.attractors.iter().map(|at| attractor_report::entry(at, &map, &m, omega)).collect::<Vec<_>>(),
        "basin": map.basin_time,
        "basin_at_periods": map.horizon,
        "grid": {"lo": grid.lo, "hi": grid.hi, "n": grid.n},
        "integrator": flow.method(),
        "parameters": with_omega(m.json(), omega),
    });
    let cat = CategoryMap {
        title: match &m.rig {
            Some(op) => format!(
                "Domains of attraction, {} rpm (Ω_h = {})",
                num(op.speed_rpm(omega)),
                num(omega)
            ),
            None => format!("Domains of attraction, Ω_h = {}", num(omega)),
        },
        caption: Some(format!(
            "{}, {}x{} initial conditions{}",
            m.caption(),
            grid.n,
            grid.n,
            if map.basin_time == geardyn::sim::BasinTime::FiniteTime {
                format!(", basins at {} periods (transients remain)", map.horizon)
            } else {
                String::new()
            }
        )),
        x_label: "q(0) (dimensionless)".into(),
        y_label: "q'(0) (dimensionless)".into(),
        x: (grid.lo, grid.hi, grid.n),
        y: (grid.lo, grid.hi, grid.n),
        cells: map.labels.iter().map(|&l| Some(l)).collect(),
        legend,
    };
    // Everything is computed before the first file is written, and staged.
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_category_map(&cat, &d.join("basins"))?;
    write_text(&d.join("basins.csv"), &csv_text)?;
    write_text(
        &d.join("attractors.json"),
        &serde_json::to_string_pretty(&summary)?,
    )?;
    written.push(d.join("basins.csv"));
    written.push(d.join("attractors.json"));
    let written = commit(stage, &written)?;
    if let Some(u) = map.attractors.iter().find(|at| !at.steady.settled) {
        eprintln!(
            "{} ({:.1}% of the initial conditions)",
            unsettled_warning(u.steady.transient_periods),
            100.0 * u.basin_fraction
        );
    }
    let mut text = String::new();
    for line in &cat.legend {
        text.push_str(line);
        text.push('\n');
    }
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}
