//! `geardyn sweep`: steady states over a frequency range (carried up/down, or all attractors).

use super::common::{check_out_dir, commit, print_text, stage, EscapeArgs, SolverArgs};
use super::geometry_excitation::ExcitationArgs;
use super::limits::{real, STATE};
use super::model_args::{FrequencyRange, ModelArgs};
use super::progress_bar::Bar;
use super::response_plot::{sweep_csv, write_response_plot, ResponseRow};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::sim::{sweep, Branch, IcGrid, SweepPlan};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    excitation: ExcitationArgs,
    #[command(flatten)]
    frequencies: FrequencyRange,
    /// up / down carry the last steady state (Fig. 13); all searches the IC grid at each
    /// frequency; both runs up then down.
    #[arg(long, value_enum, default_value_t = Direction::Up)]
    direction: Direction,
    /// Grid of initial conditions q(0), q'(0) for --direction all, dimensionless: LO:HI:N (at
    /// most 501 per axis, and at most 2000000 initial conditions over all frequencies).
    #[arg(long, default_value = super::common::SWEEP_IC_GRID, allow_hyphen_values = true)]
    ic_grid: String,
    /// Initial q of a carried sweep, dimensionless, in [-1e6, 1e6] (default: static equilibrium
    /// 1 + F_m).
    #[arg(long, allow_hyphen_values = true, value_parser = real(-STATE, STATE, false))]
    q0: Option<f64>,
    /// Initial q' of a carried sweep, dimensionless, in [-1e6, 1e6].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = real(-STATE, STATE, false))]
    v0: f64,
    #[command(flatten)]
    solver: SolverArgs,
    #[command(flatten)]
    escape: EscapeArgs,
    /// Output format on standard output (columns: docs/output-columns.md).
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Folder for the plot (PNG + SVG) and a copy of the CSV.
    #[arg(long, default_value = "reports/sweep")]
    out: PathBuf,
}

/// Largest number of initial conditions a `--direction all` sweep integrates (frequencies
/// times grid points): about 10 minutes on two cores where the motion is periodic.
const MAX_ALL_ICS: usize = 2_000_000;

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Direction {
    Up,
    Down,
    All,
    Both,
}

impl Direction {
    /// The sweep in words, for the figure's caption.
    fn name(self) -> &'static str {
        match self {
            Direction::Up => "carried up",
            Direction::Down => "carried down",
            Direction::All => "every attractor of the IC grid",
            Direction::Both => "carried up, then down",
        }
    }
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Csv,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let m = a.model.resolve_with(&a.excitation)?;
    let omegas = a.frequencies.omegas(&m)?;
    let grid = IcGrid::parse(&a.ic_grid)?;
    if a.direction == Direction::All && omegas.len() * grid.n * grid.n > MAX_ALL_ICS {
        anyhow::bail!(
            "--direction all with {} ({} frequencies) and --ic-grid '{}' ({} initial \
             conditions each) integrates {} initial conditions: at most {MAX_ALL_ICS}; use \
             fewer frequencies or a coarser grid",
            a.frequencies.text(),
            omegas.len(),
            a.ic_grid,
            grid.n * grid.n,
            omegas.len() * grid.n * grid.n
        );
    }
    m.print_conversion(omegas[0]);
    let model = m.at(omegas[0])?;
    let mut opts = a.solver.options()?;
    opts.escape = a.escape.budget(EscapeArgs::sweep_default());
    let factory = a.solver.factory();
    let branches: &[Branch] = match a.direction {
        Direction::Up => &[Branch::Up],
        Direction::Down => &[Branch::Down],
        Direction::All => &[Branch::All],
        Direction::Both => &[Branch::Up, Branch::Down],
    };
    let mut points = Vec::new();
    for &branch in branches {
        let plan = SweepPlan {
            omegas: omegas.clone(),
            branch,
            x0: [a.q0.unwrap_or(1.0 + m.fm), a.v0],
            grid,
            opts: opts.clone(),
        };
        points.extend(sweep(&factory, &model, &plan, &Bar::new())?);
    }
    let csv = sweep_csv(&points, &m)?;
    let caption = format!(
        "{}, sweep {}, integrator {}",
        m.caption(),
        a.direction.name(),
        a.solver.integrator_name(&model)
    );
    let rows: Vec<ResponseRow> = points.iter().map(ResponseRow::from).collect();
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_response_plot(
        &rows,
        m.rig.as_ref(),
        "Frequency response (digital simulation)",
        &caption,
        &d.join("sweep"),
    )?;
    super::common::write_text(&d.join("sweep.csv"), &csv)?;
    written.push(d.join("sweep.csv"));
    let written = commit(stage, &written)?;
    print_text(&csv)?;
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
