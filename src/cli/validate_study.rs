//! `geardyn validate-study --noise FAMILY --seeds N`: interval coverage of `validate munro`
//! on seeded synthetic design-load curves (Wilson 95% intervals of the rates).

use super::common::{check_out_file, parse_grid, print_study, NoiseArgs, SeedLog};
use super::limits::{real, whole};
use super::progress_bar::Bar;
use anyhow::Context;
use clap::Args as ClapArgs;
use geardyn::fit::Robust;
use geardyn::validate::SpeedGrid;
use geardyn::validate::{
    run_validate_study, ValidateSeed, ValidateStudyOptions, ValidateStudySummary,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Number of seeds (data sets), 1 to 100000.
    #[arg(long, default_value_t = 200, allow_hyphen_values = true, value_parser = whole(1..=100_000))]
    seeds: usize,
    /// First noise seed (an integer).
    #[arg(long, default_value_t = 1)]
    first_seed: u64,
    #[command(flatten)]
    noise: NoiseArgs,
    /// Speed grid: uniform (1000-5000 rpm in --speed-step steps) or nonuniform (81 speeds
    /// drawn at random in 1000-5000 rpm, one fixed draw; 79 remain once speeds within 1 rpm of
    /// another are merged).
    #[arg(long, default_value = "uniform")]
    grid: String,
    /// Step of the uniform grid, rpm, in [1, 4000].
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true, value_parser = real(1.0, 4000.0, false))]
    speed_step: f64,
    /// DOP853 relative tolerance (dimensionless) of the sets (another integrator than the fit's
    /// closed form), in [0, 0.01); 0 makes them with the exact solver.
    #[arg(long, default_value_t = 1e-9)]
    dop853_rtol: f64,
    /// True damping ratio (dimensionless), in [0.001, 0.9].
    #[arg(long, default_value_t = 0.0175, allow_hyphen_values = true, value_parser = real(0.001, 0.9, false))]
    zeta: f64,
    /// True natural frequency, Hz, in [1, 1e6].
    #[arg(long, default_value_t = 1600.0, allow_hyphen_values = true, value_parser = real(1.0, 1e6, false))]
    omega_n_hz: f64,
    /// True STE amplitude at the design load, µm, in (0, 1000].
    #[arg(long, default_value_t = 0.3, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    ste_um: f64,
    /// State every load's STE in rig.toml as a measurement of the truth with this standard
    /// uncertainty, µm, in (0, 1000] (`[ste] sd_um`; each seed draws the stated values): the
    /// coverage of a fit that weighs stated STEs against the curves. Default: none stated.
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    ste_sd_um: Option<f64>,
    /// Student-t errors in the fit: auto (when the residuals say so), on, off.
    #[arg(long, default_value = "auto")]
    robust: String,
    /// Summary JSON (per seed: SUMMARY.seeds.jsonl beside it; the scratch set in a folder
    /// removed at the end).
    #[arg(long, default_value = "target/validate-study/summary.json")]
    out: PathBuf,
}

/// The robust setting of a command-line word.
pub fn parse_robust(s: &str) -> anyhow::Result<Robust> {
    match s {
        "auto" => Ok(Robust::Auto),
        "on" => Ok(Robust::On),
        "off" => Ok(Robust::Off),
        _ => anyhow::bail!("unknown --robust '{s}': auto, on or off"),
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_file("--out", &a.out)?;
    let grid = parse_grid(&a.grid, a.speed_step)?;
    if !(a.dop853_rtol >= 0.0 && a.dop853_rtol < 1e-2) {
        anyhow::bail!("--dop853-rtol must be in [0, 0.01): 0 for the exact solver");
    }
    let opts = ValidateStudyOptions {
        first_seed: a.first_seed,
        seeds: a.seeds,
        noise: a.noise.noise()?,
        grid,
        dop853_rtol: (a.dop853_rtol > 0.0).then_some(a.dop853_rtol),
        zeta: a.zeta,
        omega_n_hz: a.omega_n_hz,
        ste_um: a.ste_um,
        ste_sd_um: a.ste_sd_um,
        robust: parse_robust(&a.robust)?,
    };
    let parent = a.out.parent().map(PathBuf::from).unwrap_or_default();
    std::fs::create_dir_all(&parent).with_context(|| parent.display().to_string())?;
    let scratch = parent.join(format!(".scratch-{}", std::process::id()));
    let seeds_path = a.out.with_extension("seeds.jsonl");
    // The per-seed lines go to a temporary file beside it, renamed when the study succeeded.
    let seeds_tmp = parent.join(format!(".seeds.jsonl.tmp-{}", std::process::id()));
    let mut log = SeedLog::open(&seeds_tmp)?;
    // Removed by an interrupt as well (Ctrl-C), until moved into place.
    geardyn::report::track_unfinished(&seeds_tmp);
    geardyn::report::track_unfinished(&scratch);
    let result = run_validate_study(&opts, &scratch, &Bar::new(), &mut |r: &ValidateSeed| {
        log.record(r)
    });
    drop(log);
    let _ = std::fs::remove_dir_all(&scratch);
    geardyn::report::untrack_unfinished(&scratch);
    let s = match result {
        Ok(s) => s,
        Err(e) => {
            let _ = std::fs::remove_file(&seeds_tmp);
            geardyn::report::untrack_unfinished(&seeds_tmp);
            return Err(e.into());
        }
    };
    let text = serde_json::to_string_pretty(&s)?;
    if seeds_tmp.exists() {
        let renamed = std::fs::rename(&seeds_tmp, &seeds_path);
        geardyn::report::untrack_unfinished(&seeds_tmp);
        renamed.with_context(|| seeds_path.display().to_string())?;
    }
    geardyn::report::write_file_atomic(&a.out, &format!("{text}\n"))?;
    print_study(summary_text(&s), &a.out, &seeds_path)
}

fn summary_text(s: &ValidateStudySummary) -> String {
    let mut msg = format!(
        "SYNTHETIC DATA (generated by geardyn synth per seed)\n{} seeds, noise {} (floor {} um, relative {}{}), {} grid of {} speeds, sets made by {}\n",
        s.seeds,
        s.noise_family,
        s.noise_floor_um,
        s.noise_relative,
        s.noise_quantum_um
            .map_or(String::new(), |q| format!(", read to {q} um"))
            + &s.noise_rho.map_or(String::new(), |r| {
                format!(", correlated along speed: {r} between neighbours at the median step")
            }),
        match s.grid {
            SpeedGrid::Uniform { .. } => "uniform",
            SpeedGrid::NonUniform { .. } => "non-uniform",
        },
        s.grid_points,
        s.data_dop853_rtol
            .map_or("the exact solver".to_string(), |r| format!("DOP853 (rtol {r:e})"))
    );
    if s.refused > 0 {
        msg.push_str(&format!(
            "{} more {} refused, as validate munro refuses it (a parameter or the errors' correlation not determined by the curves; the per-seed records say why); the coverage is over the {} fitted\n",
            s.refused,
            if s.refused == 1 { "seed's fit was" } else { "seeds' fits were" },
            s.seeds
        ));
    }
    msg.push_str("95% interval coverage (Wilson 95% interval of the rate):\n");
    for c in &s.coverage {
        let rate = |(k, r, (lo, hi)): (usize, f64, (f64, f64))| {
            format!(
                "{k}/{} = {:.1}% [{:.1}, {:.1}]",
                s.seeds,
                100.0 * r,
                100.0 * lo,
                100.0 * hi
            )
        };
        msg.push_str(&format!(
            "  {:<16} truth {:<7} Fisher {}, sandwich {}, profile {}; sd of estimates {:.3e}, mean standard error {:.3e}\n",
            c.name,
            c.truth,
            rate(c.fisher),
            rate(c.sandwich),
            c.profile.map_or("-".to_string(), rate),
            c.sd,
            c.mean_std_error
        ));
    }
    msg.push_str(&format!(
        "Student-t errors chosen on {}/{} seeds; {:.2} outlying points listed per seed\n",
        s.student_t_chosen, s.seeds, s.mean_outliers
    ));
    msg.push_str(&format!(
        "errors correlated along speed kept on {}/{} seeds{}\n",
        s.correlation_kept,
        s.seeds,
        if s.correlation_kept > 0 {
            format!(" (median length {:.0} rpm)", s.median_correlation_rpm)
        } else {
            String::new()
        }
    ));
    msg
}
