//! `geardyn bifurcation` as a user runs it: the marks against independent computations and the
//! Poincare points against the attractor searches of Sec. 3.

mod common;
use common::geardyn;

fn run(args: &[&str]) -> (String, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("b");
    let mut all: Vec<&str> = vec!["bifurcation"];
    all.extend_from_slice(args);
    let out_s = out.to_string_lossy().to_string();
    all.extend_from_slice(&["--out", &out_s]);
    let o = geardyn(&all);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["bifurcation.png", "bifurcation.svg"] {
        assert!(out.join(f).metadata().is_ok_and(|m| m.len() > 1000), "{f}");
    }
    let points = std::fs::read_to_string(out.join("bifurcation.csv")).expect("points");
    let marks = std::fs::read_to_string(out.join("marks.csv")).expect("marks");
    (points, marks, dir)
}

fn marks_of(marks: &str, what: &str, source: &str) -> Vec<f64> {
    marks
        .lines()
        .skip(1)
        .filter_map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[2] == what && c[3] == source).then(|| c[1].parse().expect("value"))
        })
        .collect()
}

/// F_hat 2, zeta 0.05 over Omega 0.6-0.9: the AFT folds bound the dual-valued region that the
/// single-harmonic solution puts at 0.690-0.820 (S6-02; the 15-harmonic AFT differs from it by up
/// to 0.02 here, so 0.03, the report's tolerance), and the sweep carried upwards jumps at the
/// upper fold (the first grid step past it).
#[test]
fn omega_diagram_marks_the_folds_where_the_carried_sweep_jumps() {
    let (_, marks, _d) = run(&[
        "--fm",
        "0.1",
        "--fah",
        "0.05",
        "--zeta",
        "0.05",
        "--vary",
        "omega",
        "--range",
        "0.6:0.9:0.01",
        "--ic-grid",
        "-2:2:5",
    ]);
    let folds = marks_of(&marks, "fold", "aft");
    assert_eq!(folds.len(), 2, "{marks}");
    assert!(
        (folds[0] - 0.690).abs() < 0.03 && (folds[1] - 0.820).abs() < 0.03,
        "{folds:?}"
    );
    let jumps = marks_of(&marks, "jump", "simulation");
    assert_eq!(jumps.len(), 1, "{marks}");
    assert!(
        (jumps[0] - folds[1]).abs() <= 0.01,
        "jump {} fold {}",
        jumps[0],
        folds[1]
    );
}

/// Fig. 8's damping values at Omega 1.0: the Poincare points of the grid's attractors are the
/// period-2, 4 and 8 orbits at zeta 0.05 (2 + 4 + 8 points, as `attractors` finds) and the
/// period-2 orbit alone at zeta 0.1.
#[test]
fn zeta_diagram_has_the_orbits_of_the_attractor_search() {
    let (points, _, _d) = run(&[
        "--fm",
        "0.1",
        "--fah",
        "0.2",
        "--omega",
        "1.0",
        "--vary",
        "zeta",
        "--range",
        "0.05:0.1:0.05",
        "--ic-grid",
        "-2:2:21",
        "--mode",
        "grid",
    ]);
    let mut at = std::collections::BTreeMap::<String, Vec<u32>>::new();
    for l in points.lines().skip(1) {
        let c: Vec<&str> = l.split(',').collect();
        assert_eq!(c[6], "attractor", "{l}");
        at.entry(c[1].to_string())
            .or_default()
            .push(c[7].parse().expect("a period"));
    }
    let count = |z: &str, p: u32| at[z].iter().filter(|&&q| q == p).count();
    assert_eq!(
        (count("0.05", 2), count("0.05", 4), count("0.05", 8)),
        (2, 4, 8)
    );
    assert_eq!(at["0.05"].len(), 14);
    assert_eq!((count("0.1", 2), at["0.1"].len()), (2, 2));
}

#[test]
fn bad_range_is_one_clear_error() {
    let o = geardyn(&[
        "bifurcation",
        "--fah",
        "0.2",
        "--omega",
        "1.0",
        "--vary",
        "zeta",
        "--range",
        "0.05:2:0.05",
        "--out",
        "/nonexistent/never",
    ]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--range") && e.contains("STOP"), "{e}");
    let o = geardyn(&[
        "bifurcation",
        "--fm",
        "0.1",
        "--fah",
        "0.2",
        "--vary",
        "zeta",
        "--range",
        "0.05:0.1:0.05",
        "--out",
        "/nonexistent/never",
    ]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--omega is needed unless --vary omega"), "{e}");
}
