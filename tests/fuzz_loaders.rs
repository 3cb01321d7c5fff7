//! Fuzzing of the data loaders (issue 22) with proptest: valid Munro and Kubo data sets and a
//! profile-modification table mutated byte by byte and token by token (numbers at the edges of
//! f64, separators, quotes, BOMs, TOML syntax, duplicated and swapped lines, random bytes), the
//! rig's mutations spread over the whole file or focused on one of its tables (`[rig]`, `[ste]`,
//! `[noise]`, `[geometry]`). Every input must load or fail with one located error
//! (`GearError::Data` naming rig.toml, the CSV or the profile table, a line within the file and a
//! field), never panic, and take well under a second. Beyond the loaders, what reads the tables
//! runs too: the rig's dimensional scales, the noise setting of `[noise]`, the gear pair of
//! `[geometry]` with its cross-checks, and the profile table on that pair with an STE waveform.
//!
//! The suite runs 256 inputs (a few seconds). The long mode runs for GEARDYN_FUZZ_SECS seconds
//! and prints the counts, panics and the slowest input:
//!
//!     GEARDYN_FUZZ_SECS=600 cargo test --release --test fuzz_loaders -- --ignored --nocapture

use geardyn::data::{
    load_kubo, load_munro, load_profile_table, load_rig_with_geometry, locate_rig_key,
};
use geardyn::mesh::{GearPairGeometry, MeshModel, TipRelief};
use geardyn::GearError;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;
use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::time::{Duration, Instant};

const RIG: &str = r#"[rig]
name = "Munro-like test rig"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1
mesh_stiffness_n_per_um = 204.0
test_load_n = 1500.0

[ste]
load_n = [3780.0, 1890.0]
amplitude_um = [0.5, 2.5]

[noise]
floor_um = 0.1
relative = 0.02

[geometry]
pinion_bore_diameter_mm = 50.0
gear_bore_diameter_mm = 50.0

[source]
kind = "measured"
citation = "Gear lab test report TR-12 (2024)"
instrument = "two optical encoders"
date = 2024-05-17
uncertainty = "+-0.1 um"
"#;

const MUNRO: &str = "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n# design load\n3780,1000,0.67,0.05\n\
3780,1050,0.65,0.05\n3780,1100,0.70,0.05\n1890,1000,2.31,0.08\n1890,1050,2.52,0.08\n";
/// Munro's gears (base diameter 190.95 mm, contact from 194.74 to 215.9 mm): a long tip relief.
const PROFILE: &str = "gear,diameter_mm,relief_um\npinion,194.0,0.0\npinion,205.4,0.0\n\
pinion,215.9,20.0\ngear,194.0,0.0\ngear,205.4,0.0\ngear,215.9,20.0\n";
const KUBO: &str =
    "mesh_freq_hz,dynamic_factor_min,dynamic_factor_max\n500,1.00,1.05\n1000,0.90,1.30\n";

/// Tokens spliced into the text: edge numbers, separators, quoting and TOML syntax.
const TOKENS: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "1e309",
    "-0",
    "0",
    "1e-320",
    "4294967295",
    "18446744073709551616",
    "99999999999999999999999999999999999999999999999999",
    "0x10",
    "1_000",
    "+5",
    ".",
    "-",
    "e",
    ",",
    ";",
    "\t",
    "\r",
    "\r\n",
    "\n",
    "\"",
    "'",
    "#",
    "\u{feff}",
    "[",
    "]",
    "[[",
    "=",
    "{",
    "}",
    "[rig]",
    "[source]",
    "[ste]",
    "[noise]",
    "[geometry]",
    "load_n",
    "speed_rpm",
    "mesh_freq_hz",
    "dte_pp_um",
    "\u{0}",
    "\u{e9}",
    "\u{1F600}",
    "\"\"\"",
    "true",
    "2024-05-17",
    ",,,",
    "  ",
    "1e-300",
    "1e-9",
    "0.001",
    "1e6",
    "-1",
    "1000",
    "pinion",
    "gear",
    "diameter_mm",
    "relief_um",
    "floor_um = ",
    "relative = ",
    "reading_um = ",
    "correlation_rpm = ",
    "amplitude_um = [",
    "load_n = [",
    "centre_distance_mm = ",
    "root_fillet_coefficient = ",
    "pinion_tip_diameter_mm = ",
];

/// The part of the rig file the rig's mutations act on.
#[derive(Clone, Copy, Debug)]
enum Focus {
    Whole,
    Table(&'static str),
}

fn focus() -> impl Strategy<Value = Focus> {
    prop_oneof![
        2 => Just(Focus::Whole),
        1 => Just(Focus::Table("[rig]")),
        1 => Just(Focus::Table("[ste]")),
        1 => Just(Focus::Table("[noise]")),
        1 => Just(Focus::Table("[geometry]")),
    ]
}

/// `muts` applied to the focused table of `text` alone (from its header to the next table).
fn apply_in(text: &str, focus: Focus, muts: &[Mutation]) -> Vec<u8> {
    let Focus::Table(name) = focus else {
        return apply(text.as_bytes(), muts);
    };
    let start = text.find(name).expect("the table is in the rig");
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |i| start + 2 + i);
    let mut out = text.as_bytes()[..start].to_vec();
    out.extend(apply(&text.as_bytes()[start..end], muts));
    out.extend_from_slice(&text.as_bytes()[end..]);
    out
}

#[derive(Clone, Debug)]
enum Mutation {
    /// Insert a token at a relative position (0..1000 of the length).
    Token(u16, usize),
    /// Insert raw bytes.
    Bytes(u16, Vec<u8>),
    /// Delete up to `n` bytes.
    Delete(u16, u8),
    /// Overwrite one byte.
    Flip(u16, u8),
    /// Duplicate one line.
    DupLine(u16),
    /// Swap two lines.
    SwapLines(u16, u16),
    /// Replace a number by a token.
    Number(u16, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let pos = 0u16..1000;
    prop_oneof![
        3 => (pos.clone(), 0..TOKENS.len()).prop_map(|(p, t)| Mutation::Token(p, t)),
        1 => (pos.clone(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(p, b)| Mutation::Bytes(p, b)),
        2 => (pos.clone(), 1u8..40).prop_map(|(p, n)| Mutation::Delete(p, n)),
        1 => (pos.clone(), any::<u8>()).prop_map(|(p, b)| Mutation::Flip(p, b)),
        1 => pos.clone().prop_map(Mutation::DupLine),
        1 => (pos.clone(), pos.clone()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        3 => (pos, 0..TOKENS.len()).prop_map(|(p, t)| Mutation::Number(p, t)),
    ]
}

fn at(len: usize, p: u16) -> usize {
    len * p as usize / 1000
}

fn apply(text: &[u8], muts: &[Mutation]) -> Vec<u8> {
    let mut t = text.to_vec();
    for m in muts {
        let n = t.len();
        match m {
            Mutation::Token(p, k) => {
                let i = at(n, *p);
                t.splice(i..i, TOKENS[*k].bytes());
            }
            Mutation::Bytes(p, b) => {
                let i = at(n, *p);
                t.splice(i..i, b.iter().copied());
            }
            Mutation::Delete(p, k) => {
                let i = at(n, *p);
                let j = (i + *k as usize).min(n);
                t.drain(i..j);
            }
            Mutation::Flip(p, b) => {
                if n > 0 {
                    let i = at(n - 1, *p);
                    t[i] = *b;
                }
            }
            Mutation::DupLine(p) | Mutation::SwapLines(p, _) => {
                let mut lines: Vec<Vec<u8>> =
                    t.split(|&c| c == b'\n').map(<[u8]>::to_vec).collect();
                let i = at(lines.len().saturating_sub(1), *p);
                if let Mutation::SwapLines(_, q) = m {
                    let j = at(lines.len().saturating_sub(1), *q);
                    lines.swap(i, j);
                } else {
                    let l = lines[i].clone();
                    lines.insert(i, l);
                }
                t = lines.join(&b'\n');
            }
            Mutation::Number(p, k) => {
                // The first number at or after the position becomes the token.
                let mut i = at(n, *p);
                while i < n && !t[i].is_ascii_digit() {
                    i += 1;
                }
                let mut j = i;
                while j < n && (t[j].is_ascii_digit() || t[j] == b'.') {
                    j += 1;
                }
                t.splice(i..j, TOKENS[*k].bytes());
            }
        }
    }
    t
}

/// One fuzz input: which CSV, where the rig's mutations act, and the mutations of the rig, the
/// CSV and the profile table.
#[derive(Clone, Debug)]
struct Input {
    kubo: bool,
    focus: Focus,
    rig: Vec<Mutation>,
    csv: Vec<Mutation>,
    profile: Vec<Mutation>,
}

fn input() -> impl Strategy<Value = Input> {
    (
        any::<bool>(),
        focus(),
        prop::collection::vec(mutation(), 0..4),
        prop::collection::vec(mutation(), 0..6),
        prop::collection::vec(mutation(), 0..3),
    )
        .prop_map(|(kubo, focus, rig, csv, profile)| Input {
            kubo,
            focus,
            rig,
            csv,
            profile,
        })
}

/// The three files of an input: rig.toml, c.csv and the profile table.
fn files_of(inp: &Input) -> [Vec<u8>; 3] {
    [
        apply_in(RIG, inp.focus, &inp.rig),
        apply(if inp.kubo { KUBO } else { MUNRO }.as_bytes(), &inp.csv),
        apply(PROFILE.as_bytes(), &inp.profile),
    ]
}

/// Check that a loader's error is one located data error in `dir`'s files.
fn located<T>(r: &geardyn::Result<T>, dir: &Path, files: &[(&str, &[u8])]) -> Result<(), String> {
    let e = match r {
        Ok(_) => return Ok(()),
        Err(e) => e,
    };
    let text = e.to_string();
    match e {
        GearError::Data {
            file, line, field, ..
        } => {
            let name = file
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let body = files
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, b)| *b)
                .ok_or_else(|| format!("error names an unknown file: {text}"))?;
            if !file.starts_with(dir) {
                return Err(format!("error names a file outside the set: {text}"));
            }
            let lines = body.iter().filter(|&&c| c == b'\n').count() + 1;
            if *line > lines + 1 {
                return Err(format!("line {line} beyond the {lines} lines: {text}"));
            }
            // Line 0: a key left at its default (or the file as a whole), named without a line.
            let at = match line {
                0 => format!("{name}: field '{field}'"),
                n => format!("{name}:{n}"),
            };
            if field.is_empty() || !text.contains(&at) {
                return Err(format!("error without file:line or field: {text}"));
            }
            Ok(())
        }
        other => Err(format!("not a located data error: {other:?}")),
    }
}

/// Load one input with every loader, and run what reads the tables; the error (if any) of each
/// must be located.
fn check(inp: &Input) -> Result<(), String> {
    let [rig, csv, profile] = files_of(inp);
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = dir.path();
    let rig_path = d.join("rig.toml");
    // Beside the data set, not in it: the data loaders read every CSV of the folder.
    let table_path = d.join("profile").join("p.csv");
    std::fs::create_dir(d.join("profile")).map_err(|e| e.to_string())?;
    std::fs::write(&rig_path, &rig).map_err(|e| e.to_string())?;
    std::fs::write(d.join("c.csv"), &csv).map_err(|e| e.to_string())?;
    std::fs::write(&table_path, &profile).map_err(|e| e.to_string())?;
    let files: [(&str, &[u8]); 3] = [("rig.toml", &rig), ("c.csv", &csv), ("p.csv", &profile)];
    if let Ok(data) = load_munro(d) {
        located(&geardyn::validate::noise_setting(&data), d, &files)?;
    }
    located(&load_munro(d), d, &files)?;
    located(&load_kubo(d), d, &files)?;
    located(&load_rig_with_geometry(&rig_path), d, &files)?;
    let table = load_profile_table(&table_path);
    located(&table, d, &files)?;
    let Ok((rig_file, geometry)) = load_rig_with_geometry(&rig_path) else {
        return Ok(());
    };
    located(&rig_file.rig.dimensional(), d, &files)?;
    let in_rig = |e: GearError| locate_rig_key(&rig_path, e);
    let pair = GearPairGeometry::from_rig(&rig_file.rig, &geometry).map_err(in_rig);
    located(&pair, d, &files)?;
    if let (Ok(pair), Ok(table)) = (pair, table) {
        let model = MeshModel::with_profile(pair, &table).map_err(in_rig);
        located(&model, d, &files)?;
        if let Ok(model) = model {
            let waveform = model
                .waveform(rig_file.rig.design_load_n, &TipRelief::none(), 64)
                .map_err(in_rig);
            located(&waveform, d, &files)?;
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// No panic, every error located, every input under a second.
    #[test]
    fn loaders_never_panic_and_locate_every_error(inp in input()) {
        let t = Instant::now();
        let r = check(&inp);
        prop_assert!(r.is_ok(), "{:?}", r);
        prop_assert!(t.elapsed() < Duration::from_secs(1), "took {:?}", t.elapsed());
    }
}

/// The long run: GEARDYN_FUZZ_SECS seconds of inputs (default 600), counting panics, unlocated
/// errors and the slowest input.
#[test]
#[ignore = "long fuzz run: GEARDYN_FUZZ_SECS=600 cargo test --release --test fuzz_loaders -- --ignored --nocapture"]
fn long_fuzz_run() {
    let secs: u64 = std::env::var("GEARDYN_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let mut runner = TestRunner::deterministic();
    let strategy = input();
    let start = Instant::now();
    let (mut runs, mut panics, mut unlocated, mut slow) = (0u64, 0u64, 0u64, 0u64);
    let mut max = (Duration::ZERO, 0usize);
    // The first input of each kind of problem (panic, or the error's first words), up to five.
    let mut problems: Vec<(String, String)> = Vec::new();
    let mut note = |kind: String, what: String| {
        if problems.len() < 5 && !problems.iter().any(|(k, _)| *k == kind) {
            problems.push((kind, what));
        }
    };
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    while start.elapsed() < Duration::from_secs(secs) {
        let inp = strategy
            .new_tree(&mut runner)
            .expect("generate an input")
            .current();
        let size: usize = files_of(&inp).iter().map(Vec::len).sum();
        let t = Instant::now();
        let r = std::panic::catch_unwind(AssertUnwindSafe(|| check(&inp)));
        let dt = t.elapsed();
        runs += 1;
        if dt > max.0 {
            max = (dt, size);
        }
        if dt > Duration::from_secs(20) {
            slow += 1;
        }
        match r {
            Err(_) => {
                panics += 1;
                note("panic".into(), format!("panic on {inp:?}"));
            }
            Ok(Err(e)) => {
                unlocated += 1;
                let kind: String = e.chars().take(60).collect();
                note(kind, format!("{e} on {inp:?}"));
            }
            Ok(Ok(())) => {}
        }
    }
    std::panic::set_hook(hook);
    println!(
        "fuzz: {runs} inputs in {:.0} s, {panics} panics, {unlocated} unlocated errors, {slow} over \
         20 s; slowest {:.2} ms ({} bytes)",
        start.elapsed().as_secs_f64(),
        max.0.as_secs_f64() * 1e3,
        max.1
    );
    assert!(
        panics == 0 && unlocated == 0 && slow == 0,
        "{}",
        problems
            .iter()
            .map(|(_, w)| w.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}
