//! The analysis commands in the rig's units (`--rig --load-n --ste-um --zeta --omega-n-hz
//! --speed-rpm`, paper Sec. 2.1) checked against computations made here by hand: the
//! dimensionless sweep scaled by b, k_h and f_n, and the closed form of the in-contact response
//! (eq. 13) on the shipped Munro rig, where the stiffness is the ISO 6336-1 estimate.

mod common;

use common::geardyn;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;

/// Rows of a CSV text as column-name -> cell maps.
fn rows(csv: &str) -> Vec<HashMap<String, String>> {
    let mut lines = csv.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

fn val(row: &HashMap<String, String>, col: &str) -> f64 {
    row.get(col)
        .unwrap_or_else(|| panic!("no column {col}"))
        .parse()
        .unwrap_or_else(|_| panic!("{col} = {:?} is not a number", row[col]))
}

/// Run a command that must succeed; its standard output and error.
fn run(args: &[&str]) -> (String, String) {
    let out = geardyn(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "geardyn {args:?} failed: {err}");
    (String::from_utf8_lossy(&out.stdout).into_owned(), err)
}

/// A rig with round scales: 2b = 0.1 mm and k_h = 250 N/um give b k_h = 12500 N, so that
/// 1250 N is F_m = 0.1 and 2.5 um is F_ah = 0.05; with 30 pinion teeth and f_n = 1000 Hz a
/// speed of n rpm is Omega = 30 n / 60 / 1000 = n / 2000. A gear pair, not a data set: no
/// [source] table, which `--rig` does not need.
const ROUND_RIG: &str = r#"[rig]
name = "round-number rig"
pinion_teeth = 30
gear_teeth = 45
module_mm = 3.0
pressure_angle_deg = 20.0
face_width_mm = 20.0
design_load_n = 1250.0
backlash_mm = 0.1
mesh_stiffness_n_per_um = 250.0
zeta = 0.05
omega_n_hz = 1000.0
"#;

#[test]
fn dimensional_sweep_is_the_dimensionless_one_scaled() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rig = dir.path().join("rig.toml");
    std::fs::write(&rig, ROUND_RIG).expect("write rig");
    let out = dir.path().join("out");
    // zeta and f_n come from rig.toml (no --zeta, --omega-n-hz); the load is its design load.
    let (dim_csv, err) = run(&[
        "sweep",
        "--rig",
        rig.to_str().unwrap(),
        "--ste-um",
        "2.5",
        "--speed-rpm",
        "400:3200:200",
        "--out",
        out.to_str().unwrap(),
    ]);
    for needle in [
        "F_m  = F̄_m / (b k_h) = 1250 N / (50 µm × 250 N/µm) = 0.100000",
        "F_ah = ē / b = 2.5 µm / 50 µm = 0.050000",
        "zeta = 0.05 from rig.toml",
        "omega_n_hz = 1000 from rig.toml",
    ] {
        assert!(
            err.contains(needle),
            "'{needle}' not in the conversion:\n{err}"
        );
    }
    let (plain_csv, _) = run(&[
        "sweep",
        "--fm",
        "0.1",
        "--fah",
        "0.05",
        "--zeta",
        "0.05",
        "--omega",
        "0.2:1.6:0.1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (d, p) = (rows(&dim_csv), rows(&plain_csv));
    assert_eq!(d.len(), 15);
    assert_eq!(d.len(), p.len());
    for (k, (d, p)) in d.iter().zip(&p).enumerate() {
        let speed = 400.0 + 200.0 * k as f64;
        assert_eq!(val(d, "speed_rpm"), speed);
        assert_eq!(val(d, "mesh_freq_hz"), speed / 2.0);
        assert!((val(d, "omega") - speed / 2000.0).abs() < 1e-12);
        // The grid prints as typed: 1.2, not 1.2000000000000002 (0.1 + 11 x 0.1 in floating
        // point would be the latter).
        assert_eq!(p["omega"], format!("{}", (2 + k) as f64 / 10.0));
        for (col, scaled, factor) in [
            ("qa", "qa_um", 50.0),
            ("qm", "qm_um", 50.0),
            ("dte_pp", "dte_pp_um", 50.0),
            ("dl_max", "mesh_force_max_n", 1250.0),
        ] {
            // The same model (F_m 0.1 and F_ah 0.05 to the last bits), so the same steady
            // state to the printed digits (10 decimals dimensionless, 6 in um, 4 in N).
            let (a, b) = (val(d, col), val(p, col));
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "{col} at {speed} rpm: {a} vs {b}"
            );
            let s = val(d, scaled);
            assert!(
                (s - factor * b).abs() <= 1e-6 * (factor * b).abs().max(1.0),
                "{scaled} at {speed} rpm: {s} vs {factor} x {b}"
            );
        }
    }
    assert!(Path::new(&out).join("sweep.png").is_file());
}

/// The in-contact response of eq. 13 in the rig's units, computed here: Omega = z1 n / 60 / f_n,
/// b q_a = e Omega^2 / |1 - Omega^2 + 2 i zeta Omega|, pp DTE = 2 e |1 + 2 i zeta Omega| /
/// |1 - Omega^2 + 2 i zeta Omega| (x = q + e / b), both independent of the load and stiffness,
/// and D_L = 1 + (e / b) Omega^2 |H_x| / F_m with F_m from k_h = c' (0.75 eps + 0.25) x face
/// width (ISO 6336-1, the contact ratio by the roll-angle form).
#[test]
fn munro_design_load_follows_eq_13() {
    let munro = concat!(env!("CARGO_MANIFEST_DIR"), "/data/munro/rig.toml");
    let dir = tempfile::tempdir().expect("temp dir");
    let (ste, zeta, f_n, load) = (0.3, 0.0175, 1600.0, 3780.0);
    let (csv, _) = run(&[
        "sweep",
        "--rig",
        munro,
        "--load-n",
        "3780",
        "--ste-um",
        "0.3",
        "--zeta",
        "0.0175",
        "--omega-n-hz",
        "1600",
        "--speed-rpm",
        "1000:5000:250",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    // Munro's gears: 32/32 teeth, 20 deg, module 6.35 mm, face 12.7 mm, 2b = 0.1 mm.
    let alpha = 20f64.to_radians();
    let alpha_a = (16.0 * alpha.cos() / 17.0).acos();
    let eps = 2.0 * 32.0 * (alpha_a.tan() - alpha.tan()) / (2.0 * PI);
    let k_h = 14.0 * (0.75 * eps + 0.25) * 12.7; // N/um
    let fm = load / (50.0 * k_h);
    let rows = rows(&csv);
    assert_eq!(rows.len(), 17);
    for r in &rows {
        let n = val(r, "speed_rpm");
        let w = 32.0 * n / 60.0 / f_n;
        let den = ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
        let hx = (1.0 + (2.0 * zeta * w).powi(2)).sqrt() / den;
        assert_eq!(val(r, "case"), 1.0, "teeth separate at {n} rpm");
        let checks = [
            ("qa_um", ste * w * w / den),
            ("dte_pp_um", 2.0 * ste * hx),
            (
                "mesh_force_max_n",
                load * (1.0 + ste / 50.0 * w * w * hx / fm),
            ),
        ];
        for (col, expected) in checks {
            let got = val(r, col);
            // The exact solver's extrema are refined to ~1e-9 of q; the CSV prints 6 decimals
            // of um (4 of N): 2e-6 relative covers both at these levels (0.01-5 um, 4 kN).
            assert!(
                (got - expected).abs() <= 2e-6 * expected.abs() + 2e-6,
                "{col} at {n} rpm: {got} vs eq. 13 {expected}"
            );
        }
    }
}

#[test]
fn wrong_combinations_are_rejected_with_the_option_named() {
    let munro = concat!(env!("CARGO_MANIFEST_DIR"), "/data/munro/rig.toml");
    let cases: [(&[&str], &str); 5] = [
        (
            &[
                "simulate",
                "--fm",
                "0.1",
                "--fah",
                "0.2",
                "--zeta",
                "0.02",
                "--speed-rpm",
                "1000",
            ],
            "--rig",
        ),
        (
            &[
                "simulate",
                "--rig",
                munro,
                "--fm",
                "0.1",
                "--ste-um",
                "1",
                "--zeta",
                "0.02",
                "--omega-n-hz",
                "1600",
                "--speed-rpm",
                "1000",
            ],
            "--fm",
        ),
        (
            &[
                "simulate",
                "--rig",
                munro,
                "--ste-um",
                "1",
                "--zeta",
                "0.02",
                "--speed-rpm",
                "1000",
            ],
            "--omega-n-hz is needed with --rig",
        ),
        (
            &[
                "simulate",
                "--rig",
                munro,
                "--zeta",
                "0.02",
                "--omega-n-hz",
                "1600",
                "--speed-rpm",
                "1000",
            ],
            "--ste-um is needed",
        ),
        (
            &[
                "sweep",
                "--rig",
                munro,
                "--ste-um",
                "1",
                "--zeta",
                "0.02",
                "--omega-n-hz",
                "1600",
                "--speed-rpm",
                "1:1000000:1",
            ],
            "--speed-rpm",
        ),
    ];
    for (args, needle) in cases {
        let out = geardyn(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(needle), "{args:?}: '{needle}' not in: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// Eq. 4's torque in the rig's units: `--torque-n T` is F_aT = T / (b k_h) (625 N on the round
/// rig is 0.05), and in contact the two forces act as one sinusoid (F_ah Ω² + F_aT) sin(Ω t),
/// so b q_a = b (F_ah Ω² + F_aT) / |1 - Ω² + 2 i ζ Ω| (computed here).
#[test]
fn torque_in_newtons_is_eq_4_in_contact() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rig = dir.path().join("rig.toml");
    std::fs::write(&rig, ROUND_RIG).expect("write rig");
    let (csv, err) = run(&[
        "sweep",
        "--rig",
        rig.to_str().unwrap(),
        "--ste-um",
        "2.5",
        "--torque-n",
        "625",
        "--speed-rpm",
        "400:1000:200",
        "--out",
        dir.path().join("out").to_str().unwrap(),
    ]);
    assert!(
        err.contains("F_aT = T̄_a / (r_b b k_h) = 625 N / (b k_h) = 0.050000"),
        "{err}"
    );
    let (fm, fah, fat, zeta) = (0.1, 0.05, 0.05, 0.05);
    let rows = rows(&csv);
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let w = val(r, "speed_rpm") / 2000.0;
        let den = ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt();
        let qa = (fah * w * w + fat) / den;
        assert!(qa < fm, "the check needs contact: q_a {qa} at Omega {w}");
        assert_eq!(val(r, "case"), 1.0);
        let got = val(r, "qa_um");
        // 6 printed decimals of um at 2-5 um, the exact solver's extrema to ~1e-9.
        assert!(
            (got - 50.0 * qa).abs() <= 2e-6 * 50.0 * qa + 2e-6,
            "qa_um at Omega {w}: {got} vs {}",
            50.0 * qa
        );
    }
}
