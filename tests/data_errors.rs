//! Bad data sets give one located error (file, line, field); good ones load, with mesh
//! frequencies converted to shaft speed. Uses only the public API, as the pipelines do.

use geardyn::data::{load_kubo, load_munro, DataKind, WHOLE_FILE};
use geardyn::GearError;
use std::path::Path;

/// A valid synthetic Munro-like rig.toml; line numbers below refer to it.
const MUNRO_RIG: &str = r#"[rig]
name = "Munro-like test rig"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1

[ste]
load_n = [3780.0, 2835.0, 1890.0, 945.0]
amplitude_um = [0.5, 2.0, 3.0, 4.0]

[source]
kind = "synthetic"
citation = "imitates Munro (1962) as compared in Kahraman & Singh (1990), Figs. 19-22"
generator = "geardyn synth 0.1.0"

[source.truth]
zeta = 0.0175
omega_n_hz = 1600.0
"#;

/// A valid digitized Kubo-like rig.toml.
const KUBO_RIG: &str = r#"[rig]
name = "Kubo-like test rig"
pinion_teeth = 25
gear_teeth = 25
module_mm = 4.0
pressure_angle_deg = 20.0
face_width_mm = 10.0
design_load_n = 2000.0
backlash_mm = 0.1
test_load_n = 1500.0
zeta = 0.1

[source]
kind = "digitized"
citation = "Kubo, via Ozguven & Houser (1988), as in Kahraman & Singh (1990) Fig. 23"
figure = "Fig. 23"
method = "manual, 4-point axis calibration"
uncertainty = "+-1 % of axis span"
"#;

const MUNRO_CSV: &str = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.0\n3780,1100,1.2\n3780,1200,1.5\n";
const KUBO_CSV: &str =
    "speed_rpm,dynamic_factor_min,dynamic_factor_max\n1000,1.0,1.1\n2000,1.1,1.4\n";

/// A temporary data set with `rig` (if any) as rig.toml and the given CSV files.
fn dataset(rig: Option<&str>, csvs: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    if let Some(rig) = rig {
        std::fs::write(dir.path().join("rig.toml"), rig).expect("write rig");
    }
    for (name, body) in csvs {
        std::fs::write(dir.path().join(name), body).expect("write csv");
    }
    dir
}

/// Assert `r` is one data error naming `file` (file name), `line` and `field`, and that its
/// message says so too.
fn assert_located<T: std::fmt::Debug>(
    r: geardyn::Result<T>,
    file: &str,
    line: usize,
    field: &str,
    case: &str,
) {
    let err = match r {
        Err(e) => e,
        Ok(v) => panic!("{case}: expected an error, loaded {v:?}"),
    };
    let text = err.to_string();
    match err {
        GearError::Data {
            file: f,
            line: l,
            field: fd,
            message,
        } => {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            assert_eq!(name.as_deref(), Some(file), "{case}: {text}");
            assert_eq!((l, fd.as_str()), (line, field), "{case}: {text}");
            assert!(!message.is_empty(), "{case}");
            assert!(text.contains(&format!("{file}:{line}")), "{case}: {text}");
            assert!(text.contains(&format!("'{field}'")), "{case}: {text}");
        }
        other => panic!("{case}: expected GearError::Data, got {other:?}"),
    }
}

/// Munro data set whose single curve file `c.csv` is `csv`.
fn munro_csv_error(csv: &str, line: usize, field: &str, case: &str) {
    let d = dataset(Some(MUNRO_RIG), &[("c.csv", csv)]);
    assert_located(load_munro(d.path()), "c.csv", line, field, case);
}

/// Munro data set whose rig.toml is `rig`.
fn munro_rig_error(rig: &str, line: usize, field: &str, case: &str) {
    let d = dataset(Some(rig), &[("c.csv", MUNRO_CSV)]);
    assert_located(load_munro(d.path()), "rig.toml", line, field, case);
}

/// Kubo data set whose single curve file `k.csv` is `csv`.
fn kubo_csv_error(csv: &str, line: usize, field: &str, case: &str) {
    let d = dataset(Some(KUBO_RIG), &[("k.csv", csv)]);
    assert_located(load_kubo(d.path()), "k.csv", line, field, case);
}

#[test]
fn munro_csv_errors_are_located() {
    let h = "load_n,speed_rpm,dte_pp_um\n";
    let cases: Vec<(String, usize, &str, &str)> = vec![
        (String::new(), 1, "(header)", "empty file"),
        (h.to_string(), 2, "(rows)", "only a header"),
        (
            "\u{feff}load_n,speed_rpm,dte_pp_um\r\n".into(),
            2,
            "(rows)",
            "BOM header only",
        ),
        (
            "load_n,speed_rpm,dte\n1,2,3\n".into(),
            1,
            "dte_pp_um",
            "missing column",
        ),
        (
            "load_n,rpm,dte_pp_um\n1,2,3\n".into(),
            1,
            "speed_rpm",
            "missing speed column",
        ),
        (
            format!("{h}3780,1000,abc\n"),
            2,
            "dte_pp_um",
            "text in a number",
        ),
        (
            format!("{h}3780,1000,1\n3780,NaN,1\n"),
            3,
            "speed_rpm",
            "NaN",
        ),
        (format!("{h}3780,1000,inf\n"), 2, "dte_pp_um", "infinite"),
        (format!("{h}-3780,1000,1\n"), 2, "load_n", "negative load"),
        (format!("{h}0,1000,1\n"), 2, "load_n", "zero load"),
        (format!("{h}3780,0,1\n"), 2, "speed_rpm", "zero speed"),
        (
            format!("{h}3780,1000,-0.5\n"),
            2,
            "dte_pp_um",
            "negative DTE",
        ),
        (format!("{h}3780,1000,\n"), 2, "dte_pp_um", "empty cell"),
        (
            format!("{h}3780,1000,1\n3780,1200,1\n3780,1100,1\n"),
            4,
            "speed_rpm",
            "unsorted",
        ),
        (
            format!("{h}3780,1000,1\n2835,1000,1\n3780,1000,2\n"),
            4,
            "speed_rpm",
            "duplicate",
        ),
        (
            "load_n,mesh_freq_hz,dte_pp_um\n3780,0,1\n".into(),
            2,
            "mesh_freq_hz",
            "zero frequency",
        ),
        (
            "load_n,mesh_freq_hz,dte_pp_um\r\n3780,600,1\r\n\r\n3780,500,1\r\n".into(),
            4,
            "mesh_freq_hz",
            "unsorted frequency, CRLF, blank line",
        ),
        (
            "load_n,speed_rpm,mesh_freq_hz,dte_pp_um\n3780,1000,900,1\n".into(),
            2,
            "mesh_freq_hz",
            "inconsistent units",
        ),
        (
            "\u{0}\u{1}\u{2}binary\n\u{3}".into(),
            1,
            "load_n",
            "control characters",
        ),
    ];
    for (csv, line, field, case) in &cases {
        munro_csv_error(csv, *line, field, case);
    }
}

#[test]
fn non_utf8_csv_is_located() {
    let d = tempfile::tempdir().expect("temp dir");
    std::fs::write(d.path().join("rig.toml"), MUNRO_RIG).expect("write");
    std::fs::write(
        d.path().join("c.csv"),
        b"load_n,speed_rpm,dte_pp_um\n\xff\xd8\xff\xe0",
    )
    .expect("write");
    assert_located(load_munro(d.path()), "c.csv", 2, WHOLE_FILE, "binary junk");
}

#[test]
fn munro_rig_errors_are_located() {
    let r = MUNRO_RIG;
    let no_source = r.split("[source]").next().unwrap_or_default().to_string();
    let no_truth = r
        .split("[source.truth]")
        .next()
        .unwrap_or_default()
        .to_string();
    let cases: Vec<(String, usize, &str, &str)> = vec![
        (
            r.replace("backlash_mm", "backlash"),
            9,
            "rig.backlash",
            "key without unit",
        ),
        (
            r.replace("design_load_n", "load_N"),
            8,
            "rig.load_N",
            "unit typo",
        ),
        (
            r.replace("module_mm = 6.35\n", ""),
            1,
            "rig.module_mm",
            "missing key",
        ),
        (no_source, 0, "source", "missing [source]"),
        (
            r.replace("\"synthetic\"", "\"measured\""),
            16,
            "source.kind",
            "bad kind",
        ),
        (no_truth, 15, "source.truth", "synthetic without truth"),
        (
            r.replace("generator = \"geardyn synth 0.1.0\"\n", ""),
            15,
            "source.generator",
            "synthetic without generator",
        ),
        (
            r.replace("\"synthetic\"", "\"digitized\""),
            15,
            "source.method",
            "digitized without method",
        ),
        (
            r.replace("[0.5, 2.0, 3.0, 4.0]", "[0.5, 2.0]"),
            13,
            "ste.amplitude_um",
            "STE lengths",
        ),
        (
            r.replace("[0.5, 2.0", "[-0.5, 2.0"),
            13,
            "ste.amplitude_um",
            "STE sign",
        ),
        (
            r.replace("gear_teeth = 32", "gear_teeth = 3"),
            4,
            "rig.gear_teeth",
            "teeth",
        ),
        (
            r.replace("= 0.1\n", "= 0.0\n"),
            9,
            "rig.backlash_mm",
            "zero backlash",
        ),
        (
            r.replace("= 6.35", "= -6.35"),
            5,
            "rig.module_mm",
            "negative module",
        ),
        (
            r.replace("= 20.0", "= 40.0"),
            6,
            "rig.pressure_angle_deg",
            "pressure angle",
        ),
        (
            r.replace("backlash_mm = 0.1", "backlash_mm = 0.1\nzeta = 1.5"),
            10,
            "rig.zeta",
            "zeta",
        ),
        (
            r.replace("= 6.35", "= \"6.35 mm\""),
            5,
            "rig.module_mm",
            "text value",
        ),
        (
            r.replace("[source]", "[source"),
            15,
            "(toml)",
            "TOML syntax",
        ),
    ];
    for (rig, line, field, case) in &cases {
        munro_rig_error(rig, *line, field, case);
    }
}

#[test]
fn missing_rig_and_missing_curves() {
    let d = dataset(None, &[("c.csv", MUNRO_CSV)]);
    assert_located(
        load_munro(d.path()),
        "rig.toml",
        0,
        WHOLE_FILE,
        "no rig.toml",
    );
    let d = dataset(Some(MUNRO_RIG), &[]);
    let folder = d
        .path()
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    assert_located(load_munro(d.path()), &folder, 0, WHOLE_FILE, "no CSV files");
}

#[test]
fn kubo_errors_are_located() {
    let h = "speed_rpm,dynamic_factor_min,dynamic_factor_max\n";
    let cases: Vec<(String, usize, &str, &str)> = vec![
        (
            format!("{h}1000,1.3,1.1\n"),
            2,
            "dynamic_factor_min",
            "min > max",
        ),
        (
            format!("{h}1000,-1.0,1.1\n"),
            2,
            "dynamic_factor_min",
            "negative factor",
        ),
        (format!("{h}1000,1.0,x\n"), 2, "dynamic_factor_max", "text"),
        (
            "speed_rpm,dynamic_factor_min\n1000,1\n".into(),
            1,
            "dynamic_factor_max",
            "column",
        ),
        (
            format!("{h}1000,1,1.1\n900,1,1.1\n"),
            3,
            "speed_rpm",
            "unsorted",
        ),
        (
            format!("{h}1000,1,1.1\n1000,1,1.2\n"),
            3,
            "speed_rpm",
            "duplicate",
        ),
        (format!("{h}-5,1,1.1\n"), 2, "speed_rpm", "negative speed"),
    ];
    for (csv, line, field, case) in &cases {
        kubo_csv_error(csv, *line, field, case);
    }
    let bad_rig = KUBO_RIG.replace("zeta = 0.1", "zeta = 0.0");
    let d = dataset(Some(&bad_rig), &[("k.csv", KUBO_CSV)]);
    assert_located(load_kubo(d.path()), "rig.toml", 11, "rig.zeta", "zeta = 0");
    let no_method = KUBO_RIG.replace("method = \"manual, 4-point axis calibration\"\n", "");
    let d = dataset(Some(&no_method), &[("k.csv", KUBO_CSV)]);
    assert_located(
        load_kubo(d.path()),
        "rig.toml",
        13,
        "source.method",
        "no method",
    );
    let no_unc = KUBO_RIG.replace("uncertainty = \"+-1 % of axis span\"\n", "");
    let d = dataset(Some(&no_unc), &[("k.csv", KUBO_CSV)]);
    assert_located(
        load_kubo(d.path()),
        "rig.toml",
        13,
        "source.uncertainty",
        "no unc.",
    );
}

#[test]
fn good_munro_set_loads() {
    // Two files (sorted by name): speeds in rpm, and mesh frequencies (CRLF, BOM, extra column,
    // trailing blank line) that become rpm = f * 60 / 32.
    let hz =
        "\u{feff}load_n,mesh_freq_hz,dte_pp_um,comment\r\n2835,400,2.0,x\r\n2835,480,2.5,y\r\n\r\n";
    let d = dataset(
        Some(MUNRO_RIG),
        &[("b_three_quarter.csv", hz), ("a_design.csv", MUNRO_CSV)],
    );
    let m = load_munro(d.path()).expect("good Munro set");
    assert_eq!(m.rig.source.kind, DataKind::Synthetic);
    assert_eq!(m.rig.source.kind.name(), "synthetic");
    assert_eq!(m.points.len(), 5);
    assert_eq!(m.loads(), vec![3780.0, 2835.0]);
    let c = m.curve(2835.0);
    assert_eq!(c.len(), 2);
    assert!((c[0].speed_rpm - 750.0).abs() < 1e-9);
    assert!((c[1].speed_rpm - 900.0).abs() < 1e-9);
    assert_eq!((c[1].dte_pp_um, c[1].line), (2.5, 3));
    assert!(c[1].file.ends_with("b_three_quarter.csv"));
    let design = m.curve(3780.0);
    let speeds: Vec<f64> = design.iter().map(|p| p.speed_rpm).collect();
    assert_eq!(speeds, vec![1000.0, 1100.0, 1200.0]);
    assert_eq!(
        m.points[0].file.file_name(),
        Path::new("a_design.csv").file_name()
    );
    assert_eq!(
        m.rig.ste.as_ref().and_then(|s| s.amplitude_at(945.0)),
        Some(4.0)
    );
}

#[test]
fn good_kubo_set_loads() {
    let hz = "mesh_freq_hz,dynamic_factor_min,dynamic_factor_max\n500,1.0,1.05\n1000,0.9,1.3\n";
    let d = dataset(Some(KUBO_RIG), &[("k.csv", hz)]);
    let k = load_kubo(d.path()).expect("good Kubo set");
    assert_eq!(k.rig.source.kind, DataKind::Digitized);
    assert_eq!(k.rig.rig.test_load_or_design_n(), 1500.0);
    assert_eq!(k.rig.rig.zeta, Some(0.1));
    assert_eq!(k.points.len(), 2);
    // 500 Hz * 60 / 25 teeth = 1200 rpm
    assert!((k.points[0].speed_rpm - 1200.0).abs() < 1e-9);
    assert!((k.points[1].speed_rpm - 2400.0).abs() < 1e-9);
    assert_eq!(k.points[1].dynamic_factor_max, 1.3);
    assert_eq!(k.points[1].line, 3);
    let d = dataset(Some(KUBO_RIG), &[("k.csv", KUBO_CSV)]);
    assert_eq!(
        load_kubo(d.path()).expect("rpm set").points[1].speed_rpm,
        2000.0
    );
}
