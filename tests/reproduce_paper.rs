//! `geardyn reproduce --quick`: every figure counterpart is written, every claim row carries a
//! verdict computed in the run, and a second run with the same options writes identical bytes.
//! The quick mode uses coarse grids (9x9 ICs, Omega step 0.05), so the verdicts asserted here are
//! the ones that do not depend on resolution; the full run's table is in reports/paper.

use geardyn::reproduce::figure_index;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn files(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("readable folder") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(root).expect("inside root").to_path_buf();
                out.insert(rel, std::fs::read(&p).expect("readable file"));
            }
        }
    }
    out
}

/// Start the quick reproduction; `threads` sets rayon's thread count (outputs must not depend
/// on it).
fn start_quick(out: &Path, threads: Option<&str>) -> Child {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_geardyn"));
    cmd.args(["reproduce", "--quick", "--out"])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    cmd.spawn().expect("the geardyn binary runs")
}

fn claim<'a>(claims: &'a [Value], id: &str) -> &'a Value {
    claims
        .iter()
        .find(|c| c["id"] == id)
        .unwrap_or_else(|| panic!("claim {id} missing"))
}

#[test]
fn quick_reproduction_is_complete_deterministic_and_honest() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    // The second run on one thread: the same bytes whatever the parallel schedule. The two run
    // at once, so the one-thread run does not leave a core idle for its whole length.
    let runs = [start_quick(&a, None), start_quick(&b, Some("1"))];
    // Both are waited for before either is checked: a failed first run must not leave the
    // second running on. The second's stderr (a few hundred bytes) fits in its pipe's buffer
    // while the first is waited for.
    let outputs = runs.map(|run| run.wait_with_output().expect("the geardyn binary runs"));
    for o in &outputs {
        assert!(
            o.status.success(),
            "reproduce failed: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }

    // Bit-for-bit identical outputs.
    let (fa, fb) = (files(&a), files(&b));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "same file list"
    );
    for (k, v) in &fa {
        assert!(v == &fb[k], "{} differs between two runs", k.display());
    }

    // Every figure of the paper (but the schematic Fig. 1) has a PNG and an SVG.
    let index = figure_index();
    let figs: Vec<u32> = index.iter().filter_map(|e| e.figure.parse().ok()).collect();
    assert_eq!(figs, (1..=29).collect::<Vec<u32>>(), "one entry per figure");
    for e in &index {
        assert!(
            e.figure == "1" || !e.files.is_empty(),
            "Fig. {} has no file",
            e.figure
        );
        for f in &e.files {
            for ext in ["png", "svg"] {
                let p = a.join(format!("{f}.{ext}"));
                let len = std::fs::metadata(&p)
                    .unwrap_or_else(|_| panic!("missing {}", p.display()))
                    .len();
                assert!(len > 1000, "{} is nearly empty", p.display());
            }
        }
    }
    for name in ["REPRODUCTION.md", "index.html", "claims.csv", "claims.json"] {
        assert!(a.join(name).is_file(), "{name} missing");
    }

    let doc: Value =
        serde_json::from_slice(&fa[Path::new("claims.json")]).expect("claims.json parses");
    let claims = doc["claims"].as_array().expect("claims array").clone();
    assert!(claims.len() >= 45, "{} claims", claims.len());
    let counts = doc["verdict_counts"].as_object().expect("counts");
    let total: u64 = counts.values().filter_map(Value::as_u64).sum();
    assert_eq!(total as usize, claims.len());
    for c in &claims {
        for key in ["id", "section", "figure", "paper", "geardyn", "explanation"] {
            assert!(
                c[key].as_str().is_some_and(|s| !s.is_empty()),
                "{} has no {key}",
                c["id"]
            );
        }
    }
    let verdict = |id: &str| {
        claim(&claims, id)["verdict"]
            .as_str()
            .unwrap_or("")
            .to_string()
    };

    // Sec. 3 claims that hold even on the coarse grid.
    for id in [
        "S3-01", "S3-02", "S3-03", "S3-04", "S3-08", "S3-12", "S3-15",
    ] {
        assert_eq!(verdict(id), "agree", "{id}: {}", claim(&claims, id));
    }
    // Omega 0.8: the paper's period-2 dominates; geardyn's extra orbits are confirmed by DOP853.
    assert_eq!(
        verdict("S3-05"),
        "more-than-paper",
        "{}",
        claim(&claims, "S3-05")
    );
    assert!(claim(&claims, "S3-05")["explanation"]
        .as_str()
        .is_some_and(|s| s.contains("both integrators")));
    // Omega 1.0 (Fig. 4): chaotic after the paper's few hundred periods, a chaotic transient to
    // the period-2 orbit when followed, with its escape rate measured by both integrators.
    assert_eq!(
        verdict("S3-06"),
        "beyond-paper",
        "{}",
        claim(&claims, "S3-06")
    );
    // "Non-periodic throughout 1.0-1.5" fails in the period-3 window (1.36-1.44; the quick
    // scan's step is 0.04), where the only attractor is a period-3 orbit.
    assert_eq!(verdict("S3-07"), "differ", "{}", claim(&claims, "S3-07"));
    let e307 = claim(&claims, "S3-07")["explanation"]
        .as_str()
        .unwrap_or("")
        .to_string();
    assert!(
        e307.contains("periodic windows") && e307.contains("period-3 double-sided at 1.36-"),
        "{e307}"
    );
    let e306 = claim(&claims, "S3-06")["explanation"]
        .as_str()
        .unwrap_or("")
        .to_string();
    assert!(
        e306.contains("chaotic transient")
            && e306.contains("escape rate")
            && e306.contains("DOP853"),
        "{e306}"
    );
    // Fig. 7: the sequence is shifted to lower F_hat.
    assert_eq!(verdict("S3-13"), "differ");
    let s306 = claim(&claims, "S3-06")["geardyn"]
        .as_str()
        .unwrap_or("")
        .to_string();
    assert!(
        s306.contains("chaotic transient double-sided") && s306.contains("Lyapunov +"),
        "{s306}"
    );
    // The Sec. 3 sets table lists every point at the paper's time scale and followed.
    let tables = doc["tables"].as_array().expect("tables");
    let sets = tables
        .iter()
        .find(|t| {
            t["heading"]
                .as_str()
                .is_some_and(|h| h.starts_with("Sec. 3"))
        })
        .expect("Sec. 3 sets table");
    assert_eq!(sets["rows"].as_array().map(Vec::len), Some(22));

    // HB: eq. 13 and eq. 14 hold; no case III at zeta 0.05 (the paper has it).
    for id in [
        "S4-01", "S4-02", "S4-03", "S5-02", "S6-02", "S6-05", "S6-07", "S6-09",
    ] {
        assert_eq!(verdict(id), "agree", "{id}: {}", claim(&claims, id));
    }
    for id in [
        "S5-04", "S6-03", "S6-04", "S6-06", "S8-02", "S8-05", "S8-08",
    ] {
        assert_eq!(verdict(id), "differ", "{id}: {}", claim(&claims, id));
    }
    // S5-04: the simulation half holds (no period-1 double-sided orbit; its double-sided steady
    // states are subharmonic or aperiodic), the harmonic-balance half fails.
    let e504 = claim(&claims, "S5-04")["explanation"]
        .as_str()
        .unwrap_or("")
        .to_string();
    assert!(
        e504.contains("simulation finds no period-1 double-sided orbit")
            && e504.contains("not case III")
            && e504.contains("no case III at zeta 0.05"),
        "{e504}"
    );
    assert!(claim(&claims, "S4-03")["geardyn"]
        .as_str()
        .is_some_and(|s| s.contains("Omega_t1 0.821") && s.contains("Omega_t2 1.407")));
    // F_hat 10: the linear peak grazes the backlash by 1.25e-4 (closed form), a marginal grazing.
    assert_eq!(verdict("S6-01"), "agree", "{}", claim(&claims, "S6-01"));
    assert!(claim(&claims, "S6-01")["explanation"]
        .as_str()
        .is_some_and(|s| s.contains("marginal grazing") && s.contains("1.25e-4")));
    // The normalisation table: eq. 5 as printed fails exactly the case III claims.
    let norm = tables
        .iter()
        .find(|t| {
            t["heading"]
                .as_str()
                .is_some_and(|h| h.starts_with("Case III"))
        })
        .expect("normalisation table");
    let rows = norm["rows"].as_array().expect("rows");
    let fails = rows.last().expect("a last row");
    assert_eq!(fails[0], "claims not reproduced");
    assert_eq!(fails[1], "S6-03; S6-04; S6-06", "{norm}");
    // Fig. 14: the case III share at zeta 0.02 is "almost half".
    assert_eq!(verdict("S5-08"), "agree", "{}", claim(&claims, "S5-08"));

    // Sec. 7 on synthetic data: never "agree", always labelled.
    for c in claims.iter().filter(|c| c["section"] == "7") {
        assert_eq!(c["verdict"], "not-testable-synthetic", "{}", c["id"]);
        assert!(c["geardyn"]
            .as_str()
            .is_some_and(|s| s.contains("SYNTHETIC")));
    }
    let md = String::from_utf8(fa[Path::new("REPRODUCTION.md")].clone()).expect("utf-8");
    assert!(md.contains("SYNTHETIC"), "report names the data kind");
    assert!(md.contains("| S3-05 |"), "claim table in the report");
    // Every image of the HTML page exists.
    let html = String::from_utf8(fa[Path::new("index.html")].clone()).expect("utf-8");
    let images: Vec<&str> = html
        .split("<img src=\"")
        .skip(1)
        .filter_map(|t| t.split('"').next())
        .collect();
    assert!(images.len() >= 30, "{} images", images.len());
    for src in images {
        assert!(
            fa.contains_key(Path::new(src)),
            "index.html shows missing {src}"
        );
    }
    let munro =
        String::from_utf8(fa[Path::new("sec7-validation/munro/report.md")].clone()).expect("utf-8");
    assert!(
        munro.starts_with("**SYNTHETIC DATA"),
        "Munro report labelled synthetic"
    );
}

/// A missing data folder fails at once with the file named, a non-zero status and no output.
#[test]
fn missing_data_fails_before_computing_and_writes_nothing() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args(["reproduce", "--quick", "--data"])
        .arg(tmp.path().join("no-such-data"))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("the geardyn binary runs");
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("munro") && err.contains("rig.toml"), "{err}");
    assert!(!out.exists(), "no partial output");
}
