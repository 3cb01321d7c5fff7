//! indep-synth: an independent generator of Munro-style pp DTE sets for testing geardyn on data it
//! did not make. See README.md.

mod gen;
mod kubo;
mod model;
mod noise;
mod rig;
mod sim;
#[cfg(test)]
mod tests;

use clap::{Parser, Subcommand, ValueEnum};
use gen::{write_set, Effect, Grid, SetSpec};
use noise::{Correlation, Family, NoiseSpec};
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rig::Rig;
use serde_json::json;
use sim::SimConfig;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

const MUNRO_LOADS: &str = "3780:0.3,2835:1.5,1890:2.5,945:3.5";

#[derive(Parser)]
#[command(
    name = "indep-synth",
    version,
    about = "Independent generator of Munro-style synthetic pp DTE sets (not geardyn's code)"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
enum Kind {
    Validate,
    Discover,
    /// Kubo-layout dynamic-factor envelopes (for geardyn validate kubo)
    Kubo,
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
enum GridKind {
    Uniform,
    Nonuniform,
}

#[derive(Subcommand)]
enum Cmd {
    /// Write one set: OUT/rig.toml + OUT/dte.csv, and the truth JSON outside OUT.
    Set(SetArgs),
    /// Write one Kubo-layout set: OUT/rig.toml + OUT/dynamic_factor.csv (envelope of the dynamic
    /// factor over tooth pairs), and the truth JSON outside OUT.
    KuboSet(KuboSetArgs),
    /// Write a batch: OUT/sets/NAME/ and OUT/truth/NAME.json (+ truth/INDEX.json, BATCH.json).
    Batch(BatchArgs),
}

#[derive(clap::Args)]
struct Common {
    /// Template rig.toml whose [rig] table is used (default: Munro's rig, as data/munro/rig.toml)
    #[arg(long)]
    rig: Option<PathBuf>,
    /// Noise floor (um): SD of the constant family, level-independent part of the others
    #[arg(long, default_value_t = 0.15)]
    noise_um: f64,
    /// Relative part of the level-dependent families (fraction of the level; default 0.03, kubo
    /// batches 0.02)
    #[arg(long)]
    noise_relative: Option<f64>,
    /// Degrees of freedom of the student-t family
    #[arg(long, default_value_t = 3.0)]
    noise_dof: f64,
    /// Reading grid of the quantized family (um)
    #[arg(long, default_value_t = 0.25)]
    noise_quantum_um: f64,
    /// correlated family: lag-one correlation of the standardized errors between neighbouring
    /// speeds of the grid, in [0, 0.999] (default 0.6 when --noise-corr-length-rpm is not given)
    #[arg(long, visible_alias = "rho", allow_negative_numbers = true)]
    noise_rho: Option<f64>,
    /// correlated family: correlation length L in rpm instead of --noise-rho, corr(z_i, z_j) =
    /// exp(-|s_i - s_j| / L) (finite, > 0)
    #[arg(long, visible_alias = "corr-length-rpm", allow_negative_numbers = true)]
    noise_corr_length_rpm: Option<f64>,
    /// Dopri5 relative tolerance (absolute: rtol / 100)
    #[arg(long, default_value_t = 1e-10)]
    rtol: f64,
    /// Decimals of dte_pp_um in the CSV
    #[arg(long, default_value_t = 5)]
    digits: usize,
    /// Extra periods before a converged subharmonic orbit's state is carried to the next speed
    /// (0: the end of a 64-period window; see README)
    #[arg(long, default_value_t = 0)]
    carry_shift: usize,
    /// Speed range LO:HI rpm (of the non-uniform grid; of batches) (default 1000:5000, kubo
    /// batches 2000:10000)
    #[arg(long)]
    speed_range: Option<String>,
    /// Number of speeds of the non-uniform grid
    #[arg(long, default_value_t = 81)]
    n_speeds: usize,
}

#[derive(clap::Args)]
struct SetArgs {
    /// Output folder of the set
    #[arg(long)]
    out: PathBuf,
    /// Truth JSON (default: OUT.truth.json beside the folder, never inside it)
    #[arg(long)]
    truth: Option<PathBuf>,
    #[arg(long, default_value_t = 0.0175)]
    zeta: f64,
    #[arg(long, default_value_t = 1600.0)]
    omega_n_hz: f64,
    /// LOAD_N:STE_UM pairs (first-harmonic STE amplitude), comma separated
    #[arg(long, default_value = MUNRO_LOADS)]
    loads: String,
    /// Uniform speed grid START:STOP:STEP rpm
    #[arg(long, default_value = "1000:5000:50")]
    speeds: String,
    /// Use a non-uniform grid (--n-speeds drawn in --speed-range, seeded by --grid-seed)
    #[arg(long)]
    nonuniform: bool,
    #[arg(long, default_value_t = 1)]
    grid_seed: u64,
    /// Hidden mesh-stiffness variation eps: k = 1 + eps cos(Omega t + phase)
    #[arg(long, default_value_t = 0.0)]
    stiffness_eps: f64,
    #[arg(long, default_value_t = 0.0)]
    stiffness_phase: f64,
    /// Hidden 2nd STE harmonic, fraction of the first: r2 F_ah sin(2 Omega t + phase)
    #[arg(long, default_value_t = 0.0)]
    ste2_ratio: f64,
    #[arg(long, default_value_t = 0.0)]
    ste2_phase: f64,
    /// Hidden torque ripple as a fraction of the design load's mean force: F_aT sin(Omega t + phase)
    #[arg(long, default_value_t = 0.0)]
    torque_ripple_ratio: f64,
    #[arg(long, default_value_t = 0.0)]
    torque_ripple_phase: f64,
    /// Hidden contact law outside geardyn's library: f(q) = c (q - 1)^n in contact (Hertz's
    /// line contact is nearer 1.1, a point contact 1.5), c such that the local stiffness is 1 at
    /// the design load's mean deflection; the stiffness then grows as load^((n-1)/n).
    #[arg(long, default_value_t = 1.0)]
    contact_exponent: f64,
    /// Noise family: constant, relative, student-t, quantized, correlated, or none
    #[arg(long, default_value = "constant")]
    noise: String,
    /// Noise seed
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct BatchArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    /// Batch folder
    #[arg(long)]
    out: PathBuf,
    /// validate: number of sets; discover: number of null sets (families rotate)
    #[arg(long)]
    seeds: usize,
    /// Base seed: set i (0-based, generation order) has seed base_seed * 10000 + i
    #[arg(long, default_value_t = 1)]
    base_seed: u64,
    #[arg(long, value_enum, default_value = "uniform")]
    grid: GridKind,
    /// Step of the uniform grid, rpm (default 50 for validate, 100 for discover)
    #[arg(long)]
    speed_step: Option<f64>,
    /// validate, kubo: truth zeta drawn uniformly in LO:HI (default 0.012:0.035; kubo 0.06:0.16)
    #[arg(long)]
    zeta_range: Option<String>,
    /// validate, kubo: truth omega_n drawn uniformly in LO:HI Hz (default 1450:1750; kubo 2200:2900)
    #[arg(long)]
    omega_n_range: Option<String>,
    /// validate: each load's STE = Munro's times a factor drawn uniformly in LO:HI; kubo: the
    /// nominal STE = --ste-um times such a factor
    #[arg(long, default_value = "0.8:1.2")]
    ste_factor_range: String,
    /// kubo: nominal STE (um) before the factor
    #[arg(long, default_value_t = 3.0)]
    ste_um: f64,
    /// kubo: tooth pairs per set, rotating over this list (set i: entry i mod len)
    #[arg(long, default_value = "4,8,12")]
    tooth_pairs_cycle: String,
    /// Noise families, rotating. validate, discover: set i (within each kind of discover) gets
    /// entry i mod len (default constant,relative,student-t,quantized); kubo: entry
    /// (i / len(pairs)) mod len, so every pair count meets every family (default
    /// gaussian,student-t,quantized). Add correlated for errors correlated along speed.
    #[arg(long)]
    families: Option<String>,
    /// kubo: relative SD of each pair's STE amplitude
    #[arg(long, default_value_t = 0.05)]
    pair_ste_scatter: f64,
    /// kubo: floor of the reading error (D_L units)
    #[arg(long, default_value_t = 0.01)]
    noise_floor: f64,
    /// kubo: reading grid of the quantized family (D_L units)
    #[arg(long, default_value_t = 0.02)]
    noise_quantum: f64,
    /// kubo: do not write [ste] into rig.toml (geardyn then fits the STE)
    #[arg(long)]
    omit_ste: bool,
    /// discover: truth zeta
    #[arg(long, default_value_t = 0.0175)]
    zeta: f64,
    /// discover: truth natural frequency (Hz)
    #[arg(long, default_value_t = 1600.0)]
    omega_n_hz: f64,
    /// LOAD_N:STE_UM pairs (validate: before the random factor)
    #[arg(long, default_value = MUNRO_LOADS)]
    loads: String,
    /// discover: number of sets with a hidden stiffness variation (random phase)
    #[arg(long, default_value_t = 0)]
    eps_sets: usize,
    #[arg(long, default_value_t = 0.2)]
    eps: f64,
    /// discover: number of sets with a hidden 2nd STE harmonic (random phase)
    #[arg(long, default_value_t = 0)]
    r2_sets: usize,
    #[arg(long, default_value_t = 0.4)]
    r2: f64,
    /// discover: number of sets with a hidden torque ripple (random phase)
    #[arg(long, default_value_t = 0)]
    ripple_sets: usize,
    #[arg(long, default_value_t = 0.03)]
    ripple: f64,
    /// Parallel workers (the machine is shared: default 1)
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct KuboSetArgs {
    /// Output folder of the set
    #[arg(long)]
    out: PathBuf,
    /// Truth JSON (default: OUT.truth.json beside the folder, never inside it)
    #[arg(long)]
    truth: Option<PathBuf>,
    /// Template rig.toml whose [rig] table is used (default: the [rig] of geardyn's data/kubo)
    #[arg(long)]
    rig: Option<PathBuf>,
    #[arg(long, default_value_t = 0.1)]
    zeta: f64,
    #[arg(long, default_value_t = 2500.0)]
    omega_n_hz: f64,
    /// Nominal first-harmonic STE amplitude (um) at the test load
    #[arg(long, default_value_t = 3.0)]
    ste_um: f64,
    /// Uniform speed grid START:STOP:STEP rpm
    #[arg(long, default_value = "2000:10000:100")]
    speeds: String,
    /// Tooth pairs whose readings make the envelope
    #[arg(long, default_value_t = 8)]
    tooth_pairs: usize,
    /// Relative SD of each pair's STE amplitude, drawn once per set
    #[arg(long, default_value_t = 0.05)]
    pair_ste_scatter: f64,
    /// Reading error family: gaussian, student-t, quantized, correlated, or none
    #[arg(long, default_value = "gaussian")]
    noise: String,
    /// Relative part of the reading error's SD (times the pair's D_L)
    #[arg(long, default_value_t = 0.02)]
    noise_relative: f64,
    /// Floor of the reading error's SD (D_L units; added in quadrature)
    #[arg(long, default_value_t = 0.01)]
    noise_floor: f64,
    /// Degrees of freedom of the student-t family
    #[arg(long, default_value_t = 3.0)]
    noise_dof: f64,
    /// Reading grid of the quantized family (D_L units)
    #[arg(long, default_value_t = 0.02)]
    noise_quantum: f64,
    /// correlated family: lag-one correlation of the standardized errors between neighbouring
    /// speeds of the grid, in [0, 0.999] (default 0.6 when --noise-corr-length-rpm is not given)
    #[arg(long, visible_alias = "rho", allow_negative_numbers = true)]
    noise_rho: Option<f64>,
    /// correlated family: correlation length L in rpm instead of --noise-rho, corr(z_i, z_j) =
    /// exp(-|s_i - s_j| / L) (finite, > 0)
    #[arg(long, visible_alias = "corr-length-rpm", allow_negative_numbers = true)]
    noise_corr_length_rpm: Option<f64>,
    /// Seed (pair STE draws: splitmix64(seed, 4); reading errors: splitmix64(seed, 2))
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Do not write [ste] into rig.toml (geardyn then fits the STE)
    #[arg(long)]
    omit_ste: bool,
    /// Dopri5 relative tolerance (absolute: rtol / 100)
    #[arg(long, default_value_t = 1e-10)]
    rtol: f64,
    /// Decimals in the CSV
    #[arg(long, default_value_t = 5)]
    digits: usize,
    /// Threads over the tooth pairs' sweeps
    #[arg(long, default_value_t = 1)]
    threads: usize,
}

fn parse_pair(s: &str, what: &str) -> Result<(f64, f64), String> {
    let v: Vec<&str> = s.split(':').collect();
    if v.len() != 2 {
        return Err(format!("{what}: expected LO:HI, got '{s}'"));
    }
    let a = v[0]
        .trim()
        .parse::<f64>()
        .map_err(|e| format!("{what}: {e}"))?;
    let b = v[1]
        .trim()
        .parse::<f64>()
        .map_err(|e| format!("{what}: {e}"))?;
    Ok((a, b))
}

fn parse_loads(s: &str) -> Result<Vec<(f64, f64)>, String> {
    s.split(',').map(|p| parse_pair(p, "--loads")).collect()
}

fn parse_grid(s: &str) -> Result<Grid, String> {
    let v: Vec<f64> = s
        .split(':')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .map_err(|e| format!("--speeds: {e}"))
        })
        .collect::<Result<_, _>>()?;
    if v.len() != 3 || v[2] <= 0.0 || v[1] < v[0] {
        return Err(format!("--speeds: expected START:STOP:STEP, got '{s}'"));
    }
    Ok(Grid::Uniform {
        start_rpm: v[0],
        stop_rpm: v[1],
        step_rpm: v[2],
    })
}

fn load_rig(p: &Option<PathBuf>) -> Result<Rig, String> {
    match p {
        Some(p) => Rig::from_file(p),
        None => Ok(Rig::munro()),
    }
}

fn sim_config(c: &Common) -> SimConfig {
    SimConfig {
        rtol: c.rtol,
        atol: c.rtol / 100.0,
        carry_shift: c.carry_shift,
        ..SimConfig::default()
    }
}

/// The correlation of a correlated family from its two flags; refuses either flag when no family
/// in use is correlated (they would be silently ignored), and values out of range.
fn correlation_flags(
    correlated: bool,
    rho: Option<f64>,
    length_rpm: Option<f64>,
    families: &str,
) -> Result<Option<Correlation>, String> {
    if !correlated {
        return match (rho, length_rpm) {
            (Some(_), _) => Err(format!(
                "--noise-rho applies only to the correlated family (noise family: {families})"
            )),
            (None, Some(_)) => Err(format!(
                "--noise-corr-length-rpm applies only to the correlated family (noise family: {families})"
            )),
            (None, None) => Ok(None),
        };
    }
    Correlation::from_flags(rho, length_rpm).map(Some)
}

/// The floor and relative part of a correlated family's scale must be finite and >= 0.
fn check_scale(
    floor: f64,
    floor_flag: &str,
    relative: f64,
    relative_flag: &str,
) -> Result<(), String> {
    for (v, flag) in [(floor, floor_flag), (relative, relative_flag)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!("{flag} {v}: must be a finite number >= 0"));
        }
    }
    Ok(())
}

/// The Munro-mode noise of every set drawn with these flags, less its family and seed; Err if
/// the correlation flags do not apply to `families` (the families in use) or are out of range.
fn noise_template(c: &Common, families: &[Family]) -> Result<NoiseSpec, String> {
    let correlated = families.contains(&Family::Correlated);
    let names: Vec<&str> = families.iter().map(|f| f.name()).collect();
    let correlation = correlation_flags(
        correlated,
        c.noise_rho,
        c.noise_corr_length_rpm,
        &names.join(","),
    )?;
    let relative = c.noise_relative.unwrap_or(0.03);
    if correlated {
        check_scale(c.noise_um, "--noise-um", relative, "--noise-relative")?;
    }
    Ok(NoiseSpec {
        family: Family::Constant,
        floor_um: c.noise_um,
        relative,
        dof: c.noise_dof,
        quantum_um: c.noise_quantum_um,
        seed: 0,
        correlation,
    })
}

/// One set's noise: the template with its family and seed (the correlation only for the
/// correlated family, so the other families' truth records stay as they were).
fn noise_spec(template: &NoiseSpec, family: Family, seed: u64) -> NoiseSpec {
    NoiseSpec {
        family,
        seed,
        correlation: if family == Family::Correlated {
            template.correlation
        } else {
            None
        },
        ..template.clone()
    }
}

/// The noise of `set` (None for --noise none).
fn set_noise(a: &SetArgs) -> Result<Option<NoiseSpec>, String> {
    if a.noise == "none" {
        correlation_flags(
            false,
            a.common.noise_rho,
            a.common.noise_corr_length_rpm,
            "none",
        )?;
        return Ok(None);
    }
    let family = Family::parse(&a.noise)?;
    let template = noise_template(&a.common, &[family])?;
    Ok(Some(noise_spec(&template, family, a.seed)))
}

/// The reading error of `kubo-set` (None for --noise none).
fn kubo_set_noise(a: &KuboSetArgs) -> Result<Option<kubo::KNoise>, String> {
    let family = match a.noise.as_str() {
        "none" => None,
        s => Some(kubo::KFamily::parse(s)?),
    };
    let correlated = family == Some(kubo::KFamily::Correlated);
    let correlation =
        correlation_flags(correlated, a.noise_rho, a.noise_corr_length_rpm, &a.noise)?;
    if correlated {
        check_scale(
            a.noise_floor,
            "--noise-floor",
            a.noise_relative,
            "--noise-relative",
        )?;
    }
    Ok(family.map(|family| kubo::KNoise {
        family,
        relative: a.noise_relative,
        floor: a.noise_floor,
        dof: a.noise_dof,
        quantum: a.noise_quantum,
        correlation,
    }))
}

/// The rotation of a Kubo batch's reading-error families and the correlated family's correlation
/// (None when no family is correlated).
fn kubo_families(a: &BatchArgs) -> Result<(Vec<kubo::KFamily>, Option<Correlation>), String> {
    let fams: Vec<kubo::KFamily> = a
        .families
        .as_deref()
        .unwrap_or("gaussian,student-t,quantized")
        .split(',')
        .map(|x| kubo::KFamily::parse(x.trim()))
        .collect::<Result<_, _>>()?;
    let correlated = fams.contains(&kubo::KFamily::Correlated);
    let names: Vec<&str> = fams.iter().map(|f| f.name()).collect();
    let correlation = correlation_flags(
        correlated,
        a.common.noise_rho,
        a.common.noise_corr_length_rpm,
        &names.join(","),
    )?;
    if correlated {
        let relative = a.common.noise_relative.unwrap_or(0.02);
        check_scale(a.noise_floor, "--noise-floor", relative, "--noise-relative")?;
    }
    Ok((fams, correlation))
}

/// The rotation of a Munro-mode batch's noise families.
fn munro_families(a: &BatchArgs) -> Result<Vec<Family>, String> {
    match &a.families {
        None => Ok(Family::INDEPENDENT.to_vec()),
        Some(list) => list.split(',').map(|x| Family::parse(x.trim())).collect(),
    }
}

/// splitmix64 of (seed, stream): independent generator streams per set.
fn mix(seed: u64, stream: u64) -> u64 {
    let mut z = seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn run_set(a: SetArgs) -> Result<(), String> {
    let rig = load_rig(&a.common.rig)?;
    let effects = [
        a.stiffness_eps > 0.0,
        a.ste2_ratio > 0.0,
        a.torque_ripple_ratio > 0.0,
        a.contact_exponent != 1.0,
    ];
    if effects.iter().filter(|&&x| x).count() > 1 {
        return Err("give at most one hidden effect".into());
    }
    let effect = if a.stiffness_eps > 0.0 {
        Effect::MeshStiffnessVariation {
            eps: a.stiffness_eps,
            phase_rad: a.stiffness_phase,
        }
    } else if a.ste2_ratio > 0.0 {
        Effect::SteHarmonics {
            r2: a.ste2_ratio,
            phase_rad: a.ste2_phase,
        }
    } else if a.contact_exponent != 1.0 {
        if !(a.contact_exponent > 1.0 && a.contact_exponent <= 2.0) {
            return Err(format!(
                "--contact-exponent {}: must lie in (1, 2] (1 is the linear contact of eq. 3c)",
                a.contact_exponent
            ));
        }
        Effect::ContactLaw {
            exponent: a.contact_exponent,
        }
    } else if a.torque_ripple_ratio > 0.0 {
        Effect::TorqueRipple {
            ratio: a.torque_ripple_ratio,
            phase_rad: a.torque_ripple_phase,
        }
    } else {
        Effect::None
    };
    let grid = if a.nonuniform {
        let (lo, hi) = parse_pair(
            a.common.speed_range.as_deref().unwrap_or("1000:5000"),
            "--speed-range",
        )?;
        Grid::Nonuniform {
            n: a.common.n_speeds,
            lo_rpm: lo,
            hi_rpm: hi,
            seed: a.grid_seed,
            decimals: 2,
        }
    } else {
        parse_grid(&a.speeds)?
    };
    let noise = set_noise(&a)?;
    let name = a
        .out
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or("set".into());
    let truth = a.truth.clone().unwrap_or_else(|| {
        let mut p = a.out.clone().into_os_string();
        p.push(".truth.json");
        PathBuf::from(p)
    });
    if truth.starts_with(&a.out) {
        return Err("--truth must be outside the set folder (geardyn must be blind)".into());
    }
    let spec = SetSpec {
        name,
        rig,
        zeta: a.zeta,
        omega_n_hz: a.omega_n_hz,
        loads: parse_loads(&a.loads)?,
        effect,
        grid,
        noise,
        sim: sim_config(&a.common),
        extra: json!({"command": std::env::args().collect::<Vec<_>>().join(" ")}),
    };
    let w = write_set(&spec, &a.out, &truth, a.common.digits)?;
    for c in &w.curves {
        let np = c.points.iter().filter(|p| p.period.is_none()).count();
        eprintln!(
            "  load {} N: F_hat {:.3}, {} points ({} without a period found), {} steps, {:.2} s",
            c.load_n,
            c.fhat,
            c.points.len(),
            np,
            c.steps,
            c.seconds
        );
    }
    if w.floor.redrawn + w.floor.clipped_to_zero + w.floor.zero_readings > 0 {
        eprintln!(
            "  at the floor: {} negative draws redrawn, {} clipped to 0, {} readings of 0",
            w.floor.redrawn, w.floor.clipped_to_zero, w.floor.zero_readings
        );
    }
    eprintln!(
        "SYNTHETIC (indep-synth) set written to {} in {:.1} s; truth in {}",
        a.out.display(),
        w.seconds,
        truth.display()
    );
    Ok(())
}

fn run_kubo_set(a: KuboSetArgs) -> Result<(), String> {
    let rig = match &a.rig {
        Some(p) => Rig::from_file(p)?,
        None => Rig::from_toml_str(kubo::KUBO_RIG_TOML)?,
    };
    let noise = kubo_set_noise(&a)?;
    let name = a
        .out
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or("set".into());
    let truth = a.truth.clone().unwrap_or_else(|| {
        let mut p = a.out.clone().into_os_string();
        p.push(".truth.json");
        PathBuf::from(p)
    });
    if truth.starts_with(&a.out) {
        return Err("--truth must be outside the set folder (geardyn must be blind)".into());
    }
    let spec = kubo::KuboSpec {
        name,
        rig,
        zeta: a.zeta,
        omega_n_hz: a.omega_n_hz,
        ste_um: a.ste_um,
        tooth_pairs: a.tooth_pairs,
        pair_ste_scatter: a.pair_ste_scatter,
        grid: parse_grid(&a.speeds)?,
        noise,
        pair_seed: mix(a.seed, 4),
        noise_seed: mix(a.seed, 2),
        ste_in_rig: !a.omit_ste,
        sim: kubo::kubo_sim(a.rtol),
        threads: a.threads,
        extra: json!({"command": std::env::args().collect::<Vec<_>>().join(" "), "seed": a.seed}),
    };
    let w = kubo::write_kubo_set(&spec, &a.out, &truth, a.digits)?;
    eprintln!(
        "SYNTHETIC (indep-synth) Kubo set written to {} in {:.1} s ({} pairs, F_m {:.5}, {} pair/nominal points not period-1); truth in {}",
        a.out.display(),
        w.seconds,
        spec.tooth_pairs,
        w.nominal.fm,
        w.not_period1,
        truth.display()
    );
    Ok(())
}

fn run_kubo_batch(a: BatchArgs) -> Result<(), String> {
    let rig = match &a.common.rig {
        Some(p) => Rig::from_file(p)?,
        None => Rig::from_toml_str(kubo::KUBO_RIG_TOML)?,
    };
    let step = a.speed_step.unwrap_or(100.0);
    let (lo_rpm, hi_rpm) = parse_pair(
        a.common.speed_range.as_deref().unwrap_or("2000:10000"),
        "--speed-range",
    )?;
    let (zl, zh) = parse_pair(
        a.zeta_range.as_deref().unwrap_or("0.06:0.16"),
        "--zeta-range",
    )?;
    let (wl, wh) = parse_pair(
        a.omega_n_range.as_deref().unwrap_or("2200:2900"),
        "--omega-n-range",
    )?;
    let (fl, fh) = parse_pair(&a.ste_factor_range, "--ste-factor-range")?;
    let pairs_cycle: Vec<usize> = a
        .tooth_pairs_cycle
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<usize>()
                .map_err(|e| format!("--tooth-pairs-cycle: {e}"))
        })
        .collect::<Result<_, _>>()?;
    let (fams, correlation) = kubo_families(&a)?;
    let relative = a.common.noise_relative.unwrap_or(0.02);
    let sim = kubo::kubo_sim(a.common.rtol);
    let width = a.seeds.to_string().len().max(3);
    let mut specs = Vec::new();
    for i in 0..a.seeds {
        let seed = a.base_seed * 10000 + i as u64;
        let name = format!("set-{:0width$}", i + 1, width = width);
        let mut rng = ChaCha20Rng::seed_from_u64(mix(seed, 1));
        let zeta = rng.random_range(zl..=zh);
        let omega_n = rng.random_range(wl..=wh);
        let factor = rng.random_range(fl..=fh);
        let n_pairs = pairs_cycle[i % pairs_cycle.len()];
        let family = fams[(i / pairs_cycle.len()) % fams.len()];
        specs.push(kubo::KuboSpec {
            name,
            rig: rig.clone(),
            zeta,
            omega_n_hz: omega_n,
            ste_um: a.ste_um * factor,
            tooth_pairs: n_pairs,
            pair_ste_scatter: a.pair_ste_scatter,
            grid: Grid::Uniform {
                start_rpm: lo_rpm,
                stop_rpm: hi_rpm,
                step_rpm: step,
            },
            noise: Some(kubo::KNoise {
                family,
                relative,
                floor: a.noise_floor,
                dof: a.common.noise_dof,
                quantum: a.noise_quantum,
                correlation: if family == kubo::KFamily::Correlated {
                    correlation
                } else {
                    None
                },
            }),
            pair_seed: mix(seed, 4),
            noise_seed: mix(seed, 2),
            ste_in_rig: !a.omit_ste,
            sim: sim.clone(),
            threads: 1,
            extra: json!({
                "batch_kind": "kubo",
                "set_seed": seed,
                "base_seed": a.base_seed,
                "seed_streams": "ChaCha20 (rand_chacha) seeded with splitmix64(set_seed, stream): 1 = truth draws (zeta, omega_n, STE factor), 2 = reading errors, 4 = pair STE factors",
                "ste_factor": factor,
            }),
        });
    }
    std::fs::create_dir_all(a.out.join("sets")).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(a.out.join("truth")).map_err(|e| e.to_string())?;
    let batch = json!({
        "generator": gen::GENERATOR,
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "kind": "kubo",
        "n_sets": specs.len(),
        "note": "truth/ holds the generating parameters; geardyn must be run on sets/NAME only",
    });
    std::fs::write(
        a.out.join("BATCH.json"),
        serde_json::to_string_pretty(&batch).unwrap(),
    )
    .map_err(|e| e.to_string())?;
    let next = AtomicUsize::new(0);
    let errors = Mutex::new(Vec::<String>::new());
    let out = &a.out;
    let digits = a.common.digits;
    std::thread::scope(|s| {
        for _ in 0..a.jobs.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= specs.len() {
                    break;
                }
                let sp = &specs[i];
                let dir = out.join("sets").join(&sp.name);
                let truth = out.join("truth").join(format!("{}.json", sp.name));
                match kubo::write_kubo_set(sp, &dir, &truth, digits) {
                    Ok(w) => eprintln!(
                        "{} (zeta {:.4}, {:.0} Hz, {} pairs, {}) written in {:.1} s, {} points not period-1",
                        sp.name,
                        sp.zeta,
                        sp.omega_n_hz,
                        sp.tooth_pairs,
                        sp.noise.as_ref().map(|n| n.family.name()).unwrap_or("none"),
                        w.seconds,
                        w.not_period1
                    ),
                    Err(e) => errors.lock().unwrap().push(e),
                }
            });
        }
    });
    let index: Vec<_> = specs
        .iter()
        .map(|sp| {
            json!({
                "name": sp.name,
                "zeta": sp.zeta,
                "omega_n_hz": sp.omega_n_hz,
                "ste_um": sp.ste_um,
                "tooth_pairs": sp.tooth_pairs,
                "noise_family": sp.noise.as_ref().map(|n| n.family.name()),
                "seed": sp.extra["set_seed"],
            })
        })
        .collect();
    std::fs::write(
        a.out.join("truth").join("INDEX.json"),
        serde_json::to_string_pretty(&index).unwrap(),
    )
    .map_err(|e| e.to_string())?;
    let errs = errors.into_inner().unwrap();
    if !errs.is_empty() {
        return Err(errs.join("\n"));
    }
    eprintln!(
        "batch of {} SYNTHETIC Kubo sets in {}",
        specs.len(),
        out.display()
    );
    Ok(())
}

fn run_batch(a: BatchArgs) -> Result<(), String> {
    if a.kind == Kind::Kubo {
        return run_kubo_batch(a);
    }
    let rig = load_rig(&a.common.rig)?;
    let base_loads = parse_loads(&a.loads)?;
    let step = a.speed_step.unwrap_or(if a.kind == Kind::Validate {
        50.0
    } else {
        100.0
    });
    let (lo_rpm, hi_rpm) = parse_pair(
        a.common.speed_range.as_deref().unwrap_or("1000:5000"),
        "--speed-range",
    )?;
    let sim = sim_config(&a.common);
    let fams = munro_families(&a)?;
    let template = noise_template(&a.common, &fams)?;

    // The list of sets, in generation order (each: effect kind, family).
    let mut plan: Vec<(&str, Family)> = Vec::new();
    match a.kind {
        Kind::Validate => {
            for i in 0..a.seeds {
                plan.push(("none", fams[i % fams.len()]));
            }
        }
        Kind::Kubo => unreachable!("kubo batches are made by run_kubo_batch"),
        Kind::Discover => {
            for (kind, n) in [
                ("none", a.seeds),
                ("eps", a.eps_sets),
                ("r2", a.r2_sets),
                ("ripple", a.ripple_sets),
            ] {
                for i in 0..n {
                    plan.push((kind, fams[i % fams.len()]));
                }
            }
            // Neutral names in a seeded random order: the set names do not tell the effect.
            plan.shuffle(&mut ChaCha20Rng::seed_from_u64(mix(a.base_seed, 99)));
        }
    }
    let width = plan.len().to_string().len().max(3);
    let mut specs = Vec::new();
    for (i, &(kind, family)) in plan.iter().enumerate() {
        let seed = a.base_seed * 10000 + i as u64;
        let name = format!("set-{:0width$}", i + 1, width = width);
        let mut rng = ChaCha20Rng::seed_from_u64(mix(seed, 1));
        let (zeta, omega_n, loads, factors) = match a.kind {
            Kind::Validate => {
                let (zl, zh) = parse_pair(
                    a.zeta_range.as_deref().unwrap_or("0.012:0.035"),
                    "--zeta-range",
                )?;
                let (wl, wh) = parse_pair(
                    a.omega_n_range.as_deref().unwrap_or("1450:1750"),
                    "--omega-n-range",
                )?;
                let (fl, fh) = parse_pair(&a.ste_factor_range, "--ste-factor-range")?;
                let zeta = rng.random_range(zl..=zh);
                let omega_n = rng.random_range(wl..=wh);
                let factors: Vec<f64> = base_loads
                    .iter()
                    .map(|_| rng.random_range(fl..=fh))
                    .collect();
                let loads = base_loads
                    .iter()
                    .zip(&factors)
                    .map(|(&(l, e), f)| (l, e * f))
                    .collect();
                (zeta, omega_n, loads, Some(factors))
            }
            Kind::Discover | Kind::Kubo => (a.zeta, a.omega_n_hz, base_loads.clone(), None),
        };
        let phase = rng.random_range(0.0..2.0 * PI);
        let effect = match kind {
            "eps" => Effect::MeshStiffnessVariation {
                eps: a.eps,
                phase_rad: phase,
            },
            "r2" => Effect::SteHarmonics {
                r2: a.r2,
                phase_rad: phase,
            },
            "ripple" => Effect::TorqueRipple {
                ratio: a.ripple,
                phase_rad: phase,
            },
            _ => Effect::None,
        };
        let grid = match a.grid {
            GridKind::Uniform => Grid::Uniform {
                start_rpm: lo_rpm,
                stop_rpm: hi_rpm,
                step_rpm: step,
            },
            GridKind::Nonuniform => Grid::Nonuniform {
                n: a.common.n_speeds,
                lo_rpm,
                hi_rpm,
                seed: mix(seed, 3),
                decimals: 2,
            },
        };
        specs.push(SetSpec {
            name: name.clone(),
            rig: rig.clone(),
            zeta,
            omega_n_hz: omega_n,
            loads,
            effect,
            grid,
            noise: Some(noise_spec(&template, family, mix(seed, 2))),
            sim: sim.clone(),
            extra: json!({
                "batch_kind": format!("{:?}", a.kind).to_lowercase(),
                "set_seed": seed,
                "base_seed": a.base_seed,
                "seed_streams": "ChaCha20 (rand_chacha) seeded with splitmix64(set_seed, stream): 1 = truth draws (zeta, omega_n, STE factors, phase), 2 = noise, 3 = non-uniform grid",
                "ste_factors": factors,
                "noise_family": family.name(),
            }),
        });
    }

    std::fs::create_dir_all(a.out.join("sets")).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(a.out.join("truth")).map_err(|e| e.to_string())?;
    let batch = json!({
        "generator": gen::GENERATOR,
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "kind": format!("{:?}", a.kind).to_lowercase(),
        "n_sets": specs.len(),
        "note": "truth/ holds the generating parameters; geardyn must be run on sets/NAME only",
    });
    std::fs::write(
        a.out.join("BATCH.json"),
        serde_json::to_string_pretty(&batch).unwrap(),
    )
    .map_err(|e| e.to_string())?;

    let next = AtomicUsize::new(0);
    let errors = Mutex::new(Vec::<String>::new());
    let out = &a.out;
    let digits = a.common.digits;
    std::thread::scope(|s| {
        for _ in 0..a.jobs.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= specs.len() {
                    break;
                }
                let sp = &specs[i];
                let dir = out.join("sets").join(&sp.name);
                let truth = out.join("truth").join(format!("{}.json", sp.name));
                match write_set(sp, &dir, &truth, digits) {
                    Ok(w) => eprintln!(
                        "{} ({}, {}) written in {:.1} s",
                        sp.name,
                        sp.effect.label(),
                        sp.noise.as_ref().map(|n| n.family.name()).unwrap_or("none"),
                        w.seconds
                    ),
                    Err(e) => errors.lock().unwrap().push(e),
                }
            });
        }
    });
    let index: Vec<_> = specs
        .iter()
        .map(|sp| {
            json!({
                "name": sp.name,
                "effect": sp.effect,
                "effect_name": sp.effect.label(),
                "noise_family": sp.noise.as_ref().map(|n| n.family.name()),
                "zeta": sp.zeta,
                "omega_n_hz": sp.omega_n_hz,
                "loads": sp.loads,
                "seed": sp.extra["set_seed"],
            })
        })
        .collect();
    std::fs::write(
        a.out.join("truth").join("INDEX.json"),
        serde_json::to_string_pretty(&index).unwrap(),
    )
    .map_err(|e| e.to_string())?;
    let errs = errors.into_inner().unwrap();
    if !errs.is_empty() {
        return Err(errs.join("\n"));
    }
    eprintln!(
        "batch of {} SYNTHETIC sets in {}",
        specs.len(),
        Path::new(out).display()
    );
    Ok(())
}

fn main() {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Set(a) => run_set(a),
        Cmd::KuboSet(a) => run_kubo_set(a),
        Cmd::Batch(a) => run_batch(a),
    };
    if let Err(e) = r {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
