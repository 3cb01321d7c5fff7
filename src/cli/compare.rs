//! `geardyn compare`: harmonic balance and simulation overlaid for the same parameters
//! (Figs 11-13), with where each method finds steady states the other misses.

use super::common::{parse_range, print_json, write_text, ModelArgs};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::compare::{compare, compare_panels, CompareSettings};
use geardyn::plot::write_panels;
use geardyn::sim::IcGrid;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Frequency range START:STOP:STEP.
    #[arg(long, allow_hyphen_values = true)]
    omega: String,
    /// Grid of initial conditions of the all-attractor search: LO:HI:N.
    #[arg(long, default_value = "-2:2:11", allow_hyphen_values = true)]
    ic_grid: String,
    /// Harmonics H of the AFT ansatz.
    #[arg(long, default_value_t = 15)]
    harmonics: usize,
    /// Relative q_a tolerance of a match between the methods (0.01 = 1%).
    #[arg(long, default_value_t = 0.01)]
    tolerance: f64,
    /// Print the JSON report instead of the CSV of all points on standard output.
    #[arg(long)]
    json: bool,
    /// Folder for compare.png/.svg, compare.csv and compare.json.
    #[arg(long, default_value = "reports/compare")]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let settings = CompareSettings {
        fm: a.model.fm,
        fah: a.model.fah,
        zeta: a.model.zeta,
        omegas: parse_range("--omega", &a.omega)?,
        grid: IcGrid::parse(&a.ic_grid)?,
        harmonics: a.harmonics,
        tolerance: a.tolerance,
    };
    let c = compare(&settings, &Bar::new())?;
    let csv = c.csv()?;
    let json = c.json();
    let mut written = write_panels(
        "Harmonic balance vs digital simulation",
        &compare_panels(&c),
        2,
        &a.out.join("compare"),
    )?;
    write_text(&a.out.join("compare.csv"), &csv)?;
    write_text(
        &a.out.join("compare.json"),
        &format!("{}\n", serde_json::to_string_pretty(&json)?),
    )?;
    written.extend([a.out.join("compare.csv"), a.out.join("compare.json")]);
    if a.json {
        print_json(&json)?;
    } else {
        super::common::print_text(&csv)?;
    }
    for line in c.gaps.summary_lines() {
        eprintln!("{line}");
    }
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
