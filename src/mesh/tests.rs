//! Checks of the tooth-contact model on Munro's gears (32/32, module 6.35 mm, 20 deg, face
//! 12.7 mm; Kahraman & Singh 1990 Sec. 7) against hand calculation, published closed forms and
//! ISO 6336-1, and the Harris-map properties of issue 24.

use super::ste::pp;
use super::tooth_stiffness::{hertz_compliance, tooth_compliance};
use super::*;
use crate::data::GearGeometry;
use crate::model::{Dimensional, StiffnessSource};

fn munro() -> GearPairGeometry {
    GearPairGeometry::from_rig(&crate::data::munro_rig(), &GearGeometry::default()).unwrap()
}

/// Harris's long relief on both tips, `amount_um` deep.
fn long_relief(geo: &GearPairGeometry, amount_um: f64) -> TipRelief {
    TipRelief {
        amount_m: amount_um * 1e-6,
        length_m: TipRelief::long_length(geo),
        shape: ReliefShape::Linear,
    }
}

#[test]
fn munro_path_of_contact_matches_hand_calculation() {
    // Hand calculation, lengths in mm:
    //   r   = m z / 2            = 6.35 x 32 / 2          = 101.6
    //   r_b = r cos 20 deg       = 101.6 x 0.93969262     = 95.472770
    //   r_a = r + m              = 107.95
    //   T1E = sqrt(r_a^2 - r_b^2) = sqrt(11653.2025 - 9115.0499) = sqrt(2538.1526) = 50.380082
    //   T1T2 = a sin 20 deg      = 203.2 x 0.34202014     = 69.498493
    //   T1A = T1T2 - T2A         = 69.498493 - 50.380082  = 19.118411
    //   g_alpha = T1E - T1A      = 31.261670
    //   T1C = r_b tan 20 deg     = 34.749247 (approach = recess = 15.630835)
    //   p_b = pi m cos 20 deg    = 18.746035
    //   eps_alpha = 31.261670 / 18.746035 = 1.667642
    //   single contact: T1E - p_b = 31.634047 to T1A + p_b = 37.864446 (length 6.230399)
    let g = munro();
    let mm = |x: f64| x * 1e3;
    let close = |a: f64, b: f64| (a - b).abs() < 2e-6;
    assert!(close(mm(g.pinion.base_radius_m), 95.472770));
    assert!(close(mm(g.end_of_contact()), 50.380082));
    assert!(close(mm(g.line_of_action_length()), 69.498493));
    assert!(close(mm(g.start_of_contact()), 19.118411));
    assert!(close(mm(g.path_of_contact()), 31.261670));
    assert!(close(mm(g.pitch_point() - g.start_of_contact()), 15.630835));
    assert!(close(mm(g.end_of_contact() - g.pitch_point()), 15.630835));
    assert!(close(mm(g.base_pitch()), 18.746035));
    assert!((g.contact_ratio() - 1.667642).abs() < 1e-6);
    let (lo, hi) = g.single_contact_zone();
    assert!(close(mm(lo), 31.634047) && close(mm(hi), 37.864446));
    // The same contact ratio as the model's standard-geometry formula.
    let std = Dimensional::standard_contact_ratio(32, 32, 20.0);
    assert!((g.contact_ratio() - std).abs() < 1e-9);
}

/// Tian (MSc thesis, U. Alberta, 2004, eqs. 2.13-2.15; also Chaari et al. 2009) give the
/// bending, shear and axial compliances of a tooth whose root circle is its base circle as
/// integrals over the angle alpha in [-alpha_1, alpha_2]. The y-integrals of
/// `tooth_compliance` must agree with them.
#[test]
fn tooth_compliance_agrees_with_tians_closed_form_integrals() {
    let geo = munro();
    let mut body = geo.pinion.clone();
    body.root_radius_m = body.base_radius_m;
    let (e, l, nu) = (geo.youngs_modulus_pa, geo.face_width_m, geo.poisson_ratio);
    let a2 = body.half_base_angle;
    for roll_mm in [22.0, 30.0, 34.75, 42.0, 50.0] {
        let roll = roll_mm * 1e-3;
        let a1 = (roll / body.base_radius_m) - a2; // tan(phi) - alpha_2
        let c = tooth_compliance(&geo, &body, roll);
        let n = 20_000;
        let integral = |f: &dyn Fn(f64) -> f64| {
            let h = (a2 + a1) / n as f64;
            (0..=n)
                .map(|i| {
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * f(-a1 + i as f64 * h)
                })
                .sum::<f64>()
                * h
                / 3.0
        };
        let den = |a: f64| a.sin() + (a2 - a) * a.cos();
        let kb = integral(&|a: f64| {
            let t = 1.0 + a1.cos() * ((a2 - a) * a.sin() - a.cos());
            3.0 * t * t * (a2 - a) * a.cos() / (2.0 * e * l * den(a).powi(3))
        });
        let ks = integral(&|a: f64| {
            1.2 * (1.0 + nu) * (a2 - a) * a.cos() * a1.cos().powi(2) / (e * l * den(a))
        });
        let ka = integral(&|a: f64| (a2 - a) * a.cos() * a1.sin().powi(2) / (2.0 * e * l * den(a)));
        let rel = |x: f64, y: f64| (x - y).abs() / y;
        assert!(
            rel(c.bending, kb) < 2e-3,
            "bending {} vs Tian {kb}",
            c.bending
        );
        assert!(rel(c.shear, ks) < 2e-3, "shear {} vs Tian {ks}", c.shear);
        assert!(rel(c.axial, ka) < 2e-3, "axial {} vs Tian {ka}", c.axial);
    }
}

#[test]
fn hertz_term_is_yang_and_lins_line_contact() {
    // Yang & Lin (1987): k_h = pi E L / (4 (1 - nu^2)); E = 206 GPa, nu = 0.3, L = 12.7 mm:
    // pi x 206e9 x 0.0127 / (4 x 0.91) = 2.2579e9 N/m.
    let k = 1.0 / hertz_compliance(&munro());
    assert!((k - 2.2579e9).abs() / 2.2579e9 < 1e-4, "{k}");
}

/// ISO 6336-1 method B for Munro's gears ([`crate::mesh::IsoStiffness`]): c' = 12.968 N/(mm
/// um), c_gamma_alpha = c' (0.75 eps_alpha + 0.25) = 19.461 N/(mm um), times 12.7 mm = 247.2
/// N/um. The potential-energy mean (every pair in contact, no relief) is 240.1 N/um, 2.8%
/// below: within the 10% issue 24 asks. It was 23% below while the fillet-foundation term took
/// the tooth's root as the base-circle thickness, without the fillets the rack cuts
/// ([`crate::mesh::GearBody::root_half_angle`]). ISO's typical c' = 14 (the model's default k_h
/// when the rig gives none, [`Dimensional::new`]) gives 266.8 N/um, 10.0% above. Also the
/// shape ISO assumes: mean over the largest pair stiffness near 0.75 eps_alpha + 0.25.
#[test]
fn mean_mesh_stiffness_against_iso_6336_c_gamma() {
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    let mean = model.mean_mesh_stiffness_n_per_um(1024);
    let iso = geo.iso6336();
    let iso_b = iso.c_gamma_alpha * 12.7;
    assert!(
        (iso_b - 247.16).abs() < 0.05,
        "ISO c_gamma_alpha b = {iso_b}"
    );
    let ratio = mean / iso_b;
    assert!(
        (ratio - 1.0).abs() < 0.10,
        "PE mean {mean} N/um vs ISO method B {iso_b}: {ratio}"
    );
    let dim = crate::data::munro_rig().dimensional().unwrap();
    let StiffnessSource::Iso6336Estimate { contact_ratio, .. } = dim.stiffness_source else {
        panic!("Munro's rig gives no stiffness: ISO estimate expected");
    };
    let typical = dim.mesh_stiffness_n_per_m * 1e-6;
    assert!((typical - 266.83).abs() < 0.05, "ISO c' = 14: {typical}");
    let kmax = model
        .stiffness
        .points
        .iter()
        .map(|p| p.stiffness_n_per_m * 1e-6)
        .fold(0.0, f64::max);
    let shape = mean / kmax;
    let iso_shape = 0.75 * contact_ratio + 0.25;
    assert!(
        (shape - iso_shape).abs() / iso_shape < 0.05,
        "{shape} vs {iso_shape}"
    );
}

/// The largest pair stiffness along the path (at the pitch point) per face width against
/// ISO 6336-1's single-pair stiffness c' = c'_th C_M C_R C_B = 12.968 N/(mm um) (method B,
/// [`crate::mesh::IsoStiffness`]): within 10%.
#[test]
fn peak_pair_stiffness_against_iso_6336_single_stiffness() {
    let geo = munro();
    let c_prime = geo.iso6336().c_prime;
    assert!((c_prime - 12.968).abs() < 1e-3);
    let model = MeshModel::new(geo.clone());
    let peak = model
        .stiffness
        .points
        .iter()
        .max_by(|a, b| a.stiffness_n_per_m.total_cmp(&b.stiffness_n_per_m))
        .unwrap();
    let per_mm = peak.stiffness_n_per_m * 1e-6 / 12.7;
    assert!(
        (per_mm / c_prime - 1.0).abs() < 0.1,
        "{per_mm} vs c' {c_prime}"
    );
    // Identical gears: the stiffest point is the pitch point (symmetric path).
    assert!((peak.roll_m - geo.pitch_point()).abs() < 0.01 * geo.path_of_contact());
}

/// The tooth's root between its fillets (ISO 53 profile A rack: h_f* 1.25, rho* 0.38): theta_f
/// = (pi/2 + 2 tan 20 deg (1.25 - 0.38) + 2 x 0.38 / cos 20 deg) / 32 = 0.094152 rad by hand,
/// wider than the straight flank at the base-circle thickness (half angle 0.0652 on the root
/// circle) that the foundation term used before.
#[test]
fn root_half_angle_includes_the_fillets() {
    let geo = munro();
    let t = 20f64.to_radians();
    let by_hand = (std::f64::consts::PI / 2.0 + 2.0 * t.tan() * 0.87 + 0.76 / t.cos()) / 32.0;
    assert!((by_hand - 0.094152).abs() < 1e-6, "{by_hand}");
    assert!((geo.pinion.root_half_angle - by_hand).abs() < 1e-12);
    let straight = (geo.pinion.base_radius_m * geo.pinion.half_base_angle.sin()
        / geo.pinion.root_radius_m)
        .asin();
    assert!((straight - 0.0652).abs() < 5e-4, "{straight}");
    // The rack's tip (pi/4 - 1.25 tan 20 deg = 0.3304 m half wide) holds tip radii up to
    // 0.3304 cos 20 deg / (1 - sin 20 deg) = 0.472 m; 0.5 m is refused, naming the key.
    let too_round = GearGeometry {
        root_fillet_coefficient: Some(0.5),
        ..GearGeometry::default()
    };
    let e = GearPairGeometry::from_rig(&crate::data::munro_rig(), &too_round).unwrap_err();
    assert!(e.to_string().contains("root_fillet_coefficient"), "{e}");
    let fits = GearGeometry {
        root_fillet_coefficient: Some(0.47),
        ..GearGeometry::default()
    };
    assert!(GearPairGeometry::from_rig(&crate::data::munro_rig(), &fits).is_ok());
}

#[test]
fn foundation_dominates_the_pair_compliance() {
    let geo = munro();
    let p = pair_stiffness(&geo, geo.pitch_point());
    let total = 1.0 / p.stiffness_n_per_m;
    let f = (p.pinion.foundation + p.gear.foundation) / total;
    let b = (p.pinion.bending + p.gear.bending) / total;
    assert!(f > 0.5 && f < 0.8, "foundation share {f}");
    assert!(b > 0.02 && b < 0.2, "bending share {b}");
    // Bending grows as the contact moves to the tip; the foundation term too.
    let tip = pair_stiffness(&geo, geo.end_of_contact());
    assert!(tip.pinion.bending > 5.0 * p.pinion.bending);
    assert!(tip.pinion.foundation > p.pinion.foundation);
}

/// With no profile modification every pair on the line of action carries load in proportion
/// to its stiffness, so the loaded STE has a closed form (Harris 1958; Tavakoli & Houser 1986):
/// delta(t) = W / k(t), k(t) = sum_j k(s_j) over the pairs at s_j = s_A + (tau + j) p_b <= s_E.
/// Its mean and peak-to-peak follow from the stiffness function alone, here
/// [`pair_stiffness`] evaluated directly (the model interpolates a 401-point table of it). The
/// compatibility solve is exact (no iteration), so the tolerance, 1e-5 relative at every
/// position, is set by the table's linear interpolation: at most (h^2/8) |k''| / k = 3e-6 here
/// (h = g_alpha / 400 = 0.078 mm, |k''| from the table's second differences).
#[test]
fn without_relief_ste_is_load_over_mesh_stiffness() {
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    let samples = 512;
    let (sa, se, pb) = (
        geo.start_of_contact(),
        geo.end_of_contact(),
        geo.base_pitch(),
    );
    // k(t) in N/um at tau / p_b = i / samples, from the potential-energy function itself.
    let k: Vec<f64> = (0..samples)
        .map(|i| {
            let frac = i as f64 / samples as f64;
            (0..3)
                .map(|j| sa + (frac + j as f64) * pb)
                .filter(|&s| s <= se + 1e-12 * pb)
                .map(|s| pair_stiffness(&geo, s).stiffness_n_per_m * 1e-6)
                .sum()
        })
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    for load in [945.0, 3780.0, 4725.0] {
        let w = model.waveform(load, &TipRelief::none(), samples).unwrap();
        let closed: Vec<f64> = k.iter().map(|k| load / k).collect();
        for (i, (ste, c)) in w.ste_um.iter().zip(&closed).enumerate() {
            assert!(
                (ste - c).abs() < 1e-5 * c,
                "{load} N, position {i}: STE {ste} um vs W / k(t) = {c} um"
            );
        }
        let (m, mc) = (mean(&w.ste_um), mean(&closed));
        assert!((m - mc).abs() < 1e-5 * mc, "{load} N: mean {m} vs {mc}");
        let pc = pp(&closed);
        assert!(
            (w.ste_pp_um() - pc).abs() < 1e-5 * mc,
            "{load} N: pp {} vs {pc}",
            w.ste_pp_um()
        );
        // The peak-to-peak is the load times the compliance swing, F (1/k_min - 1/k_max).
        let kmin = k.iter().copied().fold(f64::INFINITY, f64::min);
        let kmax = k.iter().copied().fold(0.0, f64::max);
        assert!((pc - load * (1.0 / kmin - 1.0 / kmax)).abs() < 1e-9 * mc);
        // Every pair geometrically in contact carries load; equilibrium at every position.
        for pairs in &w.pairs {
            let sum: f64 = pairs.iter().map(|p| p.load_n).sum();
            assert!((sum - load).abs() < 1e-6 * load);
            assert!(pairs.iter().all(|p| p.load_n > 0.0));
        }
    }
}

/// Harris's rule on Munro's gears: the relief sized for 3780 N gives the Harris map (STE pp
/// against load) its minimum near 3780 N, and that minimum is not zero, as the paper says of
/// Munro's profile modifications (Kahraman & Singh 1990 Sec. 7: minimum, not zero, STE at the
/// design load).
#[test]
fn relief_designed_for_a_load_is_best_there_and_worse_at_light_load() {
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    let (relief, pp_design) = design_relief(&model, &long_relief(&geo, 0.0), 3780.0, 256).unwrap();
    // Harris's rule of thumb: the optimum long relief is near the single-pair deflection at the
    // design load (3780 N over the pitch-point pair stiffness, 23.6 um here).
    let single = 3780.0 / pair_stiffness(&geo, geo.pitch_point()).stiffness_n_per_m;
    assert!(
        (relief.amount_m / single - 1.0).abs() < 0.25,
        "{relief:?} vs {single}"
    );
    let loads = [945.0, 1890.0, 2835.0, 3400.0, 3780.0, 4200.0, 4725.0];
    let map = harris_map(&model, &relief, &loads, 256).unwrap();
    let at = |l: f64| map.iter().find(|p| p.load_n == l).unwrap().ste_pp_um;
    assert!((at(3780.0) - pp_design).abs() < 1e-9);
    let best = map
        .iter()
        .min_by(|a, b| a.ste_pp_um.total_cmp(&b.ste_pp_um))
        .unwrap();
    assert!(best.load_n >= 3400.0 && best.load_n <= 4200.0, "{best:?}");
    // Rising toward light load, and well below the unrelieved STE at the design load.
    assert!(at(945.0) > at(1890.0) && at(1890.0) > at(2835.0) && at(2835.0) > at(3780.0));
    let bare = model.waveform(3780.0, &TipRelief::none(), 256).unwrap();
    assert!(pp_design < 0.25 * bare.ste_pp_um());
    // Not zero: in the single-tooth-contact zone [s_E - p_b, s_A + p_b] the long relief leaves
    // the one pair in contact unrelieved, so there delta = W / k(s) whatever the depth, and the
    // STE pp at any load W is at least the swing W (1/k(zone end) - 1/k(pitch point)), with k
    // from `pair_stiffness` (the pitch point is the stiffest point of identical gears): 0.30 um
    // at 3780 N, where the STE pp is 1.10 um. Held to 0.9 of it: the 256 positions come within
    // p_b / 256 = 0.07 mm of the zone's ends.
    let (lo, hi) = geo.single_contact_zone();
    let k = |s: f64| pair_stiffness(&geo, s).stiffness_n_per_m;
    let swing_per_n = 1.0 / k(lo).min(k(hi)) - 1.0 / k(geo.pitch_point());
    assert!(3780.0 * swing_per_n * 1e6 > 0.1, "{swing_per_n}");
    for p in &map {
        let floor_um = p.load_n * swing_per_n * 1e6;
        assert!(p.ste_pp_um >= 0.9 * floor_um, "{p:?}: floor {floor_um} um");
    }
    assert!(pp_design >= 0.9 * 3780.0 * swing_per_n * 1e6, "{pp_design}");
}

#[test]
fn at_very_light_load_the_ste_is_the_relief_profile() {
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    for shape in [ReliefShape::Linear, ReliefShape::Parabolic] {
        let relief = TipRelief {
            shape,
            ..long_relief(&geo, 20.0)
        };
        let w = model.waveform(0.5, &relief, 256).unwrap();
        let profile = model.relief_profile_um(&relief, 256);
        let pp_profile = pp(&profile);
        assert!(pp_profile > 4.0);
        assert!((w.ste_pp_um() - pp_profile).abs() / pp_profile < 0.02);
        let offset = w.ste_um[0] - profile[0];
        for (s, p) in w.ste_um.iter().zip(&profile) {
            assert!((s - p - offset).abs() < 0.01 * pp_profile);
        }
    }
}

#[test]
fn harmonics_rebuild_the_waveform() {
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    let w = model
        .waveform(2835.0, &long_relief(&geo, 24.0), 256)
        .unwrap();
    let h = mesh_harmonics(&w, 127).unwrap();
    let mean_e: f64 = ste::mean(&w.ste_um);
    let k_mean = w.mean_stiffness_n_per_um();
    // The first harmonic carries most of the STE; the series rebuilds e(t) and k(t).
    let rms_e = (w.ste_um.iter().map(|e| (e - mean_e).powi(2)).sum::<f64>() / 256.0).sqrt();
    assert!(h[0].ste_amplitude_um > 0.8 * std::f64::consts::SQRT_2 * rms_e);
    for (i, (&e, &k)) in w.ste_um.iter().zip(&w.stiffness_n_per_um).enumerate() {
        let th = 2.0 * std::f64::consts::PI * i as f64 / 256.0;
        let e_fit: f64 = mean_e
            + h.iter()
                .map(|c| c.ste_amplitude_um * (c.order as f64 * th + c.ste_phase_rad).sin())
                .sum::<f64>();
        let k_fit = k_mean
            * (1.0
                + h.iter()
                    .map(|c| c.stiffness_eps * (c.order as f64 * th + c.stiffness_phase_rad).cos())
                    .sum::<f64>());
        // Order 128 (Nyquist) is left out: its share is below the tolerance.
        assert!(
            (e - e_fit).abs() < 0.05 * w.ste_pp_um(),
            "{i}: {e} vs {e_fit}"
        );
        assert!((k - k_fit).abs() < 0.05 * k_mean, "{i}: {k} vs {k_fit}");
    }
}

#[test]
fn bad_geometry_and_relief_are_named_errors() {
    let rig = crate::data::munro_rig();
    let too_close = GearGeometry {
        centre_distance_mm: Some(150.0),
        ..GearGeometry::default()
    };
    let e = GearPairGeometry::from_rig(&rig, &too_close)
        .unwrap_err()
        .to_string();
    assert!(e.contains("geometry.centre_distance_mm"), "{e}");
    let short_tips = GearGeometry {
        pinion_tip_diameter_mm: Some(204.0),
        gear_tip_diameter_mm: Some(204.0),
        ..GearGeometry::default()
    };
    let e = GearPairGeometry::from_rig(&rig, &short_tips)
        .unwrap_err()
        .to_string();
    // The stated tips shortened the path of contact: the first of them is named.
    assert!(
        e.contains("geometry.pinion_tip_diameter_mm") && e.contains("contact ratio below 1"),
        "{e}"
    );
    // A bore below a tenth of the root diameter is outside the fillet-foundation formula.
    let pinhole = GearGeometry {
        pinion_bore_diameter_mm: Some(1e-300),
        ..GearGeometry::default()
    };
    let e = GearPairGeometry::from_rig(&rig, &pinhole)
        .unwrap_err()
        .to_string();
    assert!(e.contains("geometry.pinion_bore_diameter_mm"), "{e}");
    let inside = GearGeometry {
        pinion_tip_diameter_mm: Some(190.0),
        ..GearGeometry::default()
    };
    let e = GearPairGeometry::from_rig(&rig, &inside)
        .unwrap_err()
        .to_string();
    assert!(e.contains("geometry.pinion_tip_diameter_mm"), "{e}");
    let geo = munro();
    let model = MeshModel::new(geo.clone());
    let too_long = TipRelief {
        length_m: 0.02,
        ..long_relief(&geo, 10.0)
    };
    let e = model
        .waveform(1000.0, &too_long, 64)
        .unwrap_err()
        .to_string();
    assert!(e.contains("relief_length_mm"), "{e}");
    let e = model
        .waveform(-1.0, &TipRelief::none(), 64)
        .unwrap_err()
        .to_string();
    assert!(e.contains("load_n"), "{e}");
}

#[test]
fn profile_shift_moves_the_centre_distance_and_path() {
    // x1 = x2 = 0.2: inv(alpha_w) = inv 20 deg + 2 tan 20 deg x 0.4 / 64 = 0.0194540,
    // alpha_w = 21.7872 deg, a = 203.2 cos 20 deg / cos alpha_w = 205.6 mm (to 0.1 mm).
    let g = GearGeometry {
        pinion_profile_shift: Some(0.2),
        gear_profile_shift: Some(0.2),
        ..GearGeometry::default()
    };
    let geo = GearPairGeometry::from_rig(&crate::data::munro_rig(), &g).unwrap();
    assert!((geo.working_pressure_angle.to_degrees() - 21.7872).abs() < 1e-3);
    assert!((geo.centre_distance_m * 1e3 - 205.6).abs() < 0.1);
    assert!(geo.contact_ratio() > 1.0 && geo.contact_ratio() < munro().contact_ratio());
}

/// A profile table sampled from the long linear relief of both gears (three points a flank:
/// below the start of active profile, the start of relief and the tip, as diameters) gives the
/// STE of the analytic relief: the diameter-to-roll conversion, the gear's roll measured from
/// T2 and the interpolation checked against the closed form, at 945 and 3780 N.
#[test]
fn profile_table_of_a_tip_relief_reproduces_it() {
    let geo = munro();
    let relief = long_relief(&geo, 20.0);
    let (sa, se, t) = (
        geo.start_of_contact(),
        geo.end_of_contact(),
        geo.line_of_action_length(),
    );
    let l = relief.length_m;
    let diameter = |rb: f64, rho: f64| 2e3 * (rho * rho + rb * rb).sqrt();
    let flank = |rb: f64, tip_roll: f64, sap_roll: f64| {
        vec![
            (diameter(rb, sap_roll - 5e-4), 0.0),
            (diameter(rb, tip_roll - l), 0.0),
            (diameter(rb, tip_roll), 20.0),
        ]
    };
    let pinion = flank(geo.pinion.base_radius_m, se, sa);
    let gear = flank(geo.gear.base_radius_m, t - sa, t - se);
    let dev = ProfileDeviation::from_diameters(&geo, &pinion, &gear).unwrap();
    let tabled = MeshModel::new(geo.clone()).with_deviation(dev);
    let analytic = MeshModel::new(geo.clone());
    for load in [945.0, 3780.0] {
        let a = analytic.waveform(load, &relief, 128).unwrap();
        let b = tabled.waveform(load, &TipRelief::none(), 128).unwrap();
        let worst = a
            .ste_um
            .iter()
            .zip(&b.ste_um)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{load} N: STE differs by {worst} um");
    }
}

/// A table that stops short of the flank in contact, or starts inside the base circle, is
/// refused with the diameters it needs.
#[test]
fn profile_table_must_cover_the_flank_in_contact() {
    let geo = munro();
    let rb = geo.pinion.base_radius_m;
    let d_sap = 2e3 * (geo.start_of_contact().powi(2) + rb * rb).sqrt();
    let short = [(d_sap, 0.0), (200.0, 1.0)];
    let e = ProfileDeviation::from_diameters(&geo, &short, &[]).unwrap_err();
    assert!(e.to_string().contains("extend the table"), "{e}");
    let inside = [(2e3 * rb - 0.1, 0.0), (216.0, 1.0)];
    let e = ProfileDeviation::from_diameters(&geo, &inside, &[]).unwrap_err();
    assert!(e.to_string().contains("inside its base circle"), "{e}");
    assert!(ProfileDeviation::from_diameters(&geo, &[], &[])
        .unwrap()
        .is_empty());
}
