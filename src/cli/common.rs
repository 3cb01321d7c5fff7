//! Options shared by several commands (the integrator choice, noise) and output helpers.

use super::limits::{real, whole, RTOL};
use anyhow::Context;
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::model::GearPair;
use geardyn::report::Staged;
use geardyn::sim::{EscapeBudget, ExactFlow, PeriodFlow, RkFlow, SteadyOptions};
use std::path::{Path, PathBuf};

/// The initial-condition grid of the commands that search for attractors at many frequencies
/// or values (sweep, bifurcation, compare, a subharmonic hbm branch): 11 x 11 over the paper's
/// -2 < q(0), q'(0) < 2, coarser than one frequency's searches (attractors, basins) since it is
/// repeated at every value.
pub const SWEEP_IC_GRID: &str = "-2:2:11";

/// Integration and steady-state options.
#[derive(ClapArgs, Debug, Clone)]
pub struct SolverArgs {
    /// Forcing periods skipped as transient, 1 to 1000000 (default chosen from zeta; ends early
    /// once settled).
    #[arg(long, value_name = "N", allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::sim::MAX_TRANSIENT))]
    pub periods: Option<usize>,
    /// Forcing periods analysed after the transient, 1 to 100000.
    #[arg(long, value_name = "M", default_value_t = 64, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::sim::MAX_KEEP))]
    pub keep: usize,
    /// Integrator: the exact piecewise solution (k = 1) or the adaptive DOP853 with event location
    /// (any model; the independent cross-check). Default: exact, or DOP853 where the mesh
    /// stiffness varies (--excitation geometry).
    #[arg(long, value_enum)]
    pub integrator: Option<Integrator>,
    /// Relative tolerance of DOP853 (dimensionless), in [1e-14, 0.01] (1e-10 gives Poincaré
    /// points to ~1e-9).
    #[arg(long, default_value_t = 1e-10, allow_hyphen_values = true,
          value_parser = real(RTOL.0, RTOL.1, false))]
    pub rtol: f64,
}

/// How long attractor searches follow non-periodic sets (chaotic attractor or transient).
#[derive(ClapArgs, Debug, Clone)]
pub struct EscapeArgs {
    /// Age, in forcing periods from the initial conditions, up to which non-periodic sets are
    /// followed to tell a chaotic attractor from a chaotic transient (0: not followed), at most
    /// 1000000. A set stops being followed earlier once --target-escapes left it or
    /// --max-exposure trajectory-periods were spent on it. Default 40000 (validate munro:
    /// 10000, the time scale of a measurement at one speed).
    #[arg(long, value_name = "N", allow_hyphen_values = true,
          value_parser = whole(0..=geardyn::sim::MAX_HORIZON))]
    pub horizon: Option<usize>,
    /// Trajectory-periods after which a non-periodic set is no longer followed, in [1000, 5e7]
    /// (about 1 µs each with the exact solver); without escapes the rate's 95% upper bound is
    /// then 3.69 / this. Default 4e6 (attractors, basins, validate munro), 1e6 (sweep,
    /// bifurcation: per value).
    #[arg(long, value_name = "E", allow_hyphen_values = true,
          value_parser = real(1e3, geardyn::sim::MAX_EXPOSURE, false))]
    pub max_exposure: Option<f64>,
    /// Escapes after which a set's escape rate counts as measured, 1 to 100000 (100 give about
    /// ±20% at 95%).
    #[arg(long, value_name = "D", default_value_t = 100, allow_hyphen_values = true,
          value_parser = whole(1..=100_000))]
    pub target_escapes: usize,
}

impl EscapeArgs {
    /// Default budget per frequency of a sweep: a single search's, with a quarter of its
    /// exposure.
    pub fn sweep_default() -> EscapeBudget {
        EscapeBudget {
            max_exposure: 1e6,
            ..EscapeBudget::default()
        }
    }

    /// The budget: `default` where an option is not given.
    pub fn budget(&self, default: EscapeBudget) -> EscapeBudget {
        EscapeBudget {
            horizon: self.horizon.unwrap_or(default.horizon),
            target_escapes: self.target_escapes,
            max_exposure: self.max_exposure.unwrap_or(default.max_exposure),
            ..default
        }
    }
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Integrator {
    Exact,
    Dop853,
}

impl SolverArgs {
    pub fn options(&self) -> anyhow::Result<SteadyOptions> {
        if self.keep == 0 {
            anyhow::bail!("--keep must be at least 1");
        }
        Ok(SteadyOptions {
            transient: self.periods,
            keep: self.keep,
            ..SteadyOptions::default()
        })
    }

    pub fn flow(&self, model: &GearPair) -> anyhow::Result<Box<dyn PeriodFlow>> {
        Ok((self.factory())(model)?)
    }

    /// Builder of the chosen period map, for library functions that vary the frequency.
    pub fn factory(&self) -> impl Fn(&GearPair) -> geardyn::Result<Box<dyn PeriodFlow>> + Sync {
        let (integrator, rtol) = (self.integrator, self.rtol);
        move |m: &GearPair| -> geardyn::Result<Box<dyn PeriodFlow>> {
            match Self::chosen(integrator, m) {
                Integrator::Exact => Ok(Box::new(ExactFlow::new(m)?)),
                Integrator::Dop853 => Ok(Box::new(RkFlow::new(m, rtol)?)),
            }
        }
    }

    /// The integrator given, else the exact solver unless `m`'s stiffness varies (which only
    /// DOP853 integrates).
    fn chosen(given: Option<Integrator>, m: &GearPair) -> Integrator {
        given.unwrap_or(if m.stiffness.is_empty() {
            Integrator::Exact
        } else {
            Integrator::Dop853
        })
    }

    /// The integrator used for `m`, for captions.
    pub fn integrator_name(&self, m: &GearPair) -> &'static str {
        match Self::chosen(self.integrator, m) {
            Integrator::Exact => "exact",
            Integrator::Dop853 => "dop853",
        }
    }
}

/// Check, before any work starts, that `dir` can be the output folder of option `flag`: not an
/// existing file, and no file where one of its parent folders would be.
pub fn check_out_dir(flag: &str, dir: &Path) -> anyhow::Result<()> {
    let mut p = Some(dir);
    while let Some(d) = p.filter(|d| !d.as_os_str().is_empty()) {
        match std::fs::metadata(d) {
            Ok(m) if m.is_dir() => return Ok(()),
            Ok(_) if d == dir => anyhow::bail!(
                "{flag} {}: a folder was expected, but this is a file",
                dir.display()
            ),
            Ok(_) => anyhow::bail!(
                "{flag} {}: a folder was expected, but {} is a file",
                dir.display(),
                d.display()
            ),
            Err(_) => p = d.parent(),
        }
    }
    Ok(())
}

/// Check, before any work starts, that `dir` can be the output folder of option `flag` that
/// the command replaces as a whole: a folder (or none yet) that is empty or was written by
/// geardyn ([`geardyn::report::check_replaceable`]).
pub fn check_out_replaced(flag: &str, dir: &Path) -> anyhow::Result<()> {
    check_out_dir(flag, dir)?;
    geardyn::report::check_replaceable(dir).map_err(|e| anyhow::anyhow!("{flag} {e}"))
}

/// Check, before any work starts, that `file` can be the output file of option `flag`: not an
/// existing folder, and its folder can be made.
pub fn check_out_file(flag: &str, file: &Path) -> anyhow::Result<()> {
    if file.is_dir() {
        anyhow::bail!(
            "{flag} {}: a file was expected, but this is a folder",
            file.display()
        );
    }
    match file.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(parent) => check_out_dir(flag, parent),
        None => Ok(()),
    }
}

/// A staged output folder for option `flag` (checked with [`check_out_dir`]): files are written
/// into it and reach `dir` only with [`Staged::commit_merge`], once everything succeeded.
pub fn stage(flag: &str, dir: &Path) -> anyhow::Result<Staged> {
    check_out_dir(flag, dir)?;
    Staged::new(dir).with_context(|| format!("{flag} {}: cannot create the folder", dir.display()))
}

/// Commit a staged folder and return the final paths of the files written into it.
pub fn commit(stage: Staged, written: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let paths = written.iter().map(|p| stage.final_path(p)).collect();
    stage.commit_merge()?;
    Ok(paths)
}

/// `params` (a JSON object) with "omega" added.
pub fn with_omega(mut params: serde_json::Value, omega: f64) -> serde_json::Value {
    params["omega"] = serde_json::json!(omega);
    params
}

/// The warning printed for a steady state that did not settle within its transient budget.
pub fn unsettled_warning(transient_periods: usize) -> String {
    format!(
        "WARNING: not settled: no periodic orbit was found and {transient_periods} transient \
         periods were too few for the free decay to die out (zeta x time < {}); the motion is \
         reported as unsettled, neither aperiodic nor chaotic. Give more --periods or a larger \
         zeta.",
        geardyn::sim::SETTLED_DECAY
    )
}

/// Write a text file, creating its folder.
pub fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// Print JSON to standard output.
pub fn print_json(value: &serde_json::Value) -> anyhow::Result<()> {
    print_text(&format!("{}\n", serde_json::to_string_pretty(value)?))
}

/// A study's per-seed records: each one JSON line appended to the file as its seed finishes.
///
/// The file is locked when opened, before the first seed: two studies given the same `--out`
/// would otherwise write their lines over each other's in one file. The lock is the operating
/// system's (released when the process ends, however it ends), so an interrupted study leaves
/// nothing that refuses the next. An earlier run's lines are replaced at the first record, not
/// before, and a file this log made but never wrote to is removed when it is dropped (a study
/// refused before its first seed leaves no output).
pub struct SeedLog {
    file: std::fs::File,
    path: PathBuf,
    created: bool,
    written: bool,
}

impl SeedLog {
    /// The log of `path`, locked; refused when another running study holds it.
    pub fn open(path: &Path) -> anyhow::Result<Self> {
        let created = !path.exists();
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .with_context(|| format!("opening {}", path.display()))?;
        // Locked before it is owned: a log that failed to lock must not remove the running
        // study's file when dropped.
        match file.try_lock() {
            Ok(()) => Ok(SeedLog {
                file,
                path: path.to_path_buf(),
                created,
                written: false,
            }),
            Err(std::fs::TryLockError::WouldBlock) => anyhow::bail!(
                "{} is being written by another study that is still running (the same --out): \
                 give this one another --out",
                path.display()
            ),
            Err(std::fs::TryLockError::Error(e)) => {
                Err(e).with_context(|| format!("locking {}", path.display()))
            }
        }
    }

    /// Append `record` as one JSON line (the first replaces what an earlier run left).
    pub fn record<T: serde::Serialize>(&mut self, record: &T) -> geardyn::error::Result<()> {
        use std::io::Write;
        let io = geardyn::error::GearError::io(&self.path);
        if !self.written {
            self.file.set_len(0).map_err(&io)?;
            self.written = true;
        }
        let line = serde_json::to_string(record).map_err(|e| {
            geardyn::error::GearError::Numerical(format!("seed record to JSON: {e}"))
        })?;
        writeln!(self.file, "{line}").map_err(&io)
    }
}

impl Drop for SeedLog {
    fn drop(&mut self) {
        if self.created && !self.written {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Print a study's summary `text` and where its outputs went.
pub fn print_study(mut text: String, out: &Path, seeds: &Path) -> anyhow::Result<()> {
    text.push_str(&format!(
        "wrote {} (per seed: {})\n",
        out.display(),
        seeds.display()
    ));
    print_text(&text)
}

/// Write to standard output; a closed pipe (e.g. `| head`) ends quietly instead of panicking.
pub fn print_text(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// One LOAD_N:STE_UM pair of `--loads`.
pub fn parse_load_ste(s: &str) -> Result<(f64, f64), String> {
    let (l, e) = s
        .split_once(':')
        .ok_or_else(|| format!("'{s}': expected LOAD_N:STE_UM, e.g. 1890:2.5"))?;
    let num = |v: &str, what: &str| {
        v.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{s}': {what} '{v}' is not a number"))
    };
    let (load, ste) = (num(l, "load")?, num(e, "STE amplitude")?);
    if !(load > 0.0 && load <= 1e8) {
        return Err(format!("'{s}': load {load} N must be in (0, 1e8]"));
    }
    if !(ste > 0.0 && ste <= 1000.0) {
        return Err(format!(
            "'{s}': STE amplitude {ste} um must be in (0, 1000]"
        ));
    }
    Ok((load, ste))
}

/// The measurement noise of generated sets: a family and its parameters.
#[derive(clap::Args, Debug, Clone)]
pub struct NoiseArgs {
    /// Noise family: constant (Gaussian), relative (Gaussian, floor plus 3% of the level),
    /// student-t (3 degrees of freedom, floor plus 3%), quantized (floor plus 3%, read to a
    /// 0.25 µm grid), correlated (Gaussian, floor plus 3%, correlated along speed within each
    /// curve, 0.6 between neighbours at the median step).
    #[arg(long, default_value = "constant")]
    pub noise: String,
    /// Noise floor (the standard deviation of the constant family), µm, in [0, 1000].
    #[arg(long, default_value_t = 0.15, allow_hyphen_values = true,
          value_parser = real(0.0, 1000.0, false))]
    pub noise_um: f64,
    /// Relative part of the level-dependent families (relative, student-t, quantized), a
    /// fraction of the level (dimensionless), in [0, 0.99] (default 0.03).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 0.99, false))]
    pub noise_relative: Option<f64>,
    /// Degrees of freedom of the student-t family (dimensionless), in (2, 1000] (default 3;
    /// at 2 or fewer its variance is infinite and the floor no standard deviation).
    #[arg(long, allow_hyphen_values = true, value_parser = real(2.0, 1000.0, true))]
    pub noise_dof: Option<f64>,
    /// Reading grid of the quantized family, µm, in (0, 1000] (default 0.25).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    pub noise_quantum_um: Option<f64>,
    /// Correlation of the correlated family's errors at neighbouring speeds of the curve's
    /// median step (an Ornstein-Uhlenbeck process in speed within each curve; on an even grid
    /// an AR(1)), in [0, 0.999] (default 0.6).
    #[arg(long, allow_hyphen_values = true, value_parser = real(0.0, 0.999, false))]
    pub noise_rho: Option<f64>,
}

impl NoiseArgs {
    /// The noise these options describe.
    pub fn noise(&self) -> anyhow::Result<geardyn::validate::SynthNoise> {
        use geardyn::validate::NoiseFamily;
        let family = NoiseFamily::parse(&self.noise).ok_or_else(|| {
            anyhow::anyhow!(
                "unknown --noise '{}': constant, relative, student-t, quantized or correlated",
                self.noise
            )
        })?;
        let mut n = family.noise(self.noise_um);
        if let Some(r) = self.noise_relative {
            if family == NoiseFamily::Constant {
                anyhow::bail!(
                    "--noise-relative applies to the level-dependent families (relative, student-t, quantized, correlated); --noise constant has none"
                );
            }
            n.model.relative = r;
        }
        if let Some(d) = self.noise_dof {
            if family != NoiseFamily::StudentT {
                anyhow::bail!("--noise-dof applies to --noise student-t only");
            }
            n.model.distribution = geardyn::fit::Distribution::StudentT { dof: d };
        }
        if let Some(q) = self.noise_quantum_um {
            if family != NoiseFamily::Quantized {
                anyhow::bail!("--noise-quantum-um applies to --noise quantized only");
            }
            n.quantum_um = Some(q);
        }
        if let Some(rho) = self.noise_rho {
            if family != NoiseFamily::Correlated {
                anyhow::bail!("--noise-rho applies to --noise correlated only");
            }
            n.rho_on_grid = Some(rho);
        }
        Ok(n)
    }
}

/// The speed grid of a study's sets from `--grid` and `--speed-step`: uniform (1000-5000 rpm in
/// steps of `step_rpm`) or nonuniform (81 speeds drawn at random in 1000-5000 rpm, one fixed
/// draw, so that every seed and every study sees the same gaps and clusters; 79 remain once
/// speeds within 1 rpm of another are merged).
pub fn parse_grid(grid: &str, step_rpm: f64) -> anyhow::Result<geardyn::validate::SpeedGrid> {
    use geardyn::validate::SpeedGrid;
    match grid {
        "uniform" => Ok(SpeedGrid::Uniform { step_rpm }),
        "nonuniform" => Ok(SpeedGrid::NonUniform {
            points: 81,
            seed: 7_777,
        }),
        g => anyhow::bail!("unknown --grid '{g}': uniform or nonuniform"),
    }
}
