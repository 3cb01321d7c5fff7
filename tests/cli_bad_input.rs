//! Bad input gets one clear error, a non-zero exit status and never a panic.

mod common;
use common::geardyn;

fn fails_cleanly(args: &[&str], needle: &str) {
    let out = geardyn(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.to_lowercase().contains(&needle.to_lowercase()),
        "{args:?}: error '{err}' should mention '{needle}'"
    );
    assert!(out.stdout.is_empty(), "{args:?} wrote to stdout on error");
}

#[test]
fn negative_damping() {
    fails_cleanly(
        &[
            "simulate", "--fm", "0.1", "--fah", "0.2", "--zeta", "-0.02", "--omega", "0.5",
            "--json",
        ],
        "zeta",
    );
}

#[test]
fn zero_frequency() {
    fails_cleanly(
        &[
            "simulate", "--fm", "0.1", "--fah", "0.2", "--zeta", "0.02", "--omega", "0", "--json",
        ],
        "omega",
    );
}

#[test]
fn nan_parameters() {
    fails_cleanly(
        &[
            "simulate", "--fm", "NaN", "--fah", "0.2", "--zeta", "0.02", "--omega", "0.5",
        ],
        "--fm",
    );
    fails_cleanly(
        &[
            "simulate", "--fm", "0.1", "--fah", "0.2", "--zeta", "0.02", "--omega", "0.5", "--q0",
            "nan",
        ],
        "q0",
    );
    fails_cleanly(
        &[
            "attractors",
            "--fm",
            "0.1",
            "--fah",
            "inf",
            "--zeta",
            "0.02",
            "--omega",
            "0.5",
        ],
        "--fah",
    );
}

#[test]
fn empty_ic_grid() {
    fails_cleanly(
        &[
            "attractors",
            "--fm",
            "0.1",
            "--fah",
            "0.2",
            "--zeta",
            "0.02",
            "--omega",
            "0.5",
            "--ic-grid",
            "-2:2:0",
            "--json",
        ],
        "ic-grid",
    );
    fails_cleanly(
        &[
            "attractors",
            "--fm",
            "0.1",
            "--fah",
            "0.2",
            "--zeta",
            "0.02",
            "--omega",
            "0.5",
            "--ic-grid",
            "-2:2",
            "--json",
        ],
        "ic-grid",
    );
}

#[test]
fn bad_sweep_range() {
    fails_cleanly(
        &[
            "sweep",
            "--fm",
            "0.1",
            "--fah",
            "0.2",
            "--zeta",
            "0.02",
            "--omega",
            "1.5:0.3:0.1",
        ],
        "omega",
    );
    fails_cleanly(
        &[
            "sweep",
            "--fm",
            "0.1",
            "--fah",
            "0.2",
            "--zeta",
            "0.02",
            "--omega",
            "0.3:1.5:0",
        ],
        "omega",
    );
    fails_cleanly(
        &[
            "sweep", "--fm", "0.1", "--fah", "0.2", "--zeta", "0.02", "--omega", "a:b:c",
        ],
        "omega",
    );
}

#[test]
fn missing_parameter_and_unknown_flag() {
    fails_cleanly(
        &[
            "simulate", "--fm", "0.1", "--zeta", "0.02", "--omega", "0.5",
        ],
        "--fah",
    );
    fails_cleanly(
        &[
            "simulate", "--fm", "0.1", "--fah", "0.2", "--zeta", "0.02", "--omega", "0.5",
            "--bogus",
        ],
        "bogus",
    );
}

/// A data set whose CSV uses ';' fails before any output, naming file and line, with the hint.
#[test]
fn semicolon_csv_in_a_data_set() {
    let dir = tempfile::tempdir().expect("temp dir");
    let data = dir.path().join("data");
    std::fs::create_dir(&data).expect("mkdir");
    std::fs::write(
        data.join("rig.toml"),
        "[rig]\nname = \"r\"\npinion_teeth = 32\ngear_teeth = 32\nmodule_mm = 6.35\n\
         pressure_angle_deg = 20.0\nface_width_mm = 12.7\ndesign_load_n = 3780.0\n\
         backlash_mm = 0.1\n[source]\nkind = \"measured\"\ncitation = \"lab report\"\n\
         instrument = \"encoders\"\ndate = 2024-05-17\nuncertainty = \"+-0.1 um\"\n",
    )
    .expect("write rig");
    std::fs::write(
        data.join("dte.csv"),
        "load_n;speed_rpm;dte_pp_um\n3780;1000;1,5\n",
    )
    .expect("write csv");
    let fits = dir.path().join("fits");
    let reports = dir.path().join("reports");
    let args = [
        "validate",
        "munro",
        "--data",
        data.to_str().expect("utf-8 path"),
        "--fits",
        fits.to_str().expect("utf-8 path"),
        "--reports",
        reports.to_str().expect("utf-8 path"),
    ];
    fails_cleanly(&args, "dte.csv:1");
    fails_cleanly(&args, "comma-separated");
    assert!(
        !fits.exists() && !reports.exists(),
        "partial output written"
    );
}

/// `synth kubo` cannot hide the Munro-only effects: refused (no set whose truth records an
/// effect its curves lack), and no synth writes without `--out` (the shipped sets are never
/// overwritten by default).
#[test]
fn synth_refuses_what_it_cannot_make_and_needs_an_out_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("k");
    for (flag, value) in [
        ("--damping-exponent", "2"),
        ("--torque-ripple-ratio", "0.5"),
        ("--backlash-factor", "0.7"),
        ("--sensor-peak-hz", "900"),
    ] {
        fails_cleanly(
            &["synth", "kubo", flag, value, "--out", out.to_str().unwrap()],
            flag,
        );
        assert!(!out.exists(), "{flag}: nothing written");
    }
    fails_cleanly(&["synth", "munro"], "--out");
    fails_cleanly(&["synth", "kubo"], "--out");
}

/// `validate kubo --hold-ste` on a rig.toml without an STE at the test load: refused, not
/// silently fitted.
#[test]
fn holding_an_ste_that_is_not_stated_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("kubo");
    std::fs::create_dir(&data).unwrap();
    let rig = std::fs::read_to_string("data/kubo/rig.toml").unwrap();
    let start = rig.find("[ste]").expect("data/kubo states an STE");
    let end = rig[start + 1..]
        .find("\n[")
        .map_or(rig.len(), |e| start + 2 + e);
    std::fs::write(
        data.join("rig.toml"),
        format!("{}{}", &rig[..start], &rig[end..]),
    )
    .unwrap();
    std::fs::copy(
        "data/kubo/dynamic_factor.csv",
        data.join("dynamic_factor.csv"),
    )
    .unwrap();
    let fits = tmp.path().join("fits");
    fails_cleanly(
        &[
            "validate",
            "kubo",
            "--data",
            data.to_str().unwrap(),
            "--hold-ste",
            "--fits",
            fits.to_str().unwrap(),
            "--reports",
            tmp.path().join("reports").to_str().unwrap(),
        ],
        "--hold-ste",
    );
    assert!(!fits.exists());
}

/// A command that replaces its output folder as a whole (`mesh`, `discover`, `synth`, the
/// validate reports) refuses a folder holding files it did not write, before any work, and
/// leaves it as it was; the folder it wrote itself (marked) it replaces on the next run.
#[test]
fn an_output_folder_of_the_users_is_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let user = dir.path().join("my-rig");
    std::fs::create_dir(&user).unwrap();
    std::fs::write(user.join("notes.txt"), "mine").unwrap();
    let user_s = user.to_str().unwrap();
    let mesh = [
        "mesh",
        "--rig",
        "data/munro/rig.toml",
        "--load-n",
        "945:4725:945",
        "--tip-relief-design-load-n",
        "3780",
        "--out",
    ];
    fails_cleanly(&[&mesh[..], &[user_s]].concat(), "did not write");
    fails_cleanly(&["synth", "munro", "--out", user_s], "did not write");
    assert_eq!(
        std::fs::read_to_string(user.join("notes.txt")).unwrap(),
        "mine"
    );
    assert_eq!(std::fs::read_dir(&user).unwrap().count(), 1);
    let own = dir.path().join("mesh-out");
    let own_s = own.to_str().unwrap();
    for _ in 0..2 {
        let out = geardyn(&[&mesh[..], &[own_s]].concat());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert!(own.join(".geardyn-output").exists());
}

/// `synth` writes only sets that `validate munro` can fit: the design load among the loads,
/// enough speeds, values geardyn loads; a basin map needs more than one initial condition per axis.
#[test]
fn synth_and_basins_refuse_what_cannot_be_used() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let out_s = out.to_str().unwrap();
    fails_cleanly(
        &["synth", "munro", "--loads", "2000:0.3", "--out", out_s],
        "design load",
    );
    fails_cleanly(
        &["synth", "munro", "--speeds", "1000:1000:50", "--out", out_s],
        "fewer than 6",
    );
    // Curves past the 1000 um a data set may hold: geardyn would not load them.
    fails_cleanly(
        &[
            "synth",
            "munro",
            "--loads",
            "3780:40,945:40",
            "--out",
            out_s,
        ],
        "plausible range",
    );
    assert!(!out.exists());
    fails_cleanly(
        &[
            "basins",
            "--fm",
            "0.1",
            "--fah",
            "0.2",
            "--zeta",
            "0.02",
            "--omega",
            "0.5",
            "--ic-grid",
            "-2:2:1",
            "--out",
            out_s,
        ],
        "at least 2",
    );
}
