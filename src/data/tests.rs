//! Unit tests of the data loaders: rig.toml and CSV parsing on good and nasty inputs.

use super::*;
use crate::error::{GearError, WHOLE_FILE};
use std::path::{Path, PathBuf};

/// A valid synthetic rig.toml (Munro-like).
pub(super) const RIG: &str = r#"[rig]
name = "Munro-like"
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
citation = "imitates Munro (1962) via Kahraman & Singh (1990) Figs. 19-22"
generator = "geardyn synth 0.1.0"

[source.truth]
zeta = 0.0175
omega_n_hz = 1600.0
"#;

/// Write `files` (name, contents) into a fresh temporary folder.
fn dataset(files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, body) in files {
        std::fs::write(dir.path().join(name), body).unwrap();
    }
    dir
}

/// (file name, line, field) of a data error, or a panic with what came instead.
fn located<T: std::fmt::Debug>(r: crate::Result<T>) -> (String, usize, String, String) {
    match r {
        Err(GearError::Data {
            file,
            line,
            field,
            message,
        }) => (
            file.file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default(),
            line,
            field,
            message,
        ),
        other => panic!("expected a data error, got {other:?}"),
    }
}

/// The rig error of `text` as (line, field, message).
fn rig_error(text: &str) -> (usize, String, String) {
    let d = dataset(&[("rig.toml", text.as_bytes())]);
    let (f, line, field, msg) = located(load_rig(&d.path().join("rig.toml")));
    assert_eq!(f, "rig.toml");
    (line, field, msg)
}

#[test]
fn good_rig_loads() {
    let d = dataset(&[("rig.toml", RIG.as_bytes())]);
    let r = load_rig(&d.path().join("rig.toml")).unwrap();
    assert_eq!(r.rig.pinion_teeth, 32);
    assert_eq!(r.source.kind, DataKind::Synthetic);
    assert_eq!(
        r.ste.as_ref().and_then(|s| s.amplitude_at(2835.0)),
        Some(2.0)
    );
    assert_eq!(r.rig.test_load_or_design_n(), 3780.0);
    let truth = r.source.truth.as_ref().unwrap();
    assert_eq!(truth.get("zeta").and_then(|v| v.as_float()), Some(0.0175));
}

#[test]
fn write_then_load_round_trips() {
    let d = dataset(&[("rig.toml", RIG.as_bytes())]);
    let r = load_rig(&d.path().join("rig.toml")).unwrap();
    let out = d.path().join("copy.toml");
    write_rig(&out, &r).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.contains("[source.truth]"), "{written}");
    assert!(!written.contains("mesh_stiffness"), "{written}");
    assert!(!d.path().join("copy.toml.partial").exists());
    assert_eq!(load_rig(&out).unwrap(), r);
    let mut bad = r.clone();
    bad.source.generator = None;
    let (_, _, field, _) = located(write_rig(&d.path().join("bad.toml"), &bad));
    assert_eq!(field, "source.generator");
    assert!(!d.path().join("bad.toml").exists());
}

#[test]
fn key_without_unit_is_unknown_field() {
    let (line, field, msg) = rig_error(&RIG.replace("backlash_mm = 0.1", "backlash = 0.1"));
    assert_eq!((line, field.as_str()), (9, "rig.backlash"), "{msg}");
    assert!(msg.contains("unknown field"), "{msg}");
    let (line, field, _) = rig_error(&RIG.replace("design_load_n", "design_load_N"));
    assert_eq!((line, field.as_str()), (8, "rig.design_load_N"));
}

#[test]
fn missing_and_mistyped_keys() {
    let (line, field, msg) = rig_error(&RIG.replace("module_mm = 6.35\n", ""));
    assert_eq!(field, "rig.module_mm", "{msg}");
    assert!(line <= 1, "line {line}");
    let (line, field, msg) = rig_error(&RIG.replace("6.35", "\"six\""));
    assert_eq!((line, field.as_str()), (5, "rig.module_mm"), "{msg}");
    let (line, field, _) = rig_error(&RIG.replace("6.35", "nan"));
    assert_eq!((line, field.as_str()), (5, "rig.module_mm"));
    let (line, field, _) = rig_error(&RIG.replace("pinion_teeth = 32", "pinion_teeth = -3"));
    assert_eq!((line, field.as_str()), (3, "rig.pinion_teeth"));
}

#[test]
fn source_problems() {
    let no_source = RIG.split("[source]").next().unwrap_or_default().to_string();
    let (_, field, msg) = rig_error(&no_source);
    assert_eq!(field, "source", "{msg}");
    assert!(msg.contains("[source]"), "{msg}");
    let (line, field, msg) = rig_error(&RIG.replace("\"synthetic\"", "\"observed\""));
    assert_eq!((line, field.as_str()), (16, "source.kind"), "{msg}");
    let (line, field, msg) = rig_error(&RIG.replace("\"synthetic\"", "\"measured\""));
    assert_eq!((line, field.as_str()), (15, "source.instrument"), "{msg}");
    let (_, field, _) = rig_error(&RIG.replace("generator = \"geardyn synth 0.1.0\"\n", ""));
    assert_eq!(field, "source.generator");
    let no_truth = RIG
        .split("[source.truth]")
        .next()
        .unwrap_or_default()
        .to_string();
    let (line, field, _) = rig_error(&no_truth);
    assert_eq!((line, field.as_str()), (15, "source.truth"));
    let digitized = RIG.replace("\"synthetic\"", "\"digitized\"");
    let (_, field, _) = rig_error(&digitized);
    assert_eq!(field, "source.method");
    let with_method =
        digitized.replace("generator =", "method = \"WebPlotDigitizer\"\ngenerator =");
    let (_, field, _) = rig_error(&with_method);
    assert_eq!(field, "source.uncertainty");
    let (line, field, _) =
        rig_error(&RIG.replace("citation = \"imitates", "citation = \" \"\nx=\""));
    assert!(
        field == "source.x" || field == "source.citation",
        "{field} {line}"
    );
}

#[test]
fn rig_range_checks_are_located() {
    let cases = [
        (
            "pinion_teeth = 32",
            "pinion_teeth = 4",
            3,
            "rig.pinion_teeth",
        ),
        (
            "backlash_mm = 0.1",
            "backlash_mm = 0.0",
            9,
            "rig.backlash_mm",
        ),
        (
            "backlash_mm = 0.1",
            "backlash_mm = -0.1",
            9,
            "rig.backlash_mm",
        ),
        ("module_mm = 6.35", "module_mm = 0.0", 5, "rig.module_mm"),
        ("= 20.0", "= 40.0", 6, "rig.pressure_angle_deg"),
        (
            "backlash_mm = 0.1",
            "backlash_mm = inf",
            9,
            "rig.backlash_mm",
        ),
        (
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nzeta = 1.2",
            10,
            "rig.zeta",
        ),
        (
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nzeta = 0.0",
            10,
            "rig.zeta",
        ),
    ];
    for (from, to, line, field) in cases {
        let (l, f, msg) = rig_error(&RIG.replace(from, to));
        assert_eq!((l, f.as_str()), (line, field), "{to}: {msg}");
    }
}

#[test]
fn ste_table_checks() {
    let (line, field, msg) = rig_error(&RIG.replace("[0.5, 2.0, 3.0, 4.0]", "[0.5, 2.0, 3.0]"));
    assert_eq!((line, field.as_str()), (13, "ste.amplitude_um"), "{msg}");
    let (line, field, _) = rig_error(&RIG.replace("[0.5, 2.0", "[0.0, 2.0"));
    assert_eq!((line, field.as_str()), (13, "ste.amplitude_um"));
    let (line, field, _) = rig_error(&RIG.replace("2835.0, 1890.0", "-2835.0, 1890.0"));
    assert_eq!((line, field.as_str()), (12, "ste.load_n"));
    let (_, field, _) = rig_error(&RIG.replace("2835.0, 1890.0", "3780.0, 1890.0"));
    assert_eq!(field, "ste.load_n");
}

#[test]
fn nasty_rig_files_do_not_panic() {
    let nasty: [&[u8]; 7] = [
        b"",
        b"\xff\xfe\x00\x01junk",
        b"[rig",
        b"[rig]\nname = \"a\"\n[rig]\n",
        b"\xef\xbb\xbf",
        b"rig = 3\nsource = []\n",
        b"[[rig]]\nname=1\n",
    ];
    for body in nasty {
        let d = dataset(&[("rig.toml", body)]);
        assert!(matches!(
            load_rig(&d.path().join("rig.toml")),
            Err(GearError::Data { .. })
        ));
    }
    let d = dataset(&[]);
    let (f, line, field, _) = located(load_rig(&d.path().join("rig.toml")));
    assert_eq!(
        (f.as_str(), line, field.as_str()),
        ("rig.toml", 0, WHOLE_FILE)
    );
}

#[test]
fn crlf_rig_loads() {
    let d = dataset(&[("rig.toml", RIG.replace('\n', "\r\n").as_bytes())]);
    assert!(load_rig(&d.path().join("rig.toml")).is_ok());
    let bad = RIG.replace("backlash_mm", "backlash").replace('\n', "\r\n");
    let (line, field, _) = rig_error(&bad);
    assert_eq!((line, field.as_str()), (9, "rig.backlash"));
}

/// A Munro data set folder with the good rig and the given CSV files.
fn munro_set(csvs: &[(&str, &str)]) -> tempfile::TempDir {
    let mut files: Vec<(&str, &[u8])> = vec![("rig.toml", RIG.as_bytes())];
    files.extend(csvs.iter().map(|(n, b)| (*n, b.as_bytes())));
    dataset(&files)
}

#[test]
fn munro_csv_variants_load() {
    let body = "\u{feff}load_n,speed_rpm,dte_pp_um,note\r\n# digitized by hand\r\n\
                3780,1000,1.5,a\r\n3780,1100,2.5,b\r\n\r\n2835,1000,3.0,c\r\n  \r\n,,,\r\n";
    let d = munro_set(&[
        ("b.csv", body),
        ("a.csv", "load_n,mesh_freq_hz,dte_pp_um\n945,800,9\n"),
    ]);
    let m = load_munro(d.path()).unwrap();
    assert_eq!(m.loads(), vec![3780.0, 2835.0, 945.0]);
    // files in name order: a.csv first; 800 Hz x 60 / 32 = 1500 rpm
    assert_eq!(m.points[0].speed_rpm, 1500.0);
    assert_eq!(m.points[0].line, 2);
    let c = m.curve(3780.0);
    assert_eq!(c.len(), 2);
    assert_eq!(
        (c[1].speed_rpm, c[1].dte_pp_um, c[1].line),
        (1100.0, 2.5, 4)
    );
    assert_eq!(m.curve(2835.0)[0].line, 6);
    assert!(m.curve(1.0).is_empty());
}

#[test]
fn nasty_csv_files_do_not_panic() {
    let nasty: [&str; 8] = [
        "",
        "\u{feff}",
        "\u{feff}load_n,speed_rpm,dte_pp_um\n",
        "load_n,speed_rpm,dte_pp_um\r\n",
        "load_n,speed_rpm,dte_pp_um\n1,2\n",
        "load_n,speed_rpm,dte_pp_um\n\"1,2,3\n",
        ",,,\n,,,\n",
        "load_n,load_n,speed_rpm,dte_pp_um\n1,1,2,3\n",
    ];
    for body in nasty {
        let d = munro_set(&[("c.csv", body)]);
        let (f, line, _, msg) = located(load_munro(d.path()));
        assert_eq!(f, "c.csv", "{body:?}: {msg}");
        assert!(line >= 1, "{body:?}: {msg}");
    }
    let d = dataset(&[("rig.toml", RIG.as_bytes()), ("x.csv", b"\x00\x9f\x92\x96")]);
    assert!(load_munro(d.path()).is_err());
}

#[test]
fn csv_only_header_reports_line_two() {
    let d = munro_set(&[("c.csv", "\u{feff}load_n,speed_rpm,dte_pp_um\r\n")]);
    let (_, line, field, _) = located(load_munro(d.path()));
    assert_eq!((line, field.as_str()), (2, "(rows)"));
}

/// A curve with more speeds than any steady-state measurement has is refused at the first
/// point too many, with its file and line: split over two files (the count is per curve, not
/// per file), 10,000 points at 3780 N load and the 10,001st is refused; another load's curve
/// of the same length is not.
#[test]
fn a_curve_of_more_than_ten_thousand_speeds_is_refused() {
    let curve = |load: u32, from: usize, to: usize| -> String {
        (from..to)
            .map(|k| format!("{load},{},1\n", 1000 + k))
            .collect()
    };
    let head = "load_n,speed_rpm,dte_pp_um\n";
    let a = format!("{head}{}{}", curve(3780, 0, 6000), curve(945, 0, 10_000));
    let ok = format!("{head}{}", curve(3780, 6000, 10_000));
    let d = munro_set(&[("a.csv", &a), ("b.csv", &ok)]);
    assert_eq!(load_munro(d.path()).unwrap().points.len(), 20_000);
    let over = format!("{head}{}", curve(3780, 6000, 10_001));
    let d = munro_set(&[("a.csv", &a), ("b.csv", &over)]);
    let (f, line, field, msg) = located(load_munro(d.path()));
    assert_eq!(
        (f.as_str(), line, field.as_str()),
        ("b.csv", 4002, "speed_rpm"),
        "{msg}"
    );
    assert!(msg.contains("more than 10000 speeds"), "{msg}");
}

#[test]
fn missing_values_and_duplicates() {
    let d = munro_set(&[("c.csv", "load_n,speed_rpm,dte_pp_um\n1,2,3\n1,3\n")]);
    let (_, line, field, msg) = located(load_munro(d.path()));
    assert_eq!((line, field.as_str()), (3, "dte_pp_um"), "{msg}");
    let d = munro_set(&[
        ("a.csv", "load_n,speed_rpm,dte_pp_um\n1,2,3\n"),
        ("b.csv", "load_n,speed_rpm,dte_pp_um\n2,2,3\n1,2,3\n"),
    ]);
    let (f, line, field, msg) = located(load_munro(d.path()));
    assert_eq!(
        (f.as_str(), line, field.as_str()),
        ("b.csv", 3, "speed_rpm"),
        "{msg}"
    );
    assert!(msg.contains("a.csv:2"), "{msg}");
}

#[test]
fn speed_and_mesh_frequency_must_agree() {
    let good = "load_n,speed_rpm,mesh_freq_hz,dte_pp_um\n1,1500,800,3\n";
    assert!(load_munro(munro_set(&[("c.csv", good)]).path()).is_ok());
    let bad = "load_n,speed_rpm,mesh_freq_hz,dte_pp_um\n1,1500,800,3\n1,1600,800,3\n";
    let (_, line, field, msg) = located(load_munro(munro_set(&[("c.csv", bad)]).path()));
    assert_eq!((line, field.as_str()), (3, "mesh_freq_hz"), "{msg}");
    assert!(
        msg.contains(
            "mesh_freq_hz 800 Hz is 1500 rpm with 32 pinion teeth, speed_rpm says 1600 rpm"
        ) && msg.contains("they agree for 30 teeth"),
        "{msg}"
    );
}

#[test]
fn empty_folder_and_paths() {
    let d = dataset(&[("rig.toml", RIG.as_bytes())]);
    let (_, line, field, _) = located(load_munro(d.path()));
    assert_eq!((line, field.as_str()), (0, WHOLE_FILE));
    let missing: PathBuf = Path::new("/definitely/not/here").to_path_buf();
    assert!(load_kubo(&missing).is_err());
}

/// Mutations of valid files (byte flips, truncations, insertions from a small alphabet of
/// troublesome characters) never panic and fail, if at all, with a located data error.
#[test]
fn mutated_inputs_never_panic() {
    let csv = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n3780,1100,2.5\n2835,1000,3.0\n";
    let alphabet = b"\n\r,\"#[]=.-+eE0 \xff\x00\xef\xbb\xbf";
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let d = tempfile::tempdir().unwrap();
    for case in 0..300 {
        let (base, is_rig) = if case % 2 == 0 {
            (RIG.as_bytes(), true)
        } else {
            (csv.as_bytes(), false)
        };
        let mut bytes = base.to_vec();
        for _ in 0..1 + next(4) {
            let at = next(bytes.len() + 1);
            match next(3) {
                0 => bytes.insert(at, alphabet[next(alphabet.len())]),
                1 if at < bytes.len() => bytes[at] = alphabet[next(alphabet.len())],
                _ => bytes.truncate(at),
            }
        }
        let (rig, curve) = if is_rig {
            (bytes.as_slice(), csv.as_bytes())
        } else {
            (RIG.as_bytes(), bytes.as_slice())
        };
        std::fs::write(d.path().join("rig.toml"), rig).unwrap();
        std::fs::write(d.path().join("c.csv"), curve).unwrap();
        match load_munro(d.path()) {
            Ok(_) | Err(GearError::Data { .. }) => {}
            Err(other) => panic!("case {case}: unexpected error kind {other:?}"),
        }
        assert!(matches!(load_kubo(d.path()), Err(GearError::Data { .. })));
    }
}

/// A valid measured rig.toml with a `[noise]` table; line numbers below refer to it.
const MEASURED_RIG: &str = r#"[rig]
name = "Four-square rig"
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
citation = "Test report TR-12, gear lab"
instrument = "optical encoders, 5000 lines"
date = 2024-05-17
uncertainty = "+-0.1 um"
"#;

#[test]
fn measured_rig_with_noise_loads_and_round_trips() {
    let d = dataset(&[("rig.toml", MEASURED_RIG.as_bytes())]);
    let r = load_rig(&d.path().join("rig.toml")).unwrap();
    assert_eq!(r.source.kind, DataKind::Measured);
    assert_eq!(r.source.date.as_deref(), Some("2024-05-17"));
    assert_eq!(
        r.noise,
        Some(StatedNoise {
            floor_um: Some(0.1),
            relative: Some(0.02),
            reading_um: Some(0.05),
            correlation_rpm: None,
        })
    );
    let out = d.path().join("copy.toml");
    write_rig(&out, &r).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.contains("[noise]"), "{written}");
    assert_eq!(load_rig(&out).unwrap(), r);
    // Without [noise] nothing is written for it.
    let mut plain = r.clone();
    plain.noise = None;
    write_rig(&out, &plain).unwrap();
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(!written.contains("noise"), "{written}");
    assert_eq!(load_rig(&out).unwrap(), plain);
    // A string date is as good as a TOML date; a number is not a date.
    let quoted = MEASURED_RIG.replace("2024-05-17", "\"May 2024\"");
    let d = dataset(&[("rig.toml", quoted.as_bytes())]);
    let r = load_rig(&d.path().join("rig.toml")).unwrap();
    assert_eq!(r.source.date.as_deref(), Some("May 2024"));
    let (line, field, msg) = rig_error(&MEASURED_RIG.replace("2024-05-17", "2024"));
    assert_eq!((line, field.as_str()), (20, "source.date"), "{msg}");
}

#[test]
fn measured_rig_must_state_instrument_date_uncertainty() {
    for (key, line) in [("instrument", 19), ("date", 20), ("uncertainty", 21)] {
        let text: String = MEASURED_RIG
            .lines()
            .filter(|l| !l.starts_with(key))
            .map(|l| format!("{l}\n"))
            .collect();
        let (l, field, msg) = rig_error(&text);
        assert_eq!(
            (l, field.as_str()),
            (16, format!("source.{key}").as_str()),
            "{msg}"
        );
        assert!(msg.contains("measured data must state"), "{msg}");
        let blank = MEASURED_RIG
            .lines()
            .map(|l| {
                if l.starts_with(key) {
                    format!("{key} = \"  \"\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect::<String>();
        let (l, field, msg) = rig_error(&blank);
        assert_eq!(
            (l, field.as_str()),
            (line, format!("source.{key}").as_str()),
            "{msg}"
        );
    }
}

#[test]
fn noise_table_checks() {
    let cases = [
        ("floor_um = 0.1", "floor_um = -0.1", 12, "noise.floor_um"),
        ("floor_um = 0.1", "floor_um = nan", 12, "noise.floor_um"),
        ("floor_um = 0.1", "floor_um = 1000.0", 12, "noise.floor_um"),
        (
            "floor_um = 0.1",
            "floor_um = \"small\"",
            12,
            "noise.floor_um",
        ),
        ("relative = 0.02", "relative = 1.0", 13, "noise.relative"),
        ("relative = 0.02", "relative = -0.01", 13, "noise.relative"),
        ("relative = 0.02", "relative = inf", 13, "noise.relative"),
        (
            "reading_um = 0.05",
            "reading_um = -1e-3",
            14,
            "noise.reading_um",
        ),
        (
            "reading_um = 0.05",
            "reading_um = inf",
            14,
            "noise.reading_um",
        ),
        ("reading_um = 0.05", "reading = 0.05", 14, "noise.reading"),
    ];
    for (from, to, line, field) in cases {
        let (l, f, msg) = rig_error(&MEASURED_RIG.replace(from, to));
        assert_eq!((l, f.as_str()), (line, field), "{to}: {msg}");
    }
    // A zero relative part and an empty table are allowed (nothing stated is estimated); a
    // zero floor is not (a stated noise needs one), nor one below the reading uncertainty.
    let zero = MEASURED_RIG.replace("relative = 0.02", "relative = 0.0");
    let d = dataset(&[("rig.toml", zero.as_bytes())]);
    assert!(load_rig(&d.path().join("rig.toml")).is_ok());
    for to in ["floor_um = 0.0", "floor_um = 0.04"] {
        let (l, f, msg) = rig_error(&MEASURED_RIG.replace("floor_um = 0.1", to));
        assert_eq!((l, f.as_str()), (12, "noise.floor_um"), "{to}: {msg}");
    }
    let empty = MEASURED_RIG.replace("floor_um = 0.1\nrelative = 0.02\nreading_um = 0.05\n", "");
    let d = dataset(&[("rig.toml", empty.as_bytes())]);
    let r = load_rig(&d.path().join("rig.toml")).unwrap();
    assert_eq!(r.noise.map(|n| n.floor_um), Some(None));
}

#[test]
fn stated_point_sd_column() {
    let body = "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.5,0.1\n3780,1100,2.5,0.2\n";
    let m = load_munro(munro_set(&[("c.csv", body)]).path()).unwrap();
    let sds: Vec<Option<f64>> = m.points.iter().map(|p| p.sd_um).collect();
    assert_eq!(sds, vec![Some(0.1), Some(0.2)]);
    let plain = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n";
    let m = load_munro(munro_set(&[("c.csv", plain)]).path()).unwrap();
    assert_eq!(m.points[0].sd_um, None);
    // Points serialized before the column existed still read.
    let json = r#"{"load_n":1.0,"speed_rpm":2.0,"dte_pp_um":3.0,"line":2,"file":"c.csv"}"#;
    let p: MunroPoint = serde_json::from_str(json).unwrap();
    assert_eq!(p.sd_um, None);
    for bad in ["0", "-0.1", "nan", "inf", "", "x"] {
        let body = format!(
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.5,0.1\n3780,1100,2.5,{bad}\n"
        );
        let (_, line, field, msg) = located(load_munro(munro_set(&[("c.csv", &body)]).path()));
        assert_eq!(
            (line, field.as_str()),
            (3, "dte_pp_sd_um"),
            "{bad:?}: {msg}"
        );
    }
}

#[test]
fn row_with_more_fields_than_header() {
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n3780,1100,2,5\n";
    let (f, line, field, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert_eq!(
        (f.as_str(), line, field.as_str()),
        ("c.csv", 3, "(row)"),
        "{msg}"
    );
    assert!(msg.contains("row has 4 fields, header has 3"), "{msg}");
    // The same on the first data row, after comments and CRLF, and in a Kubo file.
    let body = "# note\r\nload_n,speed_rpm,dte_pp_um\r\n# more\r\n\r\n3780,1000,1.5,1\r\n";
    let (_, line, field, _) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert_eq!((line, field.as_str()), (5, "(row)"));
    // A row of empty cells is blank, however many.
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n,,,,,\n";
    assert!(load_munro(munro_set(&[("c.csv", body)]).path()).is_ok());
}

#[test]
fn semicolon_and_tab_headers_get_a_hint() {
    for (sep, body) in [
        ("';'", "load_n;speed_rpm;dte_pp_um\n3780;1000;1,5\n"),
        (
            "tabs",
            "# exported\nload_n\tspeed_rpm\tdte_pp_um\n3780\t1000\t1.5\n",
        ),
    ] {
        let (f, line, field, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
        let header_line = if sep == "tabs" { 2 } else { 1 };
        assert_eq!(
            (f.as_str(), line, field.as_str()),
            ("c.csv", header_line, "(header)")
        );
        assert!(
            msg.contains(sep) && msg.contains("comma-separated"),
            "{msg}"
        );
    }
    // A header with commas is read as CSV even if a name holds a ';'.
    let body = "load_n,speed_rpm,dte_pp_um,note;x\n3780,1000,1.5,a\n";
    assert!(load_munro(munro_set(&[("c.csv", body)]).path()).is_ok());
}

#[test]
fn near_equal_loads_are_one_curve_for_the_duplicate_check() {
    // 1e-7 N apart: same_load groups them, so the second point repeats the first's speed.
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n3780.0000001,1000,1.6\n";
    assert!(same_load(3780.0, 3780.0 + 1e-7));
    let (_, line, field, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert_eq!((line, field.as_str()), (3, "speed_rpm"), "{msg}");
    assert!(
        msg.contains("duplicate speed") && msg.contains("line 2"),
        "{msg}"
    );
    // At different speeds they form one curve, with one load and the order checked across it.
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n3780.0000001,1100,1.6\n";
    let m = load_munro(munro_set(&[("c.csv", body)]).path()).unwrap();
    assert_eq!(m.loads().len(), 1);
    assert_eq!(m.curve(m.loads()[0]).len(), 2);
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1.5\n3780.0000001,900,1.6\n";
    let (_, line, _, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert!(msg.contains("not sorted") && line == 3, "{msg}");
    // A load the same as two curves' loads would make the grouping ambiguous.
    let body =
        "load_n,speed_rpm,dte_pp_um\n1000,1000,1\n1000.0000015,1000,1\n1000.00000075,1100,1\n";
    let (_, line, field, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert_eq!((line, field.as_str()), (4, "load_n"), "{msg}");
}

/// Line numbers stay right deep into a long file with comments, blank lines and CRLF (they are
/// kept by a running count, not recounted per row).
#[test]
fn line_numbers_in_a_long_file() {
    let mut body = String::from("# long\r\nload_n,speed_rpm,dte_pp_um\r\n");
    let mut line = 2;
    for i in 0..5000 {
        body.push_str(&format!("3780,{},1.0\r\n", 1000 + i));
        line += 1;
        if i % 7 == 0 {
            body.push_str("# c\r\n\r\n  \r\n");
            line += 3;
        }
    }
    body.push_str("3780,99999,-1\r\n");
    line += 1;
    let (_, l, field, _) = located(load_munro(munro_set(&[("c.csv", &body)]).path()));
    assert_eq!((l, field.as_str()), (line, "dte_pp_um"));
}

#[test]
fn duplicates_within_and_across_files() {
    // A repeated speed further back in the same curve is a duplicate, not just out of order.
    let body = "load_n,speed_rpm,dte_pp_um\n3780,1000,1\n3780,1100,1\n3780,1200,1\n3780,1100,2\n";
    let (_, line, field, msg) = located(load_munro(munro_set(&[("c.csv", body)]).path()));
    assert_eq!((line, field.as_str()), (5, "speed_rpm"), "{msg}");
    assert!(
        msg.contains("duplicate speed 1100") && msg.contains("line 3"),
        "{msg}"
    );
    // Across three files: the last repeats a point of the first; curves and files interleave.
    let d = munro_set(&[
        (
            "a.csv",
            "load_n,speed_rpm,dte_pp_um\n3780,1000,1\n2835,1000,1\n",
        ),
        (
            "b.csv",
            "load_n,speed_rpm,dte_pp_um\n3780,900,1\n2835,1100,1\n",
        ),
        (
            "c.csv",
            "load_n,speed_rpm,dte_pp_um\n3780,800,1\n2835.0000001,1000,1\n",
        ),
    ]);
    let (f, line, field, msg) = located(load_munro(d.path()));
    assert_eq!(
        (f.as_str(), line, field.as_str()),
        ("c.csv", 3, "speed_rpm"),
        "{msg}"
    );
    assert!(
        msg.contains("a.csv:3") && msg.contains("load 2835 N"),
        "{msg}"
    );
    // Kubo: one curve, duplicates across files too.
    let k = "speed_rpm,dynamic_factor_min,dynamic_factor_max\n";
    let d = dataset(&[
        ("rig.toml", RIG.as_bytes()),
        ("a.csv", format!("{k}1000,1,1.1\n").as_bytes()),
        ("b.csv", format!("{k}900,1,1.1\n1000,1,1.2\n").as_bytes()),
    ]);
    let (f, line, _, msg) = located(load_kubo(d.path()));
    assert_eq!((f.as_str(), line), ("b.csv", 3), "{msg}");
}
