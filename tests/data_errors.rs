//! Bad data sets give one located error (file, line, field); good ones load, with mesh
//! frequencies converted to shaft speed. Uses only the public API, as the pipelines do.

use geardyn::data::{load_kubo, load_munro, same_load, DataKind, StatedNoise};
use geardyn::error::WHOLE_FILE;
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
            // Line 0 (a missing file or table) is not printed: the file alone is named; a
            // problem of the whole file names no field.
            let at = match line {
                0 => format!("{file}: "),
                n => format!("{file}:{n}: "),
            };
            let place = match field {
                WHOLE_FILE => at,
                _ => format!("{at}field '{field}'"),
            };
            assert!(text.contains(&place), "{case}: {text}");
            assert!(!text.contains("'(file)'"), "{case}: {text}");
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
            r.replace("\"synthetic\"", "\"observed\""),
            16,
            "source.kind",
            "bad kind",
        ),
        (
            r.replace("\"synthetic\"", "\"measured\""),
            15,
            "source.instrument",
            "measured without instrument",
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
        // toml notices the open array on the next key's line; the slip is where it opens.
        (
            r.replace("2835.0, 1890.0, 945.0]", "2835.0, 1890.0, 945.0"),
            12,
            "ste.load_n",
            "array not closed",
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

/// A valid measured Munro-like rig.toml with a `[noise]` table; line numbers below refer to it.
const MEASURED_RIG: &str = r#"[rig]
name = "Four-square test rig"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1

[noise]
floor_um = 0.1
relative = 0.02
reading_um = 0.05

[source]
kind = "measured"
citation = "Gear lab test report TR-12 (2024)"
instrument = "two optical encoders, 5000 lines/rev, DTE from the angle difference"
date = "2024-05-17"
uncertainty = "+-0.1 um"
"#;

#[test]
fn new_csv_errors_are_located() {
    let h = "load_n,speed_rpm,dte_pp_um\n";
    let cases: Vec<(String, usize, &str, &str)> = vec![
        (
            format!("{h}3780,1000,1\n3780,1100,1,2\n"),
            3,
            "(row)",
            "more fields than the header",
        ),
        (
            "load_n;speed_rpm;dte_pp_um\n3780;1000;1\n".into(),
            1,
            "(header)",
            "semicolon separator",
        ),
        (
            "load_n\tspeed_rpm\tdte_pp_um\n3780\t1000\t1\n".into(),
            1,
            "(header)",
            "tab separator",
        ),
        (
            format!("{h}3780,1000,1\n2835,1000,1\n3780.0000001,1000,2\n"),
            4,
            "speed_rpm",
            "near-duplicate loads at one speed",
        ),
        (
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1,0.1\n3780,1100,1,0\n".into(),
            3,
            "dte_pp_sd_um",
            "zero stated sd",
        ),
        (
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1,-0.1\n".into(),
            2,
            "dte_pp_sd_um",
            "negative stated sd",
        ),
        (
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1,NaN\n".into(),
            2,
            "dte_pp_sd_um",
            "NaN stated sd",
        ),
        (
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1,0.1\n3780,1100,1,\n".into(),
            3,
            "dte_pp_sd_um",
            "stated sd missing on one row",
        ),
    ];
    for (csv, line, field, case) in &cases {
        munro_csv_error(csv, *line, field, case);
    }
    let d = dataset(Some(MUNRO_RIG), &[("c.csv", &cases[0].0)]);
    let msg = load_munro(d.path()).expect_err("extra field").to_string();
    assert!(msg.contains("row has 4 fields, header has 3"), "{msg}");
    let d = dataset(Some(MUNRO_RIG), &[("c.csv", &cases[1].0)]);
    let msg = load_munro(d.path()).expect_err("semicolons").to_string();
    assert!(msg.contains("comma-separated"), "{msg}");
    assert!(same_load(3780.0, 3780.0 + 1e-7));
}

#[test]
fn noise_and_measured_rig_errors_are_located() {
    let r = MEASURED_RIG;
    let without = |key: &str| -> String {
        r.lines()
            .filter(|l| !l.starts_with(key))
            .map(|l| format!("{l}\n"))
            .collect()
    };
    let cases: Vec<(String, usize, &str, &str)> = vec![
        (
            r.replace("floor_um = 0.1", "floor_um = -0.1"),
            12,
            "noise.floor_um",
            "negative floor",
        ),
        (
            r.replace("floor_um = 0.1", "floor_um = nan"),
            12,
            "noise.floor_um",
            "NaN floor",
        ),
        (
            r.replace("floor_um = 0.1", "floor_um = 5000.0"),
            12,
            "noise.floor_um",
            "implausible floor",
        ),
        (
            r.replace("floor_um = 0.1", "floor_um = 0.0"),
            12,
            "noise.floor_um",
            "zero floor",
        ),
        (
            r.replace("reading_um = 0.05", "reading_um = 0.2"),
            12,
            "noise.floor_um",
            "floor below the reading uncertainty",
        ),
        (
            r.replace("relative = 0.02", "relative = 1.5"),
            13,
            "noise.relative",
            "relative >= 1",
        ),
        (
            r.replace("relative = 0.02", "relative = -0.02"),
            13,
            "noise.relative",
            "negative relative",
        ),
        (
            r.replace("reading_um = 0.05", "reading_um = -0.05"),
            14,
            "noise.reading_um",
            "negative reading",
        ),
        (
            r.replace(
                "reading_um = 0.05",
                "reading_um = 0.05\ncorrelation_rpm = -50.0",
            ),
            15,
            "noise.correlation_rpm",
            "negative correlation length",
        ),
        (
            r.replace(
                "reading_um = 0.05",
                "reading_um = 0.05\ncorrelation_rpm = inf",
            ),
            15,
            "noise.correlation_rpm",
            "infinite correlation length",
        ),
        (
            r.replace("reading_um = 0.05", "reading_um = inf"),
            14,
            "noise.reading_um",
            "infinite reading",
        ),
        (
            r.replace("floor_um = 0.1", "floor = 0.1"),
            12,
            "noise.floor",
            "noise key without unit",
        ),
        (
            without("instrument"),
            16,
            "source.instrument",
            "measured without instrument",
        ),
        (without("date"), 16, "source.date", "measured without date"),
        (
            without("uncertainty"),
            16,
            "source.uncertainty",
            "measured without uncertainty",
        ),
        (
            r.replace("\"+-0.1 um\"", "\"\""),
            21,
            "source.uncertainty",
            "measured with empty uncertainty",
        ),
    ];
    for (rig, line, field, case) in &cases {
        munro_rig_error(rig, *line, field, case);
    }
}

#[test]
fn good_measured_set_with_stated_noise_loads() {
    let csv = "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.0,0.12\n3780,1100,1.2,0.13\n\
               2835,1000,2.0,0.2\n";
    // The noise stated per point, rig.toml giving only the reading uncertainty.
    let reading_only = MEASURED_RIG.replace("floor_um = 0.1\nrelative = 0.02\n", "");
    let d = dataset(Some(&reading_only), &[("c.csv", csv)]);
    let m = load_munro(d.path()).expect("good measured set with a noise column");
    assert_eq!(m.loads(), vec![3780.0, 2835.0]);
    let sds: Vec<Option<f64>> = m.curve(3780.0).iter().map(|p| p.sd_um).collect();
    assert_eq!(sds, vec![Some(0.12), Some(0.13)]);
    assert_eq!(m.curve(2835.0)[0].sd_um, Some(0.2));
    // The noise stated in rig.toml.
    let csv = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.0\n3780,1100,1.2\n2835,1000,2.0\n";
    let d = dataset(Some(MEASURED_RIG), &[("c.csv", csv)]);
    let m = load_munro(d.path()).expect("good measured set");
    assert_eq!(m.rig.source.kind, DataKind::Measured);
    assert_eq!(m.rig.source.kind.name(), "measured");
    assert_eq!(
        m.rig.source.instrument.as_deref(),
        Some("two optical encoders, 5000 lines/rev, DTE from the angle difference")
    );
    assert_eq!(m.rig.source.date.as_deref(), Some("2024-05-17"));
    assert_eq!(
        m.rig.noise,
        Some(StatedNoise {
            floor_um: Some(0.1),
            relative: Some(0.02),
            reading_um: Some(0.05),
            correlation_rpm: None,
        })
    );
    assert!(m.points.iter().all(|p| p.sd_um.is_none()));
    let banner = geardyn::report::data_kind_banner(&m.rig);
    assert!(
        banner.starts_with("MEASURED DATA: Gear lab test report TR-12 (2024) (two optical"),
        "{banner}"
    );
    assert!(!banner.to_lowercase().contains("synthetic"), "{banner}");
}

/// The noise is stated once: a `dte_pp_sd_um` column on one file of two is refused at the
/// first point of the other (the noise of its points would be another's), and a column beside a
/// `[noise]` model at the model's first key.
#[test]
fn noise_stated_on_some_files_or_twice_is_refused_where_it_is() {
    let with = "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.0,0.12\n3780,1100,1.2,0.13\n";
    let without = "# the other load\nload_n,speed_rpm,dte_pp_um\n2835,1000,2.0\n2835,1100,2.2\n";
    let reading_only = MEASURED_RIG.replace("floor_um = 0.1\nrelative = 0.02\n", "");
    let d = dataset(Some(&reading_only), &[("a.csv", with), ("b.csv", without)]);
    let msg = load_munro(d.path())
        .expect_err("a column on one file")
        .to_string();
    assert!(
        msg.contains("b.csv:3: field 'dte_pp_sd_um'") && msg.contains("given for 2 of 4 points"),
        "{msg}"
    );
    let d = dataset(Some(MEASURED_RIG), &[("a.csv", with)]);
    let msg = load_munro(d.path()).expect_err("stated twice").to_string();
    assert!(
        msg.contains("rig.toml:12: field 'noise.floor_um'") && msg.contains("stated twice"),
        "{msg}"
    );
    // A number written as a text is named as such, not as serde's Rust type.
    let quoted = MEASURED_RIG.replace("floor_um = 0.1", "floor_um = \"0.1\"");
    let d = dataset(Some(&quoted), &[]);
    let msg = geardyn::data::load_rig(&d.path().join("rig.toml"))
        .expect_err("quoted number")
        .to_string();
    assert!(
        msg.contains("rig.toml:12: field 'noise.floor_um'")
            && msg.contains("expected a number (unquoted)"),
        "{msg}"
    );
    let relative_only = MEASURED_RIG.replace("floor_um = 0.1\n", "");
    let d = dataset(Some(&relative_only), &[("a.csv", with)]);
    let msg = load_munro(d.path()).expect_err("stated twice").to_string();
    assert!(msg.contains("rig.toml:12: field 'noise.relative'"), "{msg}");
}

/// A 200k-row file with an error on its last row reports that row's line (loading is linear in
/// the number of rows; this once took minutes).
#[test]
fn error_on_the_last_of_200k_rows_is_located() {
    let rows = 200_000;
    let mut csv = String::with_capacity(rows * 24);
    csv.push_str("# long file\nload_n,speed_rpm,dte_pp_um\n");
    // Twenty curves of 10,000 speeds, the most a curve may have.
    for i in 0..rows - 1 {
        csv.push_str(&format!(
            "{},{},1.5\n",
            1000 + i / 10_000,
            1000 + i % 10_000
        ));
    }
    csv.push_str("1019,999999,abc\n");
    let last_line = 2 + rows;
    munro_csv_error(
        &csv,
        last_line,
        "dte_pp_um",
        "error on the last of 200k rows",
    );
}

/// The ```toml and ```csv examples of docs/data-format.md load: each rig.toml alone, each CSV
/// (Munro if its header has `load_n`, the profile table if `gear`, else Kubo) with the first
/// example rig.
#[test]
fn documented_examples_load() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/data-format.md"))
        .expect("docs/data-format.md");
    let blocks = |lang: &str| -> Vec<String> {
        let fence = format!("```{lang}\n");
        doc.split(&fence)
            .skip(1)
            .map(|b| b.split("```").next().unwrap_or_default().to_string())
            .collect()
    };
    let rigs = blocks("toml");
    let csvs = blocks("csv");
    assert_eq!((rigs.len(), csvs.len()), (2, 3), "examples in the doc");
    for rig in &rigs {
        let d = dataset(Some(rig), &[]);
        geardyn::data::load_rig(&d.path().join("rig.toml")).expect("documented rig.toml");
    }
    let kinds: Vec<DataKind> = rigs
        .iter()
        .map(|r| {
            let d = dataset(Some(r), &[]);
            geardyn::data::load_rig(&d.path().join("rig.toml"))
                .expect("rig")
                .source
                .kind
        })
        .collect();
    assert_eq!(kinds, vec![DataKind::Measured, DataKind::Digitized]);
    // "Numbers may be written as integers or floats".
    let integers = rigs[0].replace("= 3780.0\n", "= 3780\n");
    assert_ne!(integers, rigs[0]);
    let d = dataset(Some(&integers), &[]);
    let r = geardyn::data::load_rig(&d.path().join("rig.toml")).expect("integer load");
    assert_eq!(r.rig.design_load_n, 3780.0);
    for csv in &csvs {
        // The documented Munro CSV states its noise per point, so its rig is the digitized
        // example, which states only a reading uncertainty.
        let rig = if csv.starts_with("load_n") {
            &rigs[1]
        } else {
            &rigs[0]
        };
        let d = dataset(Some(rig), &[("c.csv", csv)]);
        if csv.starts_with("load_n") {
            let m = load_munro(d.path()).expect("documented Munro CSV");
            assert!(m.points.iter().all(|p| p.sd_um.is_some()));
        } else if csv.starts_with("gear,") {
            let t = geardyn::data::load_profile_table(&d.path().join("c.csv"))
                .expect("documented profile table");
            assert_eq!((t.pinion.len(), t.gear.len()), (3, 3));
        } else {
            load_kubo(d.path()).expect("documented Kubo CSV");
        }
    }
}

/// A design-load curve `validate munro` cannot fit is one located error before any fit: too
/// few points (the parameters and the noise model need six), flat (a zero reading included),
/// or so small that the column must be in another unit; loads in kN name the loads found.
#[test]
fn design_curves_that_cannot_be_fitted_are_located() {
    use geardyn::progress::NoProgress;
    use geardyn::validate::{validate_munro, MunroOptions};
    let curve = |values: &[f64]| {
        let mut csv = String::from("load_n,speed_rpm,dte_pp_um\n");
        for (k, v) in values.iter().enumerate() {
            csv.push_str(&format!("3780,{},{v}\n", 1000 + 100 * k));
        }
        csv
    };
    let run = |csv: &str, case: &str, field: &str, file: &str, needle: &str| {
        let rig = MUNRO_RIG.replace("[ste]\nload_n = [3780.0, 2835.0, 1890.0, 945.0]\namplitude_um = [0.5, 2.0, 3.0, 4.0]\n", "");
        let d = dataset(Some(&rig), &[("c.csv", csv)]);
        let data = load_munro(d.path()).expect(case);
        let r = validate_munro(&data, &MunroOptions::default(), &NoProgress);
        let text = r.as_ref().err().map(|e| e.to_string()).unwrap_or_default();
        assert!(text.contains(needle), "{case}: {text}");
        let line = if file == "rig.toml" { 8 } else { 0 };
        assert_located(r.map(|r| r.zeta), file, line, field, case);
    };
    let five = curve(&[1.0, 1.2, 1.5, 2.0, 1.1]);
    run(
        &five,
        "five points",
        "rig.design_load_n",
        "rig.toml",
        "at least 6 points",
    );
    run(&curve(&[1.0; 12]), "flat", "dte_pp_um", "c.csv", "flat");
    run(&curve(&[0.0; 12]), "zero", "dte_pp_um", "c.csv", "flat");
    let mm: Vec<f64> = (0..12).map(|k| 0.001 + 0.0005 * k as f64).collect();
    run(&curve(&mm), "in mm", "dte_pp_um", "c.csv", "in mm");
    let kn = "load_n,speed_rpm,dte_pp_um\n3.78,1000,1\n3.78,1100,1.2\n3.78,1200,1.5\n";
    run(kn, "kN", "rig.design_load_n", "rig.toml", "loads: 3.78 N");
}
