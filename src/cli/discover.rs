//! `geardyn discover --data DIR [--out DIR]`: discrepancy discovery on a Munro-style data set
//! (issue 5), writing discovery.json, a report and before/after residual plots.

use super::common::{check_out_replaced, print_text};
use super::limits::{real, whole};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::data::load_munro;
use geardyn::discover::{discover, Correlation, DiscoverOptions, TailChoice, MAX_BOOTSTRAP};
use geardyn::report::data_kind_banner;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Data set folder (rig.toml + CSV, Munro layout: load_n,speed_rpm,dte_pp_um).
    #[arg(long)]
    data: PathBuf,
    /// Output folder (discovery.json, report.md, index.html, residual plots).
    #[arg(long, default_value = "reports/discover")]
    out: PathBuf,
    /// Parametric bootstrap replicates under M0, in [100, 99999] (100 is the least at which
    /// a p-value can pass Holm's correction over the 5 candidates at alpha 0.05; the run
    /// checks).
    #[arg(long, default_value_t = 399, allow_hyphen_values = true, value_parser = whole(1..=MAX_BOOTSTRAP))]
    bootstrap: usize,
    /// Seed of the bootstrap.
    #[arg(long, default_value_t = 12345)]
    seed: u64,
    /// Stated measurement noise, um (one standard deviation at every point), in (0, 1000).
    /// Default: what the data set states (a dte_pp_sd_um column, rig.toml [noise]), else
    /// estimated from the data (floor plus a part proportional to the level).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    noise_um: Option<f64>,
    /// Tails of the estimated noise: auto (Student-t errors when the data say so) or gaussian.
    #[arg(long, default_value = "auto")]
    tails: String,
    /// The errors' correlation along speed within a curve: auto (estimated, kept when the
    /// data reject independent errors), off, on (always estimated) or a stated length in rpm.
    #[arg(long, default_value = "auto")]
    correlation: String,
}

/// The correlation setting of a command-line word.
pub fn parse_correlation(s: &str) -> anyhow::Result<Correlation> {
    Ok(match s {
        "auto" => Correlation::Auto,
        "off" => Correlation::Stated(0.0),
        "on" => Correlation::Estimated,
        s => match s.parse::<f64>() {
            Ok(l) if l.is_finite() && (0.0..1e6).contains(&l) => Correlation::Stated(l),
            _ => anyhow::bail!(
                "invalid --correlation '{s}': auto, off, on or a length in rpm in [0, 1e6)"
            ),
        },
    })
}

/// The tails setting of a command-line word.
pub fn parse_tails(s: &str) -> anyhow::Result<TailChoice> {
    match s {
        "auto" => Ok(TailChoice::Auto),
        "gaussian" => Ok(TailChoice::Gaussian),
        _ => anyhow::bail!("unknown --tails '{s}': auto or gaussian"),
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_replaced("--out", &a.out)?;
    let data = load_munro(&a.data)?;
    let opts = DiscoverOptions {
        correlation: parse_correlation(&a.correlation)?,
        bootstrap: a.bootstrap,
        seed: a.seed,
        noise_um: a.noise_um,
        tails: parse_tails(&a.tails)?,
        ..DiscoverOptions::default()
    };
    let d = discover(&data, &opts, &Bar::new())?;
    let written = geardyn::report::write_discovery(&data, &d, &a.out)?;
    let mut text = format!("{}\n", data_kind_banner(&data.rig));
    text.push_str(&geardyn::report::discovery_summary(&d));
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}
