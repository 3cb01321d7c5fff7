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
mod hbm;
mod limits;
mod mesh;
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
    /// Steady state from one initial condition (period, impact regime, q_a, q_m, pp DTE, D_L).
    Simulate(simulate::Args),
    /// Every coexisting steady state from a grid of initial conditions, with basin fractions.
    Attractors(attractors::Args),
    /// Basins of attraction over a grid of initial conditions (CSV, JSON, PNG and SVG map).
    Basins(basins::Args),
    /// Harmonic-balance frequency response: every solution at each Omega (Sec. 4, Fig. 10).
    Hbm(hbm::Args),
    /// STE and mesh stiffness from the gear geometry: waveforms, harmonics and the Harris map
    /// (STE peak-to-peak against load) for a tip relief, given or sized for a design load.
    Mesh(mesh::Args),
    /// Fit and validate against Munro's (pp DTE) or Kubo's (dynamic factor) data.
    Validate(validate::Args),
    /// Write a synthetic data set (labelled synthetic, with its truth) in the data layout.
    Synth(synth::Args),
    /// Performance figures: one steady state per integrator and a basin map (README numbers).
    Bench(bench::Args),
    /// Frequency sweep: carried up / down (Fig. 13) or every attractor at each Omega.
    Sweep(sweep::Args),
    /// Bifurcation diagram: Poincare points against Omega, F_hat or zeta (IC grid and carried
    /// sweep), chaotic transients apart, folds and period doublings marked (CSV, PNG, SVG).
    Bifurcation(bifurcation::Args),
    /// Transient chaos at one point: every initial condition followed to a long horizon by both
    /// integrators; survival curves, escape rates with 95% intervals (PNG, SVG, CSV, JSON).
    Escape(escape::Args),
    /// Figure image (PNG) to CSV: the curve of one colour, with axis calibration (Figs 19-23).
    Digitize(digitize::Args),
    /// Harmonic balance (df-exact, AFT) and simulation overlaid, with the steady states each
    /// method misses (Figs 11-13).
    Compare(compare::Args),
    /// The paper's studies: parametric (Figs 15-18), excitation (Figs 24, 25), superposition
    /// (Figs 26-28), combined excitation (Fig. 29).
    Study(study::Args),
    /// Discrepancy discovery: test M0 against the curves, name the missing effect from a
    /// library, add it, and show the gap before and after (issue 5).
    Discover(discover::Args),
    /// Null-rate and recovery studies of `discover` on seeded synthetic sets with one effect
    /// hidden (or none), with Wilson 95% intervals.
    DiscoverStudy(discover_study::Args),
    /// Coverage of `validate munro`'s 95% intervals of zeta and omega_n on seeded synthetic
    /// design-load curves (another integrator, a chosen noise family and speed grid).
    ValidateStudy(validate_study::Args),
    /// Every figure of the paper (PNG + SVG) and a claim-by-claim reproduction report
    /// (REPRODUCTION.md, index.html, claims.json, claims.csv).
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
        Command::Compare(a) => compare::run(a),
        Command::Study(a) => study::run(a),
        Command::Discover(a) => discover::run(a),
        Command::DiscoverStudy(a) => discover_study::run(a),
        Command::Reproduce(a) => reproduce::run(a),
        Command::ValidateStudy(a) => validate_study::run(a),
    }
}
