//! `geardyn synth munro|kubo`: write a synthetic data set (labelled as such, with its truth).

use super::common::{check_out_replaced, parse_grid, parse_load_ste, print_text, NoiseArgs};
use super::limits::real;
use super::progress_bar::Bar;
use clap::{Args as ClapArgs, Subcommand};
use geardyn::report::Staged;
use geardyn::validate::{
    synth_kubo, synth_munro, HiddenEffects, KuboTruth, MunroTruth, MIN_DESIGN_POINTS,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(subcommand)]
    which: Which,
}

#[derive(Subcommand, Debug)]
enum Which {
    /// pp DTE versus speed at loads 1, 3/4, 1/2, 1/4 of 3780 N on Munro's rig geometry.
    #[command(after_help = super::examples::SYNTH)]
    Munro(MunroArgs),
    /// Dynamic-factor envelope of a heavily damped rig (zeta about 0.1).
    #[command(after_help = super::examples::SYNTH)]
    Kubo(KuboArgs),
}

#[derive(ClapArgs, Debug)]
struct Hidden {
    /// Hidden mesh-stiffness variation eps (k = 1 + eps cos(Ω t + ψ)), dimensionless, in [0, 0.9].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 0.9, false))]
    stiffness_eps: f64,
    /// Phase psi of the hidden stiffness variation (rad), in [-100, 100].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-100.0, 100.0, false))]
    stiffness_phase: f64,
    /// Hidden second STE harmonic as a fraction of the first (dimensionless), in [0, 10].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 10.0, false))]
    ste2_ratio: f64,
    /// Phase of the hidden second STE harmonic (rad), in [-100, 100].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-100.0, 100.0, false))]
    ste2_phase: f64,
    /// Hidden third STE harmonic as a fraction of the first (dimensionless), in [0, 10].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 10.0, false))]
    ste3_ratio: f64,
    /// Phase of the hidden third STE harmonic (rad), in [-100, 100].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-100.0, 100.0, false))]
    ste3_phase: f64,
    /// Hidden load-dependent damping: ζ (W / W_design)^γ, this exponent γ (dimensionless; Munro only), in [-10, 10].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-10.0, 10.0, false))]
    damping_exponent: f64,
    /// Hidden true half backlash over the stated one (a ratio; Munro only; 1 = none), in [0.01, 100].
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = real(0.01, 100.0, false))]
    backlash_factor: f64,
    /// Hidden torque ripple at mesh frequency as a fraction of the design mean force (dimensionless; Munro only), in [0, 10].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 10.0, false))]
    torque_ripple_ratio: f64,
    /// Phase of the hidden torque ripple (rad), in [-100, 100].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(-100.0, 100.0, false))]
    torque_ripple_phase: f64,
    /// Out-of-library effect: a measuring-chain resonance at this mesh frequency, Hz (Munro only), in [0, 1e6].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 1e6, false))]
    sensor_peak_hz: f64,
    /// Relative height of that measuring-chain peak (dimensionless), in [0, 100].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = real(0.0, 100.0, false))]
    sensor_peak_gain: f64,
}

impl Hidden {
    /// The effects `synth kubo` cannot make (its envelope model has no load dependence, no
    /// back-side contact and no measuring chain) are refused, rather than recorded in the
    /// truth of a set that does not contain them.
    fn check_kubo(&self) -> anyhow::Result<()> {
        let munro_only = [
            ("--damping-exponent", self.damping_exponent != 0.0),
            ("--backlash-factor", self.backlash_factor != 1.0),
            ("--torque-ripple-ratio", self.torque_ripple_ratio != 0.0),
            ("--sensor-peak-hz", self.sensor_peak_hz != 0.0),
            ("--sensor-peak-gain", self.sensor_peak_gain != 0.0),
        ];
        match munro_only.iter().find(|(_, set)| *set) {
            Some((flag, _)) => anyhow::bail!(
                "{flag} applies to `synth munro` only: `synth kubo` cannot hide it (its curves would be unchanged)"
            ),
            None => Ok(()),
        }
    }

    fn effects(&self) -> HiddenEffects {
        HiddenEffects {
            stiffness_eps: self.stiffness_eps,
            stiffness_phase: self.stiffness_phase,
            ste2_ratio: self.ste2_ratio,
            ste2_phase: self.ste2_phase,
            ste3_ratio: self.ste3_ratio,
            ste3_phase: self.ste3_phase,
            damping_exponent: self.damping_exponent,
            backlash_factor: self.backlash_factor,
            torque_ripple_ratio: self.torque_ripple_ratio,
            torque_ripple_phase: self.torque_ripple_phase,
            sensor_peak_hz: self.sensor_peak_hz,
            sensor_peak_gain: self.sensor_peak_gain,
        }
    }
}

#[derive(ClapArgs, Debug)]
struct MunroArgs {
    /// Output folder (required: the shipped data/munro is never overwritten by default).
    #[arg(long)]
    out: PathBuf,
    /// True damping ratio ζ (dimensionless), in [0.001, 0.9].
    #[arg(long, default_value_t = 0.0175, allow_hyphen_values = true, value_parser = real(0.001, 0.9, false))]
    zeta: f64,
    /// True natural frequency, Hz, in [1, 1e6].
    #[arg(long, default_value_t = 1600.0, allow_hyphen_values = true, value_parser = real(1.0, 1e6, false))]
    omega_n_hz: f64,
    #[command(flatten)]
    noise: NoiseArgs,
    /// Noise seed (an integer).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also publish the STE amplitudes in rig.toml, as measurements of the true ones with the
    /// standard uncertainty --ste-sd-um (each stated value drawn about the truth).
    #[arg(long, requires = "ste_sd_um")]
    publish_ste: bool,
    /// Standard uncertainty of the published STE amplitudes, µm, in (0, 1000] (rig.toml
    /// `[ste] sd_um`; `validate munro` and `discover` weigh a stated STE as a measurement).
    #[arg(long, requires = "publish_ste", allow_hyphen_values = true, value_parser = real(0.0, 1000.0, true))]
    ste_sd_um: Option<f64>,
    /// Loads (N) and their STE amplitudes (µm) as LOAD_N:STE_UM pairs, comma separated
    /// [default: 3780:0.3,2835:1.5,1890:2.5,945:3.5].
    #[arg(long, value_parser = parse_load_ste, value_delimiter = ',')]
    loads: Option<Vec<(f64, f64)>>,
    /// Speed grid, START:STOP:STEP in rpm (Munro's: 1000:5000:50), or `nonuniform` for 81
    /// speeds drawn at random in 1000-5000 rpm (the studies' fixed draw; 79 remain once speeds
    /// within 1 rpm of another are merged).
    #[arg(long, default_value = "1000:5000:50")]
    speeds: String,
    /// Make the curves with DOP853 at this relative tolerance (dimensionless) instead of the
    /// exact solver: chaotic points then differ from what the exact solver fits (as real data
    /// would), in [1e-14, 0.01].
    #[arg(long, allow_hyphen_values = true, value_parser = real(1e-14, 1e-2, false))]
    dop853_rtol: Option<f64>,
    #[command(flatten)]
    hidden: Hidden,
}

#[derive(ClapArgs, Debug)]
struct KuboArgs {
    /// Output folder (required: the shipped data/kubo is never overwritten by default).
    #[arg(long)]
    out: PathBuf,
    /// True damping ratio ζ (dimensionless), in [0.001, 0.9].
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true, value_parser = real(0.001, 0.9, false))]
    zeta: f64,
    /// True natural frequency, Hz, in [1, 1e6].
    #[arg(long, default_value_t = 2500.0, allow_hyphen_values = true, value_parser = real(1.0, 1e6, false))]
    omega_n_hz: f64,
    /// Noise seed (an integer).
    #[arg(long, default_value_t = 2)]
    seed: u64,
    /// Tooth pairs whose dynamic factors make the envelope, in [2, 100].
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(2..=100))]
    tooth_pairs: u16,
    /// Relative scatter (standard deviation) of a tooth pair's dynamic factor about the
    /// model's, dimensionless, in [0, 0.3].
    #[arg(long, default_value_t = 0.04, allow_hyphen_values = true, value_parser = real(0.0, 0.3, false))]
    pair_scatter: f64,
    /// Make the curve with DOP853 at this relative tolerance (dimensionless) instead of the
    /// exact solver the fit uses, in [1e-14, 0.01].
    #[arg(long, allow_hyphen_values = true, value_parser = real(1e-14, 1e-2, false))]
    dop853_rtol: Option<f64>,
    #[command(flatten)]
    hidden: Hidden,
}

/// `--speeds START:STOP:STEP` in rpm: 0 < START <= STOP <= 1e6, STEP > 0, at most 100000 speeds.
fn parse_speeds(text: &str) -> anyhow::Result<(f64, f64, f64)> {
    let v: Vec<f64> = text
        .split(':')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            anyhow::anyhow!("--speeds '{text}': expected START:STOP:STEP in rpm, e.g. 1000:5000:50")
        })?;
    let [a, b, c] = v[..] else {
        anyhow::bail!("--speeds '{text}': expected START:STOP:STEP in rpm, e.g. 1000:5000:50");
    };
    let ok = a > 0.0 && a <= b && b <= 1e6 && c > 0.0 && (b - a) / c <= 1e5;
    if !(ok && [a, b, c].iter().all(|x| x.is_finite())) {
        anyhow::bail!("--speeds '{text}': need 0 < START <= STOP <= 1e6 rpm and STEP > 0, at most 100000 speeds");
    }
    // A set with fewer could not be validated.
    if ((b - a) / c + 1e-9).floor() + 1.0 < MIN_DESIGN_POINTS as f64 {
        anyhow::bail!(
            "--speeds '{text}': gives fewer than {MIN_DESIGN_POINTS} speeds, the least validate munro fits"
        );
    }
    Ok((a, b, c))
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let out = match a.which {
        Which::Munro(m) => {
            let mut t = MunroTruth::default_munro();
            t.zeta = m.zeta;
            t.omega_n_hz = m.omega_n_hz;
            t.noise = m.noise.noise()?;
            t.seed = m.seed;
            t.publish_ste = m.publish_ste;
            t.ste_sd_um = m.ste_sd_um;
            if let Some(loads) = m.loads {
                let design = t.rig.design_load_n;
                if !loads
                    .iter()
                    .any(|(l, _)| geardyn::data::same_load(*l, design))
                {
                    anyhow::bail!(
                        "--loads: must include the rig's design load, {design} N, where validate fits zeta and omega_n"
                    );
                }
                t.ste_um = loads;
            }
            t.hidden = m.hidden.effects();
            t.dop853_rtol = m.dop853_rtol;
            if m.speeds == "nonuniform" {
                t.speed_list = Some(parse_grid("nonuniform", 0.0)?.speeds()?);
            } else {
                t.speeds_rpm = parse_speeds(&m.speeds)?;
            }
            check_out_replaced("--out", &m.out)?;
            let stage = Staged::new(&m.out)?;
            synth_munro(&t, stage.dir(), &Bar::new())?;
            stage.commit()?;
            m.out
        }
        Which::Kubo(k) => {
            let mut t = KuboTruth::default_kubo();
            t.zeta = k.zeta;
            t.omega_n_hz = k.omega_n_hz;
            t.seed = k.seed;
            t.tooth_pairs = usize::from(k.tooth_pairs);
            t.pair_scatter = k.pair_scatter;
            t.dop853_rtol = k.dop853_rtol;
            k.hidden.check_kubo()?;
            t.hidden = k.hidden.effects();
            check_out_replaced("--out", &k.out)?;
            let stage = Staged::new(&k.out)?;
            synth_kubo(&t, stage.dir(), &Bar::new())?;
            stage.commit()?;
            k.out
        }
    };
    print_text(&format!(
        "SYNTHETIC DATA written to {} (rig.toml records kind = \"synthetic\" and the truth)\n",
        out.display()
    ))
}
