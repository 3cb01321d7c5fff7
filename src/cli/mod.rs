//! Command definitions (design.md section 3) and dispatch.

mod attractor_report;
mod attractors;
mod basins;
mod bench;
mod bifurcation;
mod common;
mod compare;
mod digitize;
mod digitize_parse;
mod discover;
mod discover_study;
mod escape;
mod examples;
mod geometry_excitation;
mod hbm;
mod init_data;
mod limits;
mod mesh;
mod model_args;
mod progress_bar;
mod reproduce;
mod response_plot;
mod simulate;
mod simulate_figures;
mod study;
mod sweep;
mod synth;
mod validate;
mod validate_study;

use clap::{Parser, Subcommand};

/// Non-linear dynamics of a spur gear pair with backlash (Kahraman & Singh 1990).
#[derive(Parser, Debug)]
#[command(name = "geardyn", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Steady state from one initial condition (period, impact regime, q_a, q_m, pp DTE, D_L),
    /// dimensionless or in the rig's units (--rig).
    #[command(after_help = examples::SIMULATE)]
    Simulate(simulate::Args),
    /// Every coexisting steady state from a grid of initial conditions, with basin fractions.
    #[command(after_help = examples::ATTRACTORS)]
    Attractors(attractors::Args),
    /// Basins of attraction over a grid of initial conditions (CSV, JSON, PNG and SVG map).
    #[command(after_help = examples::BASINS)]
    Basins(basins::Args),
    /// Harmonic-balance frequency response: every solution at each frequency (Sec. 4, Fig. 10).
    #[command(after_help = examples::HBM)]
    Hbm(hbm::Args),
    /// STE and mesh stiffness from the gear geometry: waveforms, harmonics and the Harris map
    /// (STE peak-to-peak against load) for a tip relief, given or sized for a design load.
    #[command(after_help = examples::MESH)]
    Mesh(mesh::Args),
    /// Fit and validate against a data set: pp DTE curves (Munro layout) or a dynamic-factor
    /// envelope (Kubo layout), the shipped ones or your own (--data).
    #[command(after_help = examples::VALIDATE)]
    Validate(validate::Args),
    /// Write a synthetic data set (labelled synthetic, with its truth) in the data layout.
    #[command(after_help = examples::SYNTH)]
    Synth(synth::Args),
    /// Start a data set of your own measurements: a commented rig.toml template (every key
    /// with unit and range) and a CSV file with its header.
    #[command(after_help = examples::INIT_DATA)]
    InitData(init_data::Args),
    /// Timings: one steady state per integrator, a basin map, `validate munro`.
    #[command(after_help = examples::BENCH)]
    Bench(bench::Args),
    /// Frequency sweep by simulation: carried up / down (Fig. 13) or every attractor at each
    /// frequency, dimensionless or in the rig's units (--rig).
    #[command(after_help = examples::SWEEP)]
    Sweep(sweep::Args),
    /// Bifurcation diagram: Poincare points against Omega, F_hat or zeta (IC grid and carried
    /// sweep), chaotic transients apart, folds and period doublings marked (CSV, PNG, SVG).
    #[command(after_help = examples::BIFURCATION)]
    Bifurcation(bifurcation::Args),
    /// Transient chaos at one point: every initial condition followed to a long horizon by both
    /// integrators; survival curves, escape rates with 95% intervals (PNG, SVG, CSV, JSON).
    #[command(after_help = examples::ESCAPE)]
    Escape(escape::Args),
    /// Figure image (PNG) to CSV: the curve of one colour, with axis calibration (Figs 19-23).
    #[command(after_help = examples::DIGITIZE)]
    Digitize(digitize::Args),
    /// Harmonic balance (df-exact, AFT) and simulation overlaid, with the steady states each
    /// method misses (Figs 11-13).
    #[command(after_help = examples::COMPARE)]
    Compare(compare::Args),
    /// The paper's studies: parametric (Figs 15-18), excitation (Figs 24, 25), superposition
    /// (Figs 26-28), combined excitation (Fig. 29).
    #[command(after_help = examples::STUDY)]
    Study(study::Args),
    /// Discrepancy discovery: test the paper's model against the curves, name the missing
    /// effect from a library, add it, and show the gap before and after.
    #[command(after_help = examples::DISCOVER)]
    Discover(discover::Args),
    /// Null-rate and recovery studies of `discover` on seeded synthetic sets with one effect
    /// hidden (or none), with Wilson 95% intervals.
    #[command(after_help = examples::DISCOVER_STUDY)]
    DiscoverStudy(discover_study::Args),
    /// Coverage of `validate munro`'s 95% intervals of zeta and omega_n on seeded synthetic
    /// design-load curves (another integrator, a chosen noise family and speed grid).
    #[command(after_help = examples::VALIDATE_STUDY)]
    ValidateStudy(validate_study::Args),
    /// Every figure of the paper (PNG + SVG) and a claim-by-claim reproduction report
    /// (REPRODUCTION.md, index.html, claims.json, claims.csv).
    #[command(after_help = examples::REPRODUCE)]
    Reproduce(reproduce::Args),
}

/// Parse the command line. Negative numbers are values everywhere (`--periods -5` reaches the
/// range check of `--periods` instead of clap's "unexpected argument").
pub fn parse() -> Cli {
    use clap::{CommandFactory, FromArgMatches};
    let matches = allow_negative_numbers(Cli::command()).get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

fn allow_negative_numbers(cmd: clap::Command) -> clap::Command {
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    let mut cmd = cmd.allow_negative_numbers(true);
    for n in names {
        cmd = cmd.mut_subcommand(n, allow_negative_numbers);
    }
    cmd
}

/// The error and its causes on one line, each text once: a cause whose text is already part of
/// the message (an I/O error shown by its wrapper) is not repeated.
pub fn error_text(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let t = cause.to_string();
        if !text.contains(&t) {
            text.push_str(": ");
            text.push_str(&t);
        }
    }
    text
}

/// Run the parsed command.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Simulate(a) => simulate::run(a),
        Command::Attractors(a) => attractors::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Escape(a) => escape::run(a),
        Command::Bifurcation(a) => bifurcation::run(a),
        Command::Basins(a) => basins::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Hbm(a) => hbm::run(a),
        Command::Digitize(a) => digitize::run(a),
        Command::Mesh(a) => mesh::run(a),
        Command::Validate(a) => validate::run(a),
        Command::Synth(a) => synth::run(a),
        Command::InitData(a) => init_data::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Study(a) => study::run(a),
        Command::Discover(a) => discover::run(a),
        Command::DiscoverStudy(a) => discover_study::run(a),
        Command::Reproduce(a) => reproduce::run(a),
        Command::ValidateStudy(a) => validate_study::run(a),
    }
}
