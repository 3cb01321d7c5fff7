//! One run of the tooth-contact model for a rig: geometry, mean mesh stiffness, the relief
//! (given or sized by Harris's rule), the loaded STE and stiffness over a mesh period at each
//! requested load with their harmonics, and a Harris map. This is what `geardyn mesh` reports;
//! the pieces are in the sibling modules.

use super::geometry::GearPairGeometry;
use super::harmonics::{mesh_harmonics, MeshHarmonic};
use super::harris::{design_relief, harris_map, HarrisPoint};
use super::iso6336::IsoStiffness;
use super::ste::{MeshModel, ReliefShape, SteWaveform, TipRelief};
use crate::data::{GearGeometry, ProfilePoints, Rig};
use crate::error::{GearError, Result};
use serde::Serialize;

/// How the tip relief is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReliefChoice {
    /// Given depth (um) and length along the line of action (mm; `None`: Harris's long relief).
    Given {
        /// Depth, um.
        amount_um: f64,
        /// Length along the line of action, mm.
        length_mm: Option<f64>,
        /// Linear or parabolic.
        shape: ReliefShape,
    },
    /// Depth sized for minimum STE peak-to-peak at `load_n` (Harris's rule), with the length
    /// given or Harris's long relief.
    DesignLoad {
        /// Design load, N.
        load_n: f64,
        /// Length along the line of action, mm.
        length_mm: Option<f64>,
        /// Linear or parabolic.
        shape: ReliefShape,
    },
}

/// Options of [`analyse`].
#[derive(Clone, Debug, PartialEq)]
pub struct MeshOptions {
    /// Loads (N) at which waveforms and harmonics are reported.
    pub loads_n: Vec<f64>,
    /// The relief.
    pub relief: ReliefChoice,
    /// Mesh positions per period (>= 16).
    pub samples: usize,
    /// Harmonic orders reported (1 ..= orders, orders < samples / 2).
    pub harmonics: u32,
    /// Loads of the Harris map (N, increasing).
    pub harris_loads_n: Vec<f64>,
    /// Profile modification of the flanks given point by point (empty: none), added to the
    /// relief.
    pub profile: ProfilePoints,
}

/// Geometry summary (lengths in mm along the line of action, from T1).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GeometrySummary {
    /// Transverse contact ratio eps_alpha = g_alpha / p_b.
    pub contact_ratio: f64,
    /// Base pitch p_b = pi m cos(alpha).
    pub base_pitch_mm: f64,
    /// Path of contact g_alpha = s_E - s_A.
    pub path_of_contact_mm: f64,
    /// s_A: start of contact (gear tip).
    pub start_of_contact_mm: f64,
    /// s_C: pitch point.
    pub pitch_point_mm: f64,
    /// s_E: end of contact (pinion tip).
    pub end_of_contact_mm: f64,
    /// Start of single-tooth contact, s_E - p_b.
    pub single_contact_from_mm: f64,
    /// End of single-tooth contact, s_A + p_b.
    pub single_contact_to_mm: f64,
    /// Operating centre distance a.
    pub centre_distance_mm: f64,
    /// Operating pressure angle alpha_w.
    pub working_pressure_angle_deg: f64,
    /// Tip diameter of the pinion.
    pub pinion_tip_diameter_mm: f64,
    /// Tip diameter of the gear.
    pub gear_tip_diameter_mm: f64,
    /// Root diameter of the pinion.
    pub pinion_root_diameter_mm: f64,
    /// Root diameter of the gear.
    pub gear_root_diameter_mm: f64,
    /// Bore diameter of the pinion (fillet-foundation term).
    pub pinion_bore_diameter_mm: f64,
    /// Bore diameter of the gear (fillet-foundation term).
    pub gear_bore_diameter_mm: f64,
    /// Young's modulus E.
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio nu.
    pub poisson_ratio: f64,
}

/// The relief used.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReliefSummary {
    /// Depth at the tip along the line of action, um.
    pub amount_um: f64,
    /// Length along the line of action, mm.
    pub length_mm: f64,
    /// Linear or parabolic.
    pub shape: ReliefShape,
    /// The load it was sized for (Harris's rule), if it was sized.
    pub designed_for_load_n: Option<f64>,
    /// Points of the profile-modification table added to it, pinion and gear (0: no table).
    pub table_points: (usize, usize),
}

/// Results at one load.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoadResult {
    /// Load F, N.
    pub load_n: f64,
    /// STE peak-to-peak over a mesh period, um.
    pub ste_pp_um: f64,
    /// Mean STE (static deflection plus relief), um.
    pub ste_mean_um: f64,
    /// STE amplitude of the model's one-harmonic form, half of `ste_pp_um`, um.
    pub ste_half_pp_um: f64,
    /// Mean loaded mesh stiffness over the period, N/um.
    pub mesh_stiffness_mean_n_per_um: f64,
    pub mesh_stiffness_min_n_per_um: f64,
    pub mesh_stiffness_max_n_per_um: f64,
    /// Share of mesh positions where a pair within the path of contact carries no load.
    pub contact_loss_fraction: f64,
    /// Dimensionless F_ah1 = e_1 / b (b = half backlash of the rig).
    pub f_ah1: f64,
    /// Harmonics of STE and stiffness in the model's conventions.
    pub harmonics: Vec<MeshHarmonic>,
    /// The waveform over one mesh period (written as CSV, not JSON).
    #[serde(skip)]
    pub waveform: SteWaveform,
}

/// Everything `geardyn mesh` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshAnalysis {
    /// Transverse contact ratio eps_alpha.
    pub contact_ratio: f64,
    /// Mean mesh stiffness with every pair in contact (no relief), N/um.
    pub mesh_stiffness_mean_n_per_um: f64,
    /// ISO 6336-1 method B c_gamma_alpha x face width for this pair at its Young's modulus
    /// (c' scaled by E / E_st, E_st = 206 GPa: ISO 6336-1 clause 9.3; [`IsoStiffness`]), N/um.
    pub iso6336_mesh_stiffness_n_per_um: f64,
    /// The steps of that estimate (q', c'_th, C_B, c', c_gamma_alpha in N/(mm um)).
    pub iso6336: IsoStiffness,
    /// ISO 6336-1 c_gamma x face width with the typical c' = 14 N/(mm um) and this pair's
    /// contact ratio, N/um: the estimate the model uses when the rig gives no stiffness. It is
    /// ISO's value for steel whatever `[geometry]` states for E, as the model's own is
    /// (`Rig::dimensional` does not read `[geometry]`).
    pub iso6336_typical_mesh_stiffness_n_per_um: f64,
    /// Geometry of the pair.
    pub geometry: GeometrySummary,
    /// The relief used.
    pub relief: ReliefSummary,
    /// Results per requested load.
    pub loads: Vec<LoadResult>,
    /// Harris map: STE pp over a load range.
    pub harris: Vec<HarrisPoint>,
    /// Pair stiffness along the path of contact (roll mm, N/um).
    pub pair_stiffness: Vec<(f64, f64)>,
    /// STE of the relief alone over a period (the light-load limit), um.
    #[serde(skip)]
    pub relief_profile_um: Vec<f64>,
}

/// Run the model for `rig` + `geometry` (see [`MeshAnalysis`]).
pub fn analyse(rig: &Rig, geometry: &GearGeometry, opts: &MeshOptions) -> Result<MeshAnalysis> {
    let geo = GearPairGeometry::from_rig(rig, geometry)?;
    check_options(opts)?;
    let model = MeshModel::with_profile(geo.clone(), &opts.profile)?;
    let (relief, designed) = chosen_relief(&model, &geo, opts)?;
    relief.validate(&geo)?;
    let half_backlash_um = rig.backlash_mm / 2.0 * 1e3;
    let loads = opts
        .loads_n
        .iter()
        .map(|&load_n| load_result(&model, &relief, load_n, opts, half_backlash_um))
        .collect::<Result<Vec<_>>>()?;
    let harris = harris_map(&model, &relief, &opts.harris_loads_n, opts.samples)?;
    let iso = Rig {
        mesh_stiffness_n_per_um: None,
        contact_ratio: Some(geo.contact_ratio()),
        ..rig.clone()
    }
    .dimensional()?;
    let mm = 1e3;
    let iso_b = geo.iso6336();
    Ok(MeshAnalysis {
        contact_ratio: geo.contact_ratio(),
        mesh_stiffness_mean_n_per_um: model.mean_mesh_stiffness_n_per_um(opts.samples),
        iso6336_mesh_stiffness_n_per_um: iso_b.c_gamma_alpha * geo.face_width_m * mm,
        iso6336: iso_b,
        iso6336_typical_mesh_stiffness_n_per_um: iso.mesh_stiffness_n_per_m * 1e-6,
        geometry: GeometrySummary::of(&geo),
        relief: ReliefSummary {
            amount_um: relief.amount_m * 1e6,
            length_mm: relief.length_m * mm,
            shape: relief.shape,
            designed_for_load_n: designed,
            table_points: (opts.profile.pinion.len(), opts.profile.gear.len()),
        },
        loads,
        harris,
        pair_stiffness: model
            .stiffness
            .points
            .iter()
            .map(|p| (p.roll_m * mm, p.stiffness_n_per_m * 1e-6))
            .collect(),
        relief_profile_um: model.relief_profile_um(&relief, opts.samples),
    })
}

/// At least 16 positions per mesh period and at least one load.
fn check_options(opts: &MeshOptions) -> Result<()> {
    if opts.samples < 16 {
        return Err(GearError::param(
            "samples",
            opts.samples as f64,
            "need at least 16 positions per mesh period",
        ));
    }
    if opts.loads_n.is_empty() {
        return Err(GearError::param("load_n", 0.0, "no load given"));
    }
    Ok(())
}

/// The tip relief: as given, or sized for minimum STE pp at the design load (Harris's rule;
/// then also that load).
fn chosen_relief(
    model: &MeshModel,
    geo: &GearPairGeometry,
    opts: &MeshOptions,
) -> Result<(TipRelief, Option<f64>)> {
    let length = |l: Option<f64>| l.map_or(TipRelief::long_length(geo), |mm| mm * 1e-3);
    Ok(match opts.relief {
        ReliefChoice::Given {
            amount_um,
            length_mm,
            shape,
        } => (
            TipRelief {
                amount_m: amount_um * 1e-6,
                length_m: length(length_mm),
                shape,
            },
            None,
        ),
        ReliefChoice::DesignLoad {
            load_n,
            length_mm,
            shape,
        } => {
            let template = TipRelief {
                amount_m: 0.0,
                length_m: length(length_mm),
                shape,
            };
            template.validate(geo)?;
            let probe = TipRelief {
                amount_m: 1e-6,
                ..template
            };
            probe.validate(geo)?;
            (
                design_relief(model, &template, load_n, opts.samples)?.0,
                Some(load_n),
            )
        }
    })
}

/// STE, stiffness, contact loss and harmonics at one load.
fn load_result(
    model: &MeshModel,
    relief: &TipRelief,
    load_n: f64,
    opts: &MeshOptions,
    half_backlash_um: f64,
) -> Result<LoadResult> {
    let w = model.waveform(load_n, relief, opts.samples)?;
    let harmonics = mesh_harmonics(&w, opts.harmonics)?;
    let ks = &w.stiffness_n_per_um;
    let lost = w
        .pairs
        .iter()
        .filter(|p| p.iter().any(|q| q.load_n == 0.0))
        .count();
    Ok(LoadResult {
        load_n,
        ste_pp_um: w.ste_pp_um(),
        ste_mean_um: super::ste::mean(&w.ste_um),
        ste_half_pp_um: w.ste_pp_um() / 2.0,
        mesh_stiffness_mean_n_per_um: w.mean_stiffness_n_per_um(),
        mesh_stiffness_min_n_per_um: ks.iter().copied().fold(f64::INFINITY, f64::min),
        mesh_stiffness_max_n_per_um: ks.iter().copied().fold(0.0, f64::max),
        contact_loss_fraction: lost as f64 / w.pairs.len() as f64,
        f_ah1: harmonics[0].ste_amplitude_um / half_backlash_um,
        harmonics,
        waveform: w,
    })
}

impl GeometrySummary {
    /// The pair's geometry in millimetres and degrees.
    fn of(geo: &GearPairGeometry) -> GeometrySummary {
        let mm = 1e3;
        let (sc_lo, sc_hi) = geo.single_contact_zone();
        GeometrySummary {
            contact_ratio: geo.contact_ratio(),
            base_pitch_mm: geo.base_pitch() * mm,
            path_of_contact_mm: geo.path_of_contact() * mm,
            start_of_contact_mm: geo.start_of_contact() * mm,
            pitch_point_mm: geo.pitch_point() * mm,
            end_of_contact_mm: geo.end_of_contact() * mm,
            single_contact_from_mm: sc_lo * mm,
            single_contact_to_mm: sc_hi * mm,
            centre_distance_mm: geo.centre_distance_m * mm,
            working_pressure_angle_deg: geo.working_pressure_angle.to_degrees(),
            pinion_tip_diameter_mm: 2.0 * geo.pinion.tip_radius_m * mm,
            gear_tip_diameter_mm: 2.0 * geo.gear.tip_radius_m * mm,
            pinion_root_diameter_mm: 2.0 * geo.pinion.root_radius_m * mm,
            gear_root_diameter_mm: 2.0 * geo.gear.root_radius_m * mm,
            pinion_bore_diameter_mm: 2.0 * geo.pinion.bore_radius_m * mm,
            gear_bore_diameter_mm: 2.0 * geo.gear.bore_radius_m * mm,
            youngs_modulus_gpa: geo.youngs_modulus_pa * 1e-9,
            poisson_ratio: geo.poisson_ratio,
        }
    }
}
