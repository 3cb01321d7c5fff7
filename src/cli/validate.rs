//! `geardyn validate munro|kubo`: fit, predict, compare, and write fits/ and reports/.

use super::common::{check_out_dir, print_text};
use super::progress_bar::Bar;
use clap::{Args as ClapArgs, Subcommand};
use geardyn::data::{load_kubo, load_munro};
use geardyn::report::{data_kind_banner, write_kubo_report, write_munro_report};
use geardyn::validate::{validate_kubo, validate_munro, KuboOptions, MunroOptions};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(subcommand)]
    which: Which,
}

#[derive(Subcommand, Debug)]
enum Which {
    /// Munro's pp dynamic transmission error at four loads (Figs 19-22).
    Munro(Dirs),
    /// Kubo's dynamic factor envelope (Fig. 23).
    Kubo(Dirs),
}

#[derive(ClapArgs, Debug)]
struct Dirs {
    /// Data set folder (rig.toml + CSV); default data/munro or data/kubo.
    #[arg(long)]
    data: Option<PathBuf>,
    /// Folder for the fitted-parameter JSON.
    #[arg(long, default_value = "fits")]
    fits: PathBuf,
    /// Parent folder of the report folder (reports/munro or reports/kubo).
    #[arg(long, default_value = "reports")]
    reports: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let (Which::Munro(d) | Which::Kubo(d)) = &a.which;
    check_out_dir("--fits", &d.fits)?;
    check_out_dir("--reports", &d.reports)?;
    let (written, banner, summary) = match a.which {
        Which::Munro(d) => {
            let data = load_munro(&d.data.unwrap_or_else(|| PathBuf::from("data/munro")))?;
            let r = validate_munro(&data, &MunroOptions::default(), &Bar::new())?;
            let written = write_munro_report(&data, &r, &d.fits, &d.reports.join("munro"))?;
            let mut s = format!(
                "zeta {:.5} [{}], omega_n {:.1} Hz [{}]\n",
                r.zeta,
                ci_text(r.fit.estimate.ci95[0], 5),
                r.omega_n_hz,
                ci_text(r.fit.estimate.ci95[1], 2)
            );
            let n = &r.fit.estimate.noise;
            s.push_str(&format!(
                "noise: floor {:.3} um, relative {:.4}, {}{}\n",
                n.model.floor,
                n.model.relative,
                match n.model.distribution {
                    geardyn::fit::Distribution::Gaussian => "Gaussian".to_string(),
                    geardyn::fit::Distribution::StudentT { dof } =>
                        format!("Student-t ({dof} dof)"),
                },
                if n.outliers.is_empty() {
                    String::new()
                } else {
                    format!(", {} outlying points", n.outliers.len())
                }
            ));
            for l in &r.loads {
                s.push_str(&format!(
                    "  {:>7.1} N {:>10}: F_hat {:6.2}, RMS {:.3} um{}, jump error {}\n",
                    l.load_n,
                    if l.fitted { "(fit)" } else { "(predicted)" },
                    l.force_ratio,
                    l.rms_um,
                    match (l.not_period1_points, l.rms_period1_um) {
                        (0, _) => String::new(),
                        (n, Some(r)) => format!(
                            " ({r:.3} um where the model is period-1; {n} speeds chaotic or subharmonic)"
                        ),
                        (n, None) => format!(" ({n} speeds chaotic or subharmonic)"),
                    },
                    l.jump_error_rpm
                        .map_or("-".to_string(), |e| format!("{e:.0} rpm"))
                ));
            }
            (written, data_kind_banner(&data.rig), s)
        }
        Which::Kubo(d) => {
            let data = load_kubo(&d.data.unwrap_or_else(|| PathBuf::from("data/kubo")))?;
            let r = validate_kubo(&data, &KuboOptions::default(), &Bar::new())?;
            let written = write_kubo_report(&data, &r, &d.fits, &d.reports.join("kubo"))?;
            let s = format!(
                "zeta {:.4}, omega_n {:.1} Hz ({}), model inside the envelope at {:.0}% of speeds, jump error {}\n",
                r.zeta,
                r.omega_n_hz,
                r.parameter_source,
                100.0 * r.inside_fraction,
                r.jump_error_rpm.map_or("-".to_string(), |e| format!("{e:.0} rpm"))
            );
            (written, data_kind_banner(&data.rig), s)
        }
    };
    let mut text = format!("{banner}\n{summary}");
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}

fn ci_text((a, b): (f64, f64), digits: usize) -> String {
    format!("95% {a:.digits$} .. {b:.digits$}")
}
