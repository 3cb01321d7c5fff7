//! `geardyn discover-study --hidden none|<candidate>|sensor_peak --seeds N`: the null-rate and
//! recovery studies of `geardyn discover` (seeded synthetic sets, Wilson 95% intervals).

use super::common::{check_out_file, parse_grid, parse_load_ste, print_study, NoiseArgs, SeedLog};
use super::discover::{parse_correlation, parse_tails};
use super::limits::{real, whole};
use super::progress_bar::Bar;
use anyhow::Context;
use clap::Args as ClapArgs;
use geardyn::discover::{DiscoverOptions, MAX_BOOTSTRAP};
use geardyn::method_study::discover::{run_study, Hidden, SeedOutcome, StudyOptions, StudySummary};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// What the sets hide: none (null rate), mesh_stiffness_variation, ste_harmonics,
    /// damping_law, backlash, torque_ripple, or sensor_peak (outside the library).
    #[arg(long, default_value = "none")]
    hidden: String,
    /// Number of seeds (data sets), in [1, 100000].
    #[arg(long, default_value_t = 100, allow_hyphen_values = true, value_parser = whole(1..=100_000))]
    seeds: usize,
    /// First noise seed.
    #[arg(long, default_value_t = 1)]
    first_seed: u64,
    /// Speed grid: uniform (1000-5000 rpm in --speed-step steps) or nonuniform (81 speeds
    /// drawn at random in 1000-5000 rpm, one fixed draw; 79 remain once speeds within 1 rpm of
    /// another are merged).
    #[arg(long, default_value = "uniform")]
    grid: String,
    /// Step of the uniform grid, rpm (Munro's: 50), in [1, 4000].
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true, value_parser = real(1.0, 4000.0, false))]
    speed_step: f64,
    /// Draw the hidden effect's phase uniformly in [0, 360) degrees per seed (else 0).
    #[arg(long)]
    random_phase: bool,
    /// Tails of the estimated noise: auto (Student-t when the data say so) or gaussian.
    #[arg(long, default_value = "auto")]
    tails: String,
    /// Strength of the hidden effect in the units of its estimate (eps, r2, gamma,
    /// b / b_stated, F_aT / F_m(design); sensor peak: relative height) [default: the study's
    /// moderate strength: 0.2, 0.4, 1, 1.5, 0.03; 0.5].
    #[arg(long, allow_hyphen_values = true)]
    strength: Option<f64>,
    /// Loads and STE amplitudes of the sets as LOAD_N:STE_UM pairs, comma separated
    /// [default: Munro's four loads 3780:0.3,2835:1.5,1890:2.5,945:3.5].
    #[arg(long, value_parser = parse_load_ste, value_delimiter = ',')]
    loads: Option<Vec<(f64, f64)>>,
    /// Make the sets with DOP853 at this relative tolerance instead of the exact solver that
    /// fits them: their chaotic points are then another window of the attractor, as in real
    /// data (the null rate of the excluded-points rule depends on it).
    #[arg(long)]
    dop853_rtol: Option<f64>,
    /// Keep each seed's data set in DIR/seed-N (rig.toml + dte.csv, truth included) to look
    /// at a seed's answer again with `geardyn discover --data DIR/seed-N`.
    #[arg(long, value_name = "DIR")]
    keep_sets: Option<PathBuf>,
    #[command(flatten)]
    noise: NoiseArgs,
    /// State every load's STE in rig.toml as a measurement of the truth with this standard
    /// uncertainty, µm, in (0, 1000] (`[ste] sd_um`; each seed draws the stated values after
    /// the curves' noise): discovery with the STE weighed as a measurement. Default: none
    /// stated, every STE free.
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    ste_sd_um: Option<f64>,
    /// The errors' correlation along speed within a curve, as `discover --correlation`.
    #[arg(long, default_value = "auto")]
    correlation: String,
    /// Bootstrap replicates per discovery run, in [100, 99999] (as `discover --bootstrap`).
    #[arg(long, default_value_t = 399, allow_hyphen_values = true, value_parser = whole(1..=MAX_BOOTSTRAP))]
    bootstrap: usize,
    /// Summary JSON (the scratch data sets go next to it, in a folder removed at the end; each
    /// seed's outcome is appended to SUMMARY.seeds.jsonl as soon as it is known).
    #[arg(long, default_value = "target/discover-study/summary.json")]
    out: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let hidden = Hidden::parse(&a.hidden).with_context(|| {
        format!(
            "unknown --hidden '{}': none, sensor_peak or a candidate name",
            a.hidden
        )
    })?;
    check_out_file("--out", &a.out)?;
    let opts = study_options(&a)?;
    opts.check()?;
    let parent = a.out.parent().map(PathBuf::from).unwrap_or_default();
    std::fs::create_dir_all(&parent).with_context(|| parent.display().to_string())?;
    let scratch = parent.join(format!(".scratch-{}", std::process::id()));
    // The per-seed lines are appended as each seed finishes, so that an interrupted study of
    // hours keeps what it has; the summary is written whole at the end.
    let seeds_path = a.out.with_extension("seeds.jsonl");
    geardyn::report::track_unfinished(&scratch);
    let mut log = SeedLog::open(&seeds_path)?;
    let result = run_study(
        hidden,
        &opts,
        &scratch,
        &Bar::new(),
        &mut |r: &SeedOutcome| log.record(r),
    );
    drop(log);
    let _ = std::fs::remove_dir_all(&scratch);
    geardyn::report::untrack_unfinished(&scratch);
    let s = result?;
    let text = serde_json::to_string_pretty(&s)?;
    geardyn::report::write_file_atomic(&a.out, &format!("{text}\n"))?;
    print_study(summary_text(&s), &a.out, &seeds_path)?;
    // The study is whole (its rates count a failed seed as not correct), but a run that failed
    // is a defect to look at, so a script must not take the study for a clean one.
    match s.failed.first() {
        Some((seed, _)) => anyhow::bail!(
            "discover failed on {} of {} seeds (first: seed {seed}; all listed above and in {}); the study's outputs are written",
            s.failed.len(),
            s.seeds,
            a.out.display()
        ),
        None => Ok(()),
    }
}

fn study_options(a: &Args) -> anyhow::Result<StudyOptions> {
    Ok(StudyOptions {
        first_seed: a.first_seed,
        seeds: a.seeds,
        grid: parse_grid(&a.grid, a.speed_step)?,
        random_phase: a.random_phase,
        strength: a.strength,
        loads: a.loads.clone(),
        dop853_rtol: a.dop853_rtol,
        keep_sets: a.keep_sets.clone(),
        noise: a.noise.noise()?,
        ste_sd_um: a.ste_sd_um,
        discover: DiscoverOptions {
            correlation: parse_correlation(&a.correlation)?,
            bootstrap: a.bootstrap,
            tails: parse_tails(&a.tails)?,
            ..DiscoverOptions::default()
        },
    })
}

/// The console summary: rates with their Wilson intervals, coverage, and the raw p-values'
/// calibration.
fn summary_text(s: &StudySummary) -> String {
    let mut msg = format!(
        "SYNTHETIC DATA (generated by geardyn synth per seed)\nhidden {}: expected '{}' in {}/{} seeds ({:.1}%, Wilson 95% {:.1}% .. {:.1}%)\n",
        s.hidden.name(),
        s.expected,
        s.correct,
        s.seeds,
        100.0 * s.correct_rate,
        100.0 * s.correct_ci95.0,
        100.0 * s.correct_ci95.1
    );
    if let Some((r, (lo, hi))) = s.false_positive_rate {
        msg.push_str(&format!(
            "false-positive rate {:.1}% (Wilson 95% {:.1}% .. {:.1}%; one-sided 95% upper bound {:.1}%, Clopper-Pearson)\n",
            100.0 * r,
            100.0 * lo,
            100.0 * hi,
            100.0 * s.false_positive_upper95.unwrap_or(1.0)
        ));
    }
    if let Some(p) = s.power_bound_mean {
        msg.push_str(&format!(
            "power of the hidden effect's test, first order (mean over seeds): {:.1}%: what a test of these data can reach\n",
            100.0 * p
        ));
    }
    if let Some((c, n)) = s.coverage {
        msg.push_str(&format!(
            "true value {:?} inside the 95% interval in {c}/{n} correctly named seeds\n",
            s.true_value
        ));
    }
    if let Some((c, n)) = s.held_out_shrunk {
        msg.push_str(&format!(
            "held-out RMS gap shrank in {c}/{n} correctly named seeds\n"
        ));
    }
    if let Some((c, n, (lo, hi))) = s.phase_coverage {
        msg.push_str(&format!(
            "true phase on the 95% Wald phase arc in {c}/{n} correctly named seeds (Wilson 95% {:.1}% .. {:.1}%)\n",
            100.0 * lo,
            100.0 * hi
        ));
    }
    msg.push_str(&format!(
        "warning about excluded points far outside M0's range in {}/{} seeds\n",
        s.warned, s.seeds
    ));
    if let Some((seed, e)) = s.failed.first() {
        let seeds: Vec<String> = s.failed.iter().map(|(k, _)| k.to_string()).collect();
        msg.push_str(&format!(
            "discover FAILED on {}/{} seeds ({}; counted as not correct), seed {seed}: {e}\n  (--keep-sets DIR --first-seed {seed} --seeds 1 keeps that set to run `geardyn discover --data` on it)\n",
            s.failed.len(),
            s.seeds,
            seeds.join(", ")
        ));
    }
    if !s.calibration.is_empty() {
        msg.push_str(
            "raw p-values per test (calibrated under the null: 5% below 0.05, 1% below 0.01):\n",
        );
        for c in &s.calibration {
            msg.push_str(&format!(
                "  {:<34} {:>4}/{:<4} below 0.05 (Wilson {:.1}-{:.1}%), {:>3} below 0.01, KS {:.3}\n",
                c.name,
                c.below_5pct.0,
                c.seeds,
                100.0 * c.below_5pct.1 .0,
                100.0 * c.below_5pct.1 .1,
                c.below_1pct.0,
                c.ks_distance
            ));
        }
    }
    msg
}
