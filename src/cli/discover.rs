//! `geardyn discover --data DIR [--out DIR]`: discrepancy discovery on a Munro-style data set
//! (issue 5), writing discovery.json, a report and before/after residual plots.

use super::common::print_text;
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::data::load_munro;
use geardyn::discover::{discover, DiscoverOptions};
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
    /// Parametric bootstrap replicates under M0 (at least 320 at alpha 0.05).
    #[arg(long, default_value_t = 1999)]
    bootstrap: usize,
    /// Seed of the bootstrap.
    #[arg(long, default_value_t = 12345)]
    seed: u64,
    /// Stated measurement noise in um (default: estimated from second differences of the curves).
    #[arg(long)]
    noise_um: Option<f64>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let data = load_munro(&a.data)?;
    let opts = DiscoverOptions {
        bootstrap: a.bootstrap,
        seed: a.seed,
        noise_um: a.noise_um,
        ..DiscoverOptions::default()
    };
    let d = discover(&data, &opts, &Bar::new())?;
    let written = geardyn::discover::write_discovery(&data, &d, &a.out)?;
    let mut text = format!("{}\n", data_kind_banner(&data.rig));
    text.push_str(&geardyn::discover::summary_text(&d));
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}
