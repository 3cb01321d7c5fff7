//! `geardyn synth munro|kubo`: write a synthetic data set (labelled as such, with its truth).

use super::common::{parse_load_ste, print_text, NoiseArgs};
use super::progress_bar::Bar;
use clap::{Args as ClapArgs, Subcommand};
use geardyn::validate::{synth_kubo, synth_munro, HiddenEffects, KuboTruth, MunroTruth};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(subcommand)]
    which: Which,
}

#[derive(Subcommand, Debug)]
enum Which {
    /// pp DTE versus speed at loads 1, 3/4, 1/2, 1/4 of 3780 N on Munro's rig geometry.
    Munro(MunroArgs),
    /// Dynamic-factor envelope of a heavily damped rig (zeta about 0.1).
    Kubo(KuboArgs),
}

#[derive(ClapArgs, Debug)]
struct Hidden {
    /// Hidden mesh-stiffness variation eps (k = 1 + eps cos(Omega t + psi)).
    #[arg(long, default_value_t = 0.0)]
    stiffness_eps: f64,
    /// Phase psi of the hidden stiffness variation (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    stiffness_phase: f64,
    /// Hidden second STE harmonic as a fraction of the first.
    #[arg(long, default_value_t = 0.0)]
    ste2_ratio: f64,
    /// Phase of the hidden second STE harmonic (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    ste2_phase: f64,
    /// Hidden third STE harmonic as a fraction of the first.
    #[arg(long, default_value_t = 0.0)]
    ste3_ratio: f64,
    /// Phase of the hidden third STE harmonic (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    ste3_phase: f64,
    /// Hidden load-dependent damping: zeta (W / W_design)^gamma, this gamma (Munro only).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    damping_exponent: f64,
    /// Hidden true half backlash over the stated one (Munro only; 1 = none).
    #[arg(long, default_value_t = 1.0)]
    backlash_factor: f64,
    /// Hidden torque ripple at mesh frequency as a fraction of the design mean force (Munro only).
    #[arg(long, default_value_t = 0.0)]
    torque_ripple_ratio: f64,
    /// Phase of the hidden torque ripple (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    torque_ripple_phase: f64,
    /// Out-of-library effect: a measuring-chain resonance at this mesh frequency, Hz (Munro only).
    #[arg(long, default_value_t = 0.0)]
    sensor_peak_hz: f64,
    /// Relative height of that measuring-chain peak.
    #[arg(long, default_value_t = 0.0)]
    sensor_peak_gain: f64,
}

impl Hidden {
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
    /// Output folder.
    #[arg(long, default_value = "data/munro")]
    out: PathBuf,
    /// True damping ratio.
    #[arg(long, default_value_t = 0.0175)]
    zeta: f64,
    /// True natural frequency, Hz.
    #[arg(long, default_value_t = 1600.0)]
    omega_n_hz: f64,
    #[command(flatten)]
    noise: NoiseArgs,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also publish the STE amplitudes in rig.toml.
    #[arg(long)]
    publish_ste: bool,
    /// Loads and their STE amplitudes as LOAD_N:STE_UM pairs, comma separated
    /// [default: 3780:0.3,2835:1.5,1890:2.5,945:3.5].
    #[arg(long, value_parser = parse_load_ste, value_delimiter = ',')]
    loads: Option<Vec<(f64, f64)>>,
    /// Make the curves with DOP853 at this relative tolerance instead of the exact solver:
    /// chaotic points then differ from what the exact solver fits (as real data would).
    #[arg(long)]
    dop853_rtol: Option<f64>,
    #[command(flatten)]
    hidden: Hidden,
}

#[derive(ClapArgs, Debug)]
struct KuboArgs {
    /// Output folder.
    #[arg(long, default_value = "data/kubo")]
    out: PathBuf,
    /// True damping ratio.
    #[arg(long, default_value_t = 0.1)]
    zeta: f64,
    /// True natural frequency, Hz.
    #[arg(long, default_value_t = 2500.0)]
    omega_n_hz: f64,
    /// Noise seed.
    #[arg(long, default_value_t = 2)]
    seed: u64,
    #[command(flatten)]
    hidden: Hidden,
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
            if let Some(loads) = m.loads {
                t.ste_um = loads;
            }
            t.hidden = m.hidden.effects();
            t.dop853_rtol = m.dop853_rtol;
            synth_munro(&t, &m.out, &Bar::new())?;
            m.out
        }
        Which::Kubo(k) => {
            let mut t = KuboTruth::default_kubo();
            t.zeta = k.zeta;
            t.omega_n_hz = k.omega_n_hz;
            t.seed = k.seed;
            t.hidden = k.hidden.effects();
            synth_kubo(&t, &k.out, &Bar::new())?;
            k.out
        }
    };
    print_text(&format!(
        "SYNTHETIC DATA written to {} (rig.toml records kind = \"synthetic\" and the truth)\n",
        out.display()
    ))
}
