//! geardyn's mesh stiffness against ROSS, an independent code (issue 67, item 4).
//!
//! ROSS (`ross-rotordynamics` 2.3.0 on PyPI, `ross/gear_element.py`: `GearElementTVMS`, `Mesh`)
//! computes a spur pair's time-varying mesh stiffness by the same family of formulas as
//! `src/mesh/tooth_stiffness.rs` (potential energy of bending, shear and axial compression,
//! Sainsot et al.'s 2004 fillet foundation, Yang & Lin's Hertz term), written independently. Its
//! numbers for two pairs are in `tests/data/ross-mesh.json`, made by
//! `tools/ross-mesh/ross_mesh.py` with their provenance (ROSS, Python, NumPy and SciPy versions,
//! the inputs with units, the date); CI does not run the script, only this file reads the JSON.
//!
//! The pairs: 62/62 teeth, module 2 mm, 20 deg, face 20 mm, bores 35 mm, E 211 GPa, nu 0.3; and
//! Munro's gears as geardyn defines them (data/munro/rig.toml with the `[geometry]` defaults:
//! bores 62.44 mm, E 206 GPa, nu 0.3). The contact ratios agree; the mean mesh stiffness is
//! 3.9% above ROSS's on the 62/62 pair and 0.85% above on Munro's gears; the single-pair
//! stiffness at the pitch point is 8% above ROSS's on both. That gap is traced to the two
//! inputs ROSS gives Sainsot's fillet-foundation term, and the mean gaps are smaller because
//! ROSS's contact path (not the line of action's) raises its own mean. Each test says which
//! fixture numbers it reads; ROSS's numbers are never recomputed here, geardyn's always are.

use geardyn::data::{load_rig_with_geometry, GearGeometry, Rig};
use geardyn::mesh::tooth_stiffness::SAINSOT;
use geardyn::mesh::{pair_stiffness, GearBody, GearPairGeometry, MeshModel, TipRelief};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize)]
struct Fixture {
    provenance: Provenance,
    cases: Vec<Case>,
}

#[derive(Deserialize)]
struct Provenance {
    script: String,
    ross_rotordynamics: String,
    python: String,
    generated_utc: String,
}

#[derive(Deserialize)]
struct Inputs {
    pinion_teeth: u32,
    gear_teeth: u32,
    module_mm: f64,
    pressure_angle_deg: f64,
    face_width_mm: f64,
    bore_diameter_mm: f64,
    youngs_modulus_gpa: f64,
    poisson_ratio: f64,
    addendum_coefficient: f64,
    tip_clearance_coefficient: f64,
}

#[derive(Deserialize)]
struct MeshPeriod {
    mesh_position: Vec<f64>,
    stiffness_n_per_um: Vec<f64>,
}

#[derive(Deserialize)]
struct Compliance {
    bending: f64,
    shear: f64,
    axial: f64,
    foundation: f64,
}

#[derive(Deserialize)]
struct PitchPoint {
    single_pair_stiffness_n_per_um: f64,
    hertz_compliance_m_per_n: f64,
    pinion_compliance_m_per_n: Compliance,
    gear_compliance_m_per_n: Compliance,
}

#[derive(Deserialize)]
struct FoundationInputs {
    root_half_angle_rad: f64,
    root_radius_mm: f64,
    root_over_bore_radius: f64,
    pitch_point_load_height_mm: f64,
}

#[derive(Deserialize)]
struct Case {
    name: String,
    inputs: Inputs,
    contact_ratio: f64,
    mesh_stiffness_mean_n_per_um: f64,
    mesh_stiffness_max_n_per_um: f64,
    mesh_stiffness_min_n_per_um: f64,
    mesh_stiffness_mean_line_of_action_n_per_um: f64,
    mesh_period: MeshPeriod,
    pitch_point: PitchPoint,
    foundation_inputs: FoundationInputs,
}

/// The fixture, its provenance checked.
fn fixture() -> Fixture {
    let text = std::fs::read_to_string("tests/data/ross-mesh.json").expect("fixture readable");
    let f: Fixture = serde_json::from_str(&text).expect("fixture parses");
    let p = &f.provenance;
    assert_eq!(p.script, "tools/ross-mesh/ross_mesh.py");
    assert!(!p.ross_rotordynamics.is_empty() && !p.python.is_empty());
    assert!(p.generated_utc.len() >= 10);
    f
}

fn case<'a>(f: &'a Fixture, name: &str) -> &'a Case {
    f.cases
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("case {name} in the fixture"))
}

/// Munro's rig as shipped (`[rig]` and the `[geometry]` defaults).
fn munro_rig() -> (Rig, GearGeometry) {
    let (file, geometry) =
        load_rig_with_geometry(Path::new("data/munro/rig.toml")).expect("Munro's rig loads");
    (file.rig, geometry)
}

/// geardyn's gears for the fixture's inputs: the `[rig]` of Munro's rig file with the teeth,
/// module, pressure angle and face width replaced, and the bores and material in `[geometry]`.
fn geardyn_pair(c: &Case) -> GearPairGeometry {
    let i = &c.inputs;
    // ROSS's rack (addendum 1 m, clearance 0.25 m) is geardyn's default one.
    assert_eq!(
        (i.addendum_coefficient, i.tip_clearance_coefficient),
        (1.0, 0.25)
    );
    let rig = Rig {
        pinion_teeth: i.pinion_teeth,
        gear_teeth: i.gear_teeth,
        module_mm: i.module_mm,
        pressure_angle_deg: i.pressure_angle_deg,
        face_width_mm: i.face_width_mm,
        ..munro_rig().0
    };
    let geometry = GearGeometry {
        pinion_bore_diameter_mm: Some(i.bore_diameter_mm),
        gear_bore_diameter_mm: Some(i.bore_diameter_mm),
        youngs_modulus_gpa: Some(i.youngs_modulus_gpa),
        poisson_ratio: Some(i.poisson_ratio),
        ..GearGeometry::default()
    };
    GearPairGeometry::from_rig(&rig, &geometry).expect("a valid pair")
}

/// Mean mesh stiffness with every pair in contact (no relief), N/um, over 1024 positions.
fn geardyn_mean(geo: &GearPairGeometry) -> f64 {
    MeshModel::new(geo.clone()).mean_mesh_stiffness_n_per_um(1024)
}

/// The Munro case is Munro's rig as geardyn reads it: the fixture's bores and modulus are
/// geardyn's defaults for data/munro/rig.toml, to the last digit printed.
#[test]
fn munro_case_is_geardyns_munro() {
    let f = fixture();
    let c = case(&f, "munro");
    let (rig, geometry) = munro_rig();
    let shipped = GearPairGeometry::from_rig(&rig, &geometry).unwrap();
    assert!((2e3 * shipped.pinion.bore_radius_m - c.inputs.bore_diameter_mm).abs() < 1e-9);
    assert!((2e3 * shipped.gear.bore_radius_m - c.inputs.bore_diameter_mm).abs() < 1e-9);
    assert_eq!(shipped.youngs_modulus_pa, c.inputs.youngs_modulus_gpa * 1e9);
    assert_eq!(shipped.poisson_ratio, c.inputs.poisson_ratio);
    assert_eq!(shipped, geardyn_pair(c));
}

/// The contact ratios agree (both codes: eps_alpha = (sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 -
/// r_b2^2) - a sin(alpha)) / p_b, written independently): 1.789780 (62/62) and 1.667642
/// (Munro), to 1e-5 relative (observed 2e-15). ROSS's samples of the period also have two pairs
/// in contact at the same mesh positions as geardyn's: both put a new pair's entry at position
/// 0, so two pairs share the load over [0, eps_alpha - 1] of the period. ROSS's two-pair
/// samples are told by their stiffness, above the midpoint of its period's max and min.
#[test]
fn contact_ratio_and_double_contact_agree_with_ross() {
    let f = fixture();
    for c in &f.cases {
        let geo = geardyn_pair(c);
        let eps = geo.contact_ratio();
        assert!(
            (eps / c.contact_ratio - 1.0).abs() < 1e-5,
            "{}: geardyn {eps} vs ROSS {}",
            c.name,
            c.contact_ratio
        );
        let model = MeshModel::new(geo);
        let mid = (c.mesh_stiffness_max_n_per_um + c.mesh_stiffness_min_n_per_um) / 2.0;
        let p = &c.mesh_period;
        assert_eq!(p.mesh_position.len(), p.stiffness_n_per_um.len());
        assert!(p.mesh_position.len() >= 24, "a few dozen samples");
        for (&pos, &k) in p.mesh_position.iter().zip(&p.stiffness_n_per_um) {
            let pairs = model.pairs_at(pos).len();
            assert_eq!(
                k > mid,
                pairs == 2,
                "{} at position {pos}: ROSS {k} N/um, geardyn {pairs} pairs",
                c.name
            );
        }
    }
}

/// geardyn's mean, max and min over the period (1024 positions, every pair in contact, no
/// relief), N/um.
fn geardyn_period(geo: &GearPairGeometry) -> (f64, f64, f64) {
    let w = MeshModel::new(geo.clone())
        .waveform(1000.0, &TipRelief::none(), 1024)
        .expect("waveform");
    let k = &w.stiffness_n_per_um;
    let max = k.iter().copied().fold(0.0, f64::max);
    let min = k.iter().copied().fold(f64::INFINITY, f64::min);
    (geardyn_mean(geo), max, min)
}

/// geardyn / ROSS - 1 of the mean, max and min.
fn period_gaps(c: &Case) -> [f64; 3] {
    let (mean, max, min) = geardyn_period(&geardyn_pair(c));
    [
        mean / c.mesh_stiffness_mean_n_per_um - 1.0,
        max / c.mesh_stiffness_max_n_per_um - 1.0,
        min / c.mesh_stiffness_min_n_per_um - 1.0,
    ]
}

/// 62/62 pair: geardyn's mean mesh stiffness is 397.6 N/um, ROSS's 382.6 (its 1000-point
/// table of the period): 3.9% above; max 445.8 against 429.8 (+3.7%), min 244.0 against 234.9
/// (+3.9%). The gap is known and held to [2%, 6%] for all three: geardyn's single-pair
/// stiffness is 8% above ROSS's because of the two inputs ROSS gives the fillet-foundation term
/// (`pitch_point_gap_is_rosss_fillet_foundation_inputs`), and ROSS's contact path raises its
/// own mean by 3% (`mean_gap_is_the_foundation_gap_less_rosss_contact_path`).
#[test]
fn mean_mesh_stiffness_of_the_62_62_pair_is_4_percent_above_ross() {
    let f = fixture();
    let gaps = period_gaps(case(&f, "pair_62_62"));
    for (what, gap) in ["mean", "max", "min"].iter().zip(gaps) {
        assert!(
            (0.02..=0.06).contains(&gap),
            "62/62 {what}: geardyn {:+.2}% from ROSS",
            100.0 * gap
        );
    }
}

/// Munro's gears (E 206 GPa): geardyn's mean mesh stiffness is 240.1 N/um, ROSS's 238.1: 0.85%
/// above; max 284.6 against 282.7, min 158.4 against 157.5. Held within 2%: here the two known
/// differences (fillet-foundation inputs, ROSS's contact path) nearly cancel in the mean.
#[test]
fn mean_mesh_stiffness_of_munros_gears_agrees_with_ross() {
    let f = fixture();
    let gaps = period_gaps(case(&f, "munro"));
    for (what, gap) in ["mean", "max", "min"].iter().zip(gaps) {
        assert!(
            gap.abs() < 0.02,
            "Munro {what}: geardyn {:+.2}% from ROSS",
            100.0 * gap
        );
    }
}

/// The single-pair stiffness with both teeth loaded at the pitch point: geardyn 244.9 N/um
/// against ROSS's 226.2 (62/62, +8.3%), 160.0 against 148.1 (Munro, +8.1%); the known gap is
/// held to [6%, 10%]. It comes from the two inputs ROSS gives Sainsot et al.'s fillet-foundation
/// term, whose formula (Table 1 polynomials, h_f = r_f / r_bore, S_f = 2 r_f theta_f) both codes
/// share:
///
/// - the root half-angle theta_f: ROSS builds it with the addendum coefficient h_a* = 1 where
///   the rack that cuts the root has the dedendum h_f* = 1.25 (geardyn, `GearBody::
///   root_half_angle`): 0.04566 against 0.04859 rad (62/62), a narrower root;
/// - the load height u: ROSS takes the contact point's height above the root circle, geardyn
///   the height where the line of action crosses the tooth's centre line (Sainsot et al.'s u_f).
///
/// With ROSS's two inputs (from the fixture) the formula gives ROSS's foundation compliance to
/// 1e-9 (observed 1e-16: the same formula), and geardyn's pair with that foundation term is
/// within 2% of ROSS's (observed -0.5% and -1.2%). What is left is bending, shear and axial
/// compression, within 5% (observed +1.9% and +4.4%: ROSS integrates the rack-cut fillet
/// curve, geardyn the involute down to the root circle, or a straight flank below the base
/// circle); the Hertz terms are the same formula (1e-9).
#[test]
fn pitch_point_gap_is_rosss_fillet_foundation_inputs() {
    let f = fixture();
    for c in &f.cases {
        let geo = geardyn_pair(c);
        let r = &c.pitch_point;
        let ross = r.single_pair_stiffness_n_per_um;
        let p = pair_stiffness(&geo, geo.pitch_point());
        let k = p.stiffness_n_per_m * 1e-6;
        let gap = k / ross - 1.0;
        assert!(
            (0.06..=0.10).contains(&gap),
            "{}: pitch-point pair {k} N/um vs ROSS {ross}: {:+.2}%",
            c.name,
            100.0 * gap
        );
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(
            rel(p.hertz, r.hertz_compliance_m_per_n) < 1e-9,
            "{}",
            c.name
        );
        // The bodies ROSS's foundation term sees: the same root circle and bore ratio.
        let fi = &c.foundation_inputs;
        assert!(rel(geo.pinion.root_radius_m * 1e3, fi.root_radius_mm) < 1e-9);
        let h = geo.pinion.root_radius_m / geo.pinion.bore_radius_m;
        assert!(rel(h, fi.root_over_bore_radius) < 1e-9);
        let mut swapped = 1.0 / p.stiffness_n_per_m;
        for (body, ours, theirs) in [
            (&geo.pinion, &p.pinion, &r.pinion_compliance_m_per_n),
            (&geo.gear, &p.gear, &r.gear_compliance_m_per_n),
        ] {
            // The test's formula is geardyn's at geardyn's inputs ...
            let own = sainsot_at(&geo, body, body.root_half_angle, None);
            assert!(rel(own, ours.foundation) < 1e-9, "{}: {own}", c.name);
            // ... and ROSS's at ROSS's.
            let with_ross = ross_input_foundation(&geo, body, c);
            assert!(
                rel(with_ross, theirs.foundation) < 1e-9,
                "{}: {with_ross} vs ROSS {}",
                c.name,
                theirs.foundation
            );
            swapped += with_ross - ours.foundation;
            let rest = ours.bending + ours.shear + ours.axial;
            let rest_ross = theirs.bending + theirs.shear + theirs.axial;
            assert!(
                rel(rest, rest_ross) < 0.05,
                "{}: bending + shear + axial {rest} vs ROSS {rest_ross}",
                c.name
            );
        }
        let k_swapped = 1e-6 / swapped;
        assert!(
            rel(k_swapped, ross) < 0.02,
            "{}: with ROSS's foundation inputs {k_swapped} N/um vs ROSS {ross}",
            c.name
        );
    }
}

/// Why the mean gap (3.9% on the 62/62 pair, 0.85% on Munro's) is smaller than the pitch-point
/// gap (8%): ROSS advances each tooth's profile pressure angle linearly in time from the basic
/// rack's limit point, not the mating gear's start of active profile, so its pairs do not sit
/// where the line of action puts them (in single contact both teeth are loaded below the pitch
/// point, stiffer). The fixture's diagnostic places ROSS's own pair stiffness on the line of
/// action as geardyn does: 370.5 and 224.6 N/um (ROSS's path raises its mean by 3.3% and 6.0%).
/// geardyn's mean is 7.3% and 6.9% above those, in [5%, 9%] and within 2 points of the
/// pitch-point gap: on the same kinematics the mean gap is the single-pair gap.
#[test]
fn mean_gap_is_the_foundation_gap_less_rosss_contact_path() {
    let f = fixture();
    for c in &f.cases {
        let geo = geardyn_pair(c);
        let gap = geardyn_mean(&geo) / c.mesh_stiffness_mean_line_of_action_n_per_um - 1.0;
        let pitch = pair_stiffness(&geo, geo.pitch_point()).stiffness_n_per_m * 1e-6
            / c.pitch_point.single_pair_stiffness_n_per_um
            - 1.0;
        assert!(
            (0.05..=0.09).contains(&gap) && (gap - pitch).abs() < 0.02,
            "{}: mean {:+.2}% vs ROSS on the line of action, pitch point {:+.2}%",
            c.name,
            100.0 * gap,
            100.0 * pitch
        );
    }
}

/// Sainsot et al.'s (2004) fillet-foundation compliance (m/N) of `body`'s tooth loaded at the
/// pitch point, with root half-angle `theta_f` and load height `height_m` above the root
/// circle (`None`: geardyn's, to where the line of action crosses the tooth's centre line).
fn sainsot_at(geo: &GearPairGeometry, body: &GearBody, theta_f: f64, height_m: Option<f64>) -> f64 {
    let phi = geo.working_pressure_angle;
    let a1 = phi.tan() - body.half_base_angle;
    let r = body.base_radius_m / phi.cos();
    let psi = body.half_base_angle - (phi.tan() - phi);
    let (xc, yc) = (r * psi.sin(), r * psi.cos());
    let rf = body.root_radius_m;
    let u = height_m.unwrap_or(yc - xc * a1.tan() - rf) / (2.0 * rf * theta_f);
    let h = rf / body.bore_radius_m;
    let [l, m, p, q] = SAINSOT.map(|c| {
        c[0] / (theta_f * theta_f)
            + c[1] * h * h
            + c[2] * h / theta_f
            + c[3] / theta_f
            + c[4] * h
            + c[5]
    });
    a1.cos().powi(2) / (geo.youngs_modulus_pa * geo.face_width_m)
        * (l * u * u + m * u + p * (1.0 + q * a1.tan().powi(2)))
}

/// The same with ROSS's two inputs from the fixture.
fn ross_input_foundation(geo: &GearPairGeometry, body: &GearBody, c: &Case) -> f64 {
    let fi = &c.foundation_inputs;
    sainsot_at(
        geo,
        body,
        fi.root_half_angle_rad,
        Some(fi.pitch_point_load_height_mm * 1e-3),
    )
}
