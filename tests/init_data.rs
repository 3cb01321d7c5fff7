//! `geardyn init-data DIR` round trip: the template is refused until it is filled (naming every
//! missing key at once, writing nothing); filled with the shipped Munro rig's [rig] values and
//! curves and labelled measured, `validate munro --data DIR` accepts it, and the fit and the
//! report say "measured" first.

mod common;

use common::geardyn;
use std::path::Path;

/// Run geardyn; (success, stdout, stderr).
fn run(args: &[&str]) -> (bool, String, String) {
    let out = geardyn(args);
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Fill the template as a user would: each line `# key = example   # REQUIRED...` becomes
/// `key = value`, the value taken from `values` ([rig] keys) or the template's example (the
/// [source] texts).
fn fill(template: &str, values: &toml::Table) -> String {
    template
        .lines()
        .map(|line| {
            let Some(rest) = line.strip_prefix("# ") else {
                return line.to_string();
            };
            let Some((assignment, comment)) = rest.split_once("# REQUIRED") else {
                return line.to_string();
            };
            let _ = comment;
            let (key, example) = assignment.split_once('=').expect("key = value");
            let key = key.trim();
            match values.get(key) {
                Some(v) => format!("{key} = {v}"),
                None => format!("{key} = {}", example.trim()),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn template_filled_with_own_data_validates_as_measured() {
    let dir = tempfile::tempdir().expect("temp dir");
    let set = dir.path().join("my-rig");
    let (fits, reports) = (dir.path().join("fits"), dir.path().join("reports"));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let (ok, _, err) = run(&["init-data", &s(&set)]);
    assert!(ok, "{err}");
    let validate = [
        "validate",
        "munro",
        "--data",
        &s(&set),
        "--fits",
        &s(&fits),
        "--reports",
        &s(&reports),
    ];

    // Unfilled: every required [rig] key named in one message, nothing written.
    let (ok, _, err) = run(&validate);
    assert!(!ok);
    assert!(
        err.contains(
            "rig.toml:11: field 'rig.name': missing in [rig]: name, pinion_teeth, \
                      gear_teeth, module_mm, pressure_angle_deg, face_width_mm, design_load_n, \
                      backlash_mm"
        ),
        "{err}"
    );
    assert!(!fits.exists() && !reports.exists());
    // A second init-data into the same folder overwrites nothing.
    let (ok, _, err) = run(&["init-data", &s(&set)]);
    assert!(!ok && err.contains("overwrites nothing"), "{err}");

    // Filled with the shipped rig's geometry; the CSV still has its header only.
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/munro");
    let rig: toml::Table =
        toml::from_str(&std::fs::read_to_string(shipped.join("rig.toml")).unwrap())
            .expect("shipped rig.toml");
    let rig_values = rig["rig"].as_table().expect("[rig]");
    let template = std::fs::read_to_string(set.join("rig.toml")).unwrap();
    std::fs::write(set.join("rig.toml"), fill(&template, rig_values)).unwrap();
    let (ok, _, err) = run(&validate);
    assert!(
        !ok && err.contains("dte.csv") && err.contains("no data rows"),
        "{err}"
    );

    // The points: the shipped curves (made by geardyn synth, not by this test) as if measured.
    let shipped_csv = std::fs::read_to_string(shipped.join("dte.csv")).unwrap();
    let rows: String = shipped_csv
        .lines()
        .skip(1)
        .map(|l| format!("{l}\n"))
        .collect();
    let mut csv = std::fs::read_to_string(set.join("dte.csv")).unwrap();
    csv.push_str(&rows);
    std::fs::write(set.join("dte.csv"), csv).unwrap();
    let (ok, out, err) = run(&validate);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("MEASURED DATA: Gear lab test report"),
        "{out}"
    );
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fits.join("munro.json")).unwrap()).unwrap();
    assert_eq!(j["data_kind"], "measured");
    assert!(j["notice"].as_str().unwrap().starts_with("MEASURED DATA"));
    // The same curves as the shipped set: the fit finds its truth (zeta 0.0175, 1600 Hz,
    // rig.toml [source.truth]) within the intervals the README reports for it.
    let (zeta, f_n) = (
        j["zeta"].as_f64().unwrap(),
        j["omega_n_hz"].as_f64().unwrap(),
    );
    assert!(
        (zeta - 0.0175).abs() < 0.001 && (f_n - 1600.0).abs() < 2.0,
        "{zeta} {f_n}"
    );
    let html = std::fs::read_to_string(reports.join("munro/index.html")).unwrap();
    assert!(html.contains("MEASURED DATA"));
    assert!(!html.contains("SYNTHETIC"));
}

#[test]
fn kubo_layout_writes_its_header() {
    let dir = tempfile::tempdir().expect("temp dir");
    let set = dir.path().join("k");
    let (ok, _, err) = run(&["init-data", set.to_str().unwrap(), "--layout", "kubo"]);
    assert!(ok, "{err}");
    let csv = std::fs::read_to_string(set.join("dynamic_factor.csv")).unwrap();
    assert!(csv.ends_with("speed_rpm,dynamic_factor_min,dynamic_factor_max\n"));
    let rig = std::fs::read_to_string(set.join("rig.toml")).unwrap();
    assert!(rig.contains("geardyn validate kubo --data DIR"));
}
