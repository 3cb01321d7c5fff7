//! `geardyn escape`: transient chaos measured at one point (issue 23): every initial condition
//! followed to a long horizon by the exact flow and DOP853, with survival curves, escape rates
//! and their agreement. The long study behind docs/simulation.md, run by .ci/run.

use super::common::{check_out_dir, commit, print_json, stage};
use super::limits::{real, whole, RTOL};
use super::model_args::{Frequency, ModelArgs};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::sim::IcGrid;
use geardyn::study::{escape_study, write_escape_study, EscapeStudyOptions};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    frequency: Frequency,
    /// Grid of initial conditions q(0), q'(0) (dimensionless: half backlashes): LO:HI:N (N
    /// values per axis, at most 501; LO and HI in [-1e4, 1e4]).
    #[arg(long, default_value = "-2:2:21", allow_hyphen_values = true)]
    ic_grid: String,
    /// Age, in forcing periods from the initial conditions, to which every trajectory is
    /// followed, 1000 to 1000000. The time grows with it: about 20 s of CPU per 10,000 periods
    /// of 441 chaotic trajectories with the exact flow, several times that with DOP853.
    #[arg(long, value_name = "N", default_value_t = 40_000, allow_hyphen_values = true,
          value_parser = whole(1000..=geardyn::sim::MAX_HORIZON))]
    horizon: usize,
    /// Relative tolerance of the DOP853 check, dimensionless, in [1e-14, 0.01].
    #[arg(long, default_value_t = 1e-10, allow_hyphen_values = true,
          value_parser = real(RTOL.0, RTOL.1, false))]
    rtol: f64,
    /// Skip the DOP853 check (the exact flow only).
    #[arg(long)]
    no_dop853: bool,
    /// Output folder for survival.png/.svg, survival.csv and escape.json.
    #[arg(long, default_value = "reports/escape")]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let grid = IcGrid::parse(&a.ic_grid)?;
    let (m, omega, _) = a.model.at_frequency(&a.frequency)?;
    let opts = EscapeStudyOptions {
        fm: m.fm,
        fah: m.fah,
        fat: m.fat,
        zeta: m.zeta,
        omega,
        grid,
        horizon: a.horizon,
        dop853_rtol: (!a.no_dop853).then_some(a.rtol),
    };
    let s = escape_study(&opts, &Bar::new())?;
    let stage = stage("--out", &a.out)?;
    let written = write_escape_study(&s, stage.dir())?;
    let written = commit(stage, &written)?;
    print_json(&s.summary)?;
    if s.found_none() {
        eprintln!(
            "no chaotic transient or other non-periodic set at Ω = {omega}: every trajectory of the {0}x{0} grid settled on a periodic attractor; the survival figure and CSV have no curve",
            opts.grid.n
        );
    }
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
