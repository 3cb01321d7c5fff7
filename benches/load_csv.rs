//! Criterion benchmark of loading a Munro data set of 10^6 rows (four curves of 250 000 speeds),
//! written with a rig.toml to a temporary folder: once valid (loaded), once with an error on its
//! last row (rejected, which must read the whole file). Loading is linear in the number of rows;
//! recounting lines from the start of the file for every row once made 10^5 rows take 85 s.

use criterion::{criterion_group, criterion_main, Criterion};
use geardyn::data::load_munro;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

/// Rows of the benchmark file.
const ROWS: usize = 1_000_000;

const RIG: &str = r#"[rig]
name = "benchmark rig"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1

[source]
kind = "synthetic"
citation = "benchmark input, not data"
generator = "benches/load_csv.rs"

[source.truth]
rows = 1000000
"#;

/// Write rig.toml and a 10^6-row `dte.csv` into `dir`; with `bad_last`, the last row's DTE is
/// not a number.
fn write_set(dir: &Path, bad_last: bool) {
    std::fs::write(dir.join("rig.toml"), RIG).expect("write rig.toml");
    let loads = [3780.0, 2835.0, 1890.0, 945.0];
    let per_load = ROWS / loads.len();
    let mut csv = String::with_capacity(ROWS * 28);
    csv.push_str("load_n,speed_rpm,dte_pp_um\n");
    for (k, load) in loads.iter().enumerate() {
        for i in 0..per_load {
            let last = k + 1 == loads.len() && i + 1 == per_load;
            let speed = 100.0 + 0.01 * i as f64;
            if last && bad_last {
                writeln!(csv, "{load},{speed:.2},n/a").expect("write to string");
            } else {
                let dte = 1.0 + 0.5 * (i as f64 * 1e-3).sin();
                writeln!(csv, "{load},{speed:.2},{dte:.5}").expect("write to string");
            }
        }
    }
    std::fs::write(dir.join("dte.csv"), csv).expect("write dte.csv");
}

fn load_million_rows(c: &mut Criterion) {
    let good = tempfile::tempdir().expect("temp dir");
    write_set(good.path(), false);
    let bad = tempfile::tempdir().expect("temp dir");
    write_set(bad.path(), true);
    let mut group = c.benchmark_group("load_csv");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function("munro 10^6 rows, valid", |b| {
        b.iter(|| {
            let m = load_munro(good.path()).expect("valid set");
            assert_eq!(m.points.len(), ROWS);
            m
        })
    });
    group.bench_function("munro 10^6 rows, error on the last row", |b| {
        b.iter(|| load_munro(bad.path()).expect_err("bad last row"))
    });
    group.finish();
}

criterion_group!(benches, load_million_rows);
criterion_main!(benches);
