//! `geardyn bifurcation`: Poincare points against Omega, F_hat or zeta, from every attractor of
//! an IC grid and from a carried sweep, with chaotic transients drawn apart and folds / period
//! doublings marked (CSV, PNG, SVG).

use super::common::{check_out_dir, commit, print_text, stage, write_text, EscapeArgs, SolverArgs};
use super::limits::{real, FAH, FM, OMEGA, ZETA};
use super::model_args::parse_range;
use super::progress_bar::Bar;
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::bifurcation::{
    bifurcation, bifurcation_csv, bifurcation_figure, BifurcationOptions, Parameter,
};
use geardyn::plot::write_xy;
use geardyn::sim::IcGrid;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Mean load F_m, dimensionless, in [0, 1e4] (not used with --vary fhat).
    #[arg(long = "fm", allow_hyphen_values = true, value_parser = real(FM.0, FM.1, false))]
    fm: Option<f64>,
    /// STE amplitude F_ah, dimensionless, in [0, 1e3].
    #[arg(long = "fah", allow_hyphen_values = true, value_parser = real(FAH.0, FAH.1, false))]
    fah: f64,
    /// Damping ratio ζ, dimensionless, in [0.001, 0.9] (not used with --vary zeta).
    #[arg(long, allow_hyphen_values = true, value_parser = real(ZETA.0, ZETA.1, false))]
    zeta: Option<f64>,
    /// Mesh frequency over natural frequency Ω_h, dimensionless, in [0.001, 100] (not used with
    /// --vary omega).
    #[arg(long, allow_hyphen_values = true, value_parser = real(OMEGA.0, OMEGA.1, false))]
    omega: Option<f64>,
    /// The parameter varied: omega, fhat (F̂ = F_m / F_ah through F_m at fixed F_ah, as Fig. 7)
    /// or zeta (as Fig. 8).
    #[arg(long, value_enum)]
    vary: Vary,
    /// Values START:STOP:STEP of the varied parameter, dimensionless (Ω_h in [0.001, 100], F̂ in
    /// [0.001, 1e4], ζ in [0.001, 0.9]; at most 2001 values).
    #[arg(long, allow_hyphen_values = true)]
    range: String,
    /// grid: every attractor of the IC grid at each value; carried: one sweep carrying the last
    /// state; both.
    #[arg(long, value_enum, default_value_t = Mode::Both)]
    mode: Mode,
    /// Grid of initial conditions q(0), q'(0) at each value (dimensionless: half backlashes):
    /// LO:HI:N (LO and HI in [-1e4, 1e4]; at most 501 per axis and 2000000 initial conditions
    /// over all values).
    #[arg(long, default_value = super::common::SWEEP_IC_GRID, allow_hyphen_values = true)]
    ic_grid: String,
    /// Poincaré points drawn per non-periodic set, 10 to 2000.
    #[arg(long, default_value_t = 200, allow_hyphen_values = true,
          value_parser = super::limits::whole(10..=2000))]
    cloud_points: usize,
    #[command(flatten)]
    solver: SolverArgs,
    #[command(flatten)]
    escape: EscapeArgs,
    /// Output folder for bifurcation.png/.svg, bifurcation.csv and marks.csv.
    #[arg(long, default_value = "reports/bifurcation")]
    out: PathBuf,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Vary {
    Omega,
    Fhat,
    Zeta,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Grid,
    Carried,
    Both,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let (parameter, bounds) = match a.vary {
        Vary::Omega => (Parameter::Omega, OMEGA),
        Vary::Fhat => (Parameter::Fhat, (1e-3, 1e4)),
        Vary::Zeta => (Parameter::Zeta, ZETA),
    };
    let need = |v: Option<f64>, flag: &str, unless: &str| {
        v.ok_or_else(|| anyhow::anyhow!("{flag} is needed unless --vary {unless}"))
    };
    let values = parse_range("--range", &a.range, bounds)?;
    if values.len() > geardyn::bifurcation::MAX_VALUES {
        anyhow::bail!(
            "--range '{}' gives {} values: at most {}",
            a.range,
            values.len(),
            geardyn::bifurcation::MAX_VALUES
        );
    }
    let fm = match a.vary {
        Vary::Fhat => a.fm.unwrap_or(0.0),
        _ => need(a.fm, "--fm", "fhat")?,
    };
    let zeta = match a.vary {
        Vary::Zeta => a.zeta.unwrap_or(values[0]),
        _ => need(a.zeta, "--zeta", "zeta")?,
    };
    let omega = match a.vary {
        Vary::Omega => a.omega.unwrap_or(values[0]),
        _ => need(a.omega, "--omega", "omega")?,
    };
    let grid = IcGrid::parse(&a.ic_grid)?;
    let mut steady = a.solver.options()?;
    steady.escape = a.escape.budget(EscapeArgs::sweep_default());
    let opts = BifurcationOptions {
        fm,
        fah: a.fah,
        zeta,
        omega,
        parameter,
        values,
        grid: (a.mode != Mode::Carried).then_some(grid),
        carried: a.mode != Mode::Grid,
        steady,
        cloud_points: a.cloud_points,
    };
    // Every value's model is checked before the long run.
    for &v in &opts.values {
        opts.model(v)?;
    }
    let factory = a.solver.factory();
    let b = bifurcation(&opts, &factory, &Bar::new())?;
    let caption = match parameter {
        Parameter::Omega => format!("F_m = {fm}, F_ah = {}, ζ = {zeta}", a.fah),
        Parameter::Fhat => format!("F_ah = {}, ζ = {zeta}, Ω = {omega}", a.fah),
        Parameter::Zeta => format!("F_m = {fm}, F_ah = {}, Ω = {omega}", a.fah),
    };
    let fig = bifurcation_figure(
        &b,
        &format!("Bifurcation diagram over {}", parameter.label()),
        &format!(
            "{caption}, {}x{} ICs, {}",
            grid.n,
            grid.n,
            a.solver.integrator_name(&opts.model(opts.values[0])?)
        ),
    );
    let (points, marks) = bifurcation_csv(&b);
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_xy(&fig, &d.join("bifurcation"))?;
    write_text(&d.join("bifurcation.csv"), &points)?;
    write_text(&d.join("marks.csv"), &marks)?;
    written.push(d.join("bifurcation.csv"));
    written.push(d.join("marks.csv"));
    let written = commit(stage, &written)?;
    let mut text = format!(
        "{} Poincare points at {} values; {} marks\n",
        b.points.len(),
        opts.values.len(),
        b.marks.len()
    );
    for m in &b.marks {
        text.push_str(&format!("  {} at {:.4} ({})\n", m.what, m.value, m.source));
    }
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}
