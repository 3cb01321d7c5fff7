//! `geardyn study NAME`: the paper's parametric and excitation studies (Figs 15-18, 24-29).

use super::common::{check_out_dir, commit, print_json, stage};
use super::limits::whole;
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::study::{run_study, write_outputs, StudyName, StudyOptions};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Which study.
    #[arg(value_enum)]
    name: Name,
    /// Number of frequencies of the Ω_h grid (dimensionless frequencies), 2 to 2001 (default:
    /// 281 for the df studies, 141 otherwise).
    #[arg(long, allow_hyphen_values = true, value_parser = whole(2..=geardyn::study::MAX_POINTS))]
    points: Option<usize>,
    /// Folder for the figures (PNG + SVG), NAME.csv and NAME.json.
    #[arg(long, default_value = "reports/study")]
    out: PathBuf,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Name {
    /// Figs 15, 16: F_m 0.1, zeta 0.05, F_hat 10, 2, 1, 0.5 (df-exact).
    ParametricLoad,
    /// Fig. 17: F_ah 0.05, zeta 0.05, F_hat 10, 4, 2, 1 (df-exact).
    ParametricMean,
    /// Fig. 18: F_m 0.1, F_hat 2, zeta 0.025 ... 0.1 (df-exact).
    Damping,
    /// Figs 24, 25: STE (eq. 5) vs torque (eq. 4) excitation, AFT H = 15.
    Excitation,
    /// Figs 26, 27: three STE harmonics, simultaneous vs superposed (simulation).
    Superposition,
    /// Fig. 28: three STE harmonics, describing-function solutions superposed vs AFT simultaneous.
    SuperpositionHb,
    /// Fig. 29: torque at Omega_T plus STE at 2 Omega_T, superposed vs simultaneous (AFT).
    Combined,
}

impl From<Name> for StudyName {
    fn from(n: Name) -> Self {
        match n {
            Name::ParametricLoad => StudyName::ParametricLoad,
            Name::ParametricMean => StudyName::ParametricMean,
            Name::Damping => StudyName::Damping,
            Name::Excitation => StudyName::Excitation,
            Name::Superposition => StudyName::Superposition,
            Name::SuperpositionHb => StudyName::SuperpositionHb,
            Name::Combined => StudyName::Combined,
        }
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let out = run_study(a.name.into(), &StudyOptions { points: a.points })?;
    let stage = stage("--out", &a.out.join(&out.name))?;
    let written = write_outputs(&out, stage.dir())?;
    let written = commit(stage, &written)?;
    print_json(&out.summary)?;
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
