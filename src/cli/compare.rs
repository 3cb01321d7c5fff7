//! `geardyn compare`: harmonic balance and simulation overlaid for the same parameters
//! (Figs 11-13), with where each method finds steady states the other misses.

use super::common::{check_out_dir, commit, print_json, stage, write_text};
use super::limits::{real, whole};
use super::model_args::{FrequencyRange, ModelArgs};
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
    #[command(flatten)]
    frequencies: FrequencyRange,
    /// Grid of initial conditions q(0), q'(0) of the all-attractor search, dimensionless:
    /// LO:HI:N (at most 501 per axis, and at most 2000000 initial conditions over all
    /// frequencies).
    #[arg(long, default_value = super::common::SWEEP_IC_GRID, allow_hyphen_values = true)]
    ic_grid: String,
    /// Harmonics H of the AFT ansatz, 1 to 128.
    #[arg(long, default_value_t = 15, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::hb::MAX_HARMONICS))]
    harmonics: usize,
    /// Relative q_a tolerance of a match between the methods (0.01 = 1%), in (0, 1].
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true,
          value_parser = real(0.0, 1.0, true))]
    tolerance: f64,
    /// Print the JSON report instead of the CSV of all points on standard output (columns:
    /// docs/output-columns.md).
    #[arg(long)]
    json: bool,
    /// Folder for compare.png/.svg, compare.csv and compare.json.
    #[arg(long, default_value = "reports/compare")]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let m = a.model.resolve()?;
    let settings = CompareSettings {
        fm: m.fm,
        fah: m.fah,
        fat: m.fat,
        zeta: m.zeta,
        omegas: a.frequencies.omegas(&m)?,
        grid: IcGrid::parse(&a.ic_grid)?,
        harmonics: a.harmonics,
        tolerance: a.tolerance,
    };
    m.print_conversion(settings.omegas[0]);
    m.at(settings.omegas[0])?;
    let ics = settings.omegas.len() * settings.grid.n * settings.grid.n;
    if ics > 2_000_000 {
        anyhow::bail!(
            "{} and --ic-grid '{}' make {ics} initial conditions: at most 2000000; use \
             fewer frequencies or a coarser grid",
            a.frequencies.text(),
            a.ic_grid
        );
    }
    let c = compare(&settings, &Bar::new())?;
    let csv = c.csv(m.rig.as_ref())?;
    let mut json = c.json();
    if m.rig.is_some() {
        json["parameters"]["rig_units"] = m.json();
    }
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_panels(
        "Harmonic balance vs digital simulation",
        &compare_panels(&c, m.rig.as_ref()),
        2,
        &d.join("compare"),
    )?;
    write_text(&d.join("compare.csv"), &csv)?;
    write_text(
        &d.join("compare.json"),
        &format!("{}\n", serde_json::to_string_pretty(&json)?),
    )?;
    written.extend([d.join("compare.csv"), d.join("compare.json")]);
    let written = commit(stage, &written)?;
    if a.json {
        print_json(&json)?;
    } else {
        super::common::print_text(&csv)?;
    }
    let rpm = m.rig.as_ref().map(|op| move |w: f64| op.speed_rpm(w));
    let rpm = rpm.as_ref().map(|f| f as &dyn Fn(f64) -> f64);
    for line in c.gaps.summary_lines_at(rpm) {
        eprintln!("{line}");
    }
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
