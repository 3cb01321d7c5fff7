//! Table of bad inputs across the commands (issue 22): every one exits non-zero before any
//! work is wasted, with one message naming the option, or the file, line and field (or the
//! rig.toml key), and writes nothing: the output folders stay absent, a file given where a folder
//! is expected stays as it was, and no staging folder is left behind. Each case runs in its own
//! temporary folder (also the working directory, so default output folders would show up there).
//! tests/cli_bad_input.rs and tests/data_errors.rs cover other bad inputs; none is repeated here.
//! A last test interrupts a long run (Ctrl-C) and checks that nothing is left behind.

use std::path::Path;
use std::process::Command;

/// A valid synthetic Munro-like rig.toml; the line numbers in the table refer to it.
const RIG: &str = r#"[rig]
name = "Munro-like test rig"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1

[source]
kind = "synthetic"
citation = "a table-driven test of bad inputs"
generator = "tests/bad_inputs.rs"

[source.truth]
zeta = 0.0175
"#;

const HEADER: &str = "load_n,speed_rpm,dte_pp_um\n";

/// What a case needs in its folder besides the command line.
enum Setup {
    /// Nothing.
    None,
    /// A Munro data set `data/` with this CSV as `data/c.csv` (after the header when the text
    /// does not start with a letter) and this rig.toml.
    Data(String, String),
    /// A plain file `file.txt`, passed where a folder (or a file) is expected.
    File,
    /// A folder `folder/`, passed where a file is expected.
    Folder,
}

struct Case {
    name: &'static str,
    args: String,
    needle: String,
    setup: Setup,
}

const M: &str = "--fm 0.1 --fah 0.2 --zeta 0.02";
const PROFILE_CMD: &str =
    "mesh --rig data/rig.toml --load-n 945 --tip-relief-um 0 --profile-table data/c.csv --out out";
const VALIDATE: &str = "validate munro --data data --fits fits --reports reports";

fn case(name: &'static str, args: &str, needle: &str, setup: Setup) -> Case {
    Case {
        name,
        args: args.to_string(),
        needle: needle.to_string(),
        setup,
    }
}

fn cli(name: &'static str, args: &str, needle: &str) -> Case {
    case(name, args, needle, Setup::None)
}

/// A data-set case: `rows` follow the header (or replace it when they start with a letter).
fn csv(name: &'static str, rows: &str, needle: &str) -> Case {
    let text = if rows.starts_with(|c: char| c.is_ascii_alphabetic()) {
        rows.to_string()
    } else {
        format!("{HEADER}{rows}")
    };
    case(name, VALIDATE, needle, Setup::Data(text, RIG.to_string()))
}

/// A rig.toml case: `from` replaced by `to` in the valid rig.
fn rig(name: &'static str, from: &str, to: &str, needle: &str) -> Case {
    assert!(RIG.contains(from), "{name}: '{from}' not in the rig");
    case(
        name,
        VALIDATE,
        needle,
        Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.replace(from, to)),
    )
}

/// A design-load curve without a resonance: 1 um +- 0.1 um (a fixed pseudo-random pattern)
/// from 1000 to 5000 rpm, which no damping ratio in the plausible range explains.
fn flat_curve() -> String {
    (0..81)
        .map(|i| {
            let wiggle = ((i * 37) % 11) as f64 / 50.0 - 0.1;
            format!("3780,{},{:.4}\n", 1000 + 50 * i, 1.0 + wiggle)
        })
        .collect()
}

/// The shipped Munro curves (`data/munro/dte.csv`), header included.
fn shipped_munro() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/munro/dte.csv"))
        .expect("shipped data")
}

/// The shipped Munro curves with this rig.toml.
fn munro_with(rig: String) -> Setup {
    Setup::Data(shipped_munro(), rig)
}

/// The valid rig with `table` (its lines, then a blank line) inserted before `[source]`: the
/// table's first key is on line 12.
fn rig_with_table(table: &str) -> String {
    RIG.replace("[source]\n", &format!("{table}\n[source]\n"))
}

const MESH_DESIGN_RELIEF: &str =
    "mesh --rig data/rig.toml --load-n 945:4725:945 --tip-relief-design-load-n 3780 --out out";

/// The mesh command of [`MESH_DESIGN_RELIEF`] on the valid rig with `from` replaced by `to`.
fn mesh_rig(name: &'static str, from: &str, to: &str, needle: &str) -> Case {
    assert!(RIG.contains(from), "{name}: '{from}' not in the rig");
    case(
        name,
        MESH_DESIGN_RELIEF,
        needle,
        Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.replace(from, to)),
    )
}

/// The shipped Munro curves at 3780 and 945 N, the lighter one measured only at 1000 rpm (pp
/// DTE 0) and from 2000 rpm on: its STE must be read from that one low-speed point.
fn zero_dte_at_lowest_speed() -> String {
    let shipped = shipped_munro();
    let mut rows = String::new();
    for line in shipped.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let speed: f64 = f[1].parse().expect("speed");
        match f[0] {
            "3780" => rows.push_str(&format!("{line}\n")),
            "945" if speed == 1000.0 => rows.push_str("945,1000,0\n"),
            "945" if speed >= 2000.0 => rows.push_str(&format!("{line}\n")),
            _ => {}
        }
    }
    rows
}

fn table() -> Vec<Case> {
    let hundred_digits = "9".repeat(100);
    vec![
        // CSV faults: each names file:line and the column.
        csv(
            "NaN DTE",
            "3780,1000,1.0\n3780,1100,NaN\n",
            "c.csv:3: field 'dte_pp_um'",
        ),
        csv("inf speed", "3780,inf,1.0\n", "c.csv:2: field 'speed_rpm'"),
        csv(
            "1e308 DTE",
            "3780,1000,1e308\n",
            "c.csv:2: field 'dte_pp_um'",
        ),
        csv(
            "100-digit DTE",
            &format!("3780,1000,1.0\n3780,1100,{hundred_digits}\n"),
            "c.csv:3: field 'dte_pp_um'",
        ),
        csv(
            "DTE in nm, not um",
            "3780,1000,411700\n",
            "c.csv:2: field 'dte_pp_um'",
        ),
        csv(
            "negative load",
            "-3780,1000,1.0\n",
            "c.csv:2: field 'load_n'",
        ),
        csv(
            "zero load",
            "3780,1000,1.0\n0,1100,1.0\n",
            "c.csv:3: field 'load_n'",
        ),
        csv(
            "load 1e300 N",
            "1e300,1000,1.0\n",
            "c.csv:2: field 'load_n'",
        ),
        csv("zero speed", "3780,0,1.0\n", "c.csv:2: field 'speed_rpm'"),
        csv(
            "negative speed",
            "3780,-1000,1.0\n",
            "c.csv:2: field 'speed_rpm'",
        ),
        csv(
            "speed 1e-200 rpm",
            "3780,1e-200,1.0\n",
            "c.csv:2: field 'speed_rpm'",
        ),
        csv(
            "speed 1e12 rpm",
            "3780,1000,1.0\n3780,1e12,1.0\n",
            "c.csv:3: field 'speed_rpm'",
        ),
        csv(
            "mesh frequency 1e12 Hz",
            "load_n,mesh_freq_hz,dte_pp_um\n3780,1e12,1.0\n",
            "c.csv:2: field 'mesh_freq_hz'",
        ),
        csv(
            "loads 1e-7 N apart at one speed",
            "3780,1000,1.0\n3780,1100,1.2\n3780.0000001,1100,1.5\n",
            "c.csv:4: field 'speed_rpm'",
        ),
        csv(
            "negative stated sd",
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.0,-0.1\n",
            "c.csv:2: field 'dte_pp_sd_um'",
        ),
        csv(
            "missing DTE column",
            "load_n,speed_rpm\n3780,1000\n",
            "c.csv:1: field 'dte_pp_um'",
        ),
        csv(
            "semicolon separator",
            "load_n;speed_rpm;dte_pp_um\n3780;1000;1,0\n",
            "comma-separated",
        ),
        csv(
            "tab separator",
            "load_n\tspeed_rpm\tdte_pp_um\n3780\t1000\t1.0\n",
            "comma-separated",
        ),
        csv("extra field", "3780,1000,1.0,7\n", "c.csv:2: field '(row)'"),
        csv("empty cell", "3780,,1.0\n", "c.csv:2: field 'speed_rpm'"),
        // rig.toml faults: each names rig.toml:line and the key.
        rig(
            "module 1e300 mm",
            "module_mm = 6.35",
            "module_mm = 1e300",
            "rig.toml:5: field 'rig.module_mm'",
        ),
        rig(
            "4294967295 teeth",
            "gear_teeth = 32",
            "gear_teeth = 4294967295",
            "rig.toml:4: field 'rig.gear_teeth'",
        ),
        rig(
            "mesh stiffness 1e30",
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nmesh_stiffness_n_per_um = 1e30",
            "rig.toml:10: field 'rig.mesh_stiffness_n_per_um'",
        ),
        rig(
            "backlash 1e9 mm",
            "backlash_mm = 0.1",
            "backlash_mm = 1e9",
            "rig.toml:9: field 'rig.backlash_mm'",
        ),
        rig(
            "design load nan",
            "design_load_n = 3780.0",
            "design_load_n = nan",
            "rig.toml:8: field 'rig.design_load_n'",
        ),
        rig(
            "omega_n 0 Hz",
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nomega_n_hz = 0",
            "rig.toml:10: field 'rig.omega_n_hz'",
        ),
        rig(
            "STE amplitude 1e300",
            "[source]\n",
            "[ste]\nload_n = [3780.0]\namplitude_um = [1e300]\n\n[source]\n",
            "field 'ste.amplitude_um'",
        ),
        rig(
            "STE load given twice to 1e-9",
            "[source]\n",
            "[ste]\nload_n = [3780.0, 3780.0000000001]\namplitude_um = [0.3, 0.4]\n\n[source]\n",
            "field 'ste.load_n': entry 2 (3780.0000000001 N) is the load of entry 1",
        ),
        rig(
            "zeta given to validate munro",
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nzeta = 0.02",
            "rig.toml:10: field 'rig.zeta': zeta = 0.02: validate munro fits zeta",
        ),
        rig(
            "omega_n given to validate munro",
            "backlash_mm = 0.1",
            "backlash_mm = 0.1\nomega_n_hz = 1600",
            "rig.toml:10: field 'rig.omega_n_hz'",
        ),
        case(
            "stated relative noise without a floor",
            VALIDATE,
            "rig.toml:11: field 'noise.floor_um': a stated noise needs a positive floor_um",
            Setup::Data(
                format!("{HEADER}{}", flat_curve()),
                RIG.replace("[source]\n", "[noise]\nrelative = 0.03\n\n[source]\n"),
            ),
        ),
        case(
            "discover with 5 speeds at a load",
            "discover --data data --out out",
            "c.csv:2: field 'load_n': discovery needs at least 8 speeds per load; load 3780 N has 5",
            Setup::Data(
                format!("{HEADER}3780,1000,1.0\n3780,1100,1.1\n3780,1200,1.2\n3780,1300,1.4\n3780,1400,1.6\n"),
                RIG.to_string(),
            ),
        ),
        case(
            "validate kubo: zeta and omega_n given without the STE",
            "validate kubo --data data --fits fits --reports reports",
            // No line: the key is missing, and so is its table.
            "rig.toml: field 'ste.amplitude_um': zeta and omega_n_hz are given",
            Setup::Data(
                "speed_rpm,dynamic_factor_min,dynamic_factor_max\n1000,1.0,1.1\n2000,1.1,1.4\n"
                    .into(),
                RIG.replace(
                    "backlash_mm = 0.1",
                    "backlash_mm = 0.1\ntest_load_n = 3780.0\nzeta = 0.1\nomega_n_hz = 2500",
                ),
            ),
        ),
        rig(
            "required keys missing",
            "module_mm = 6.35\npressure_angle_deg = 20.0\n",
            "",
            "field 'rig.module_mm': missing in [rig]: module_mm, pressure_angle_deg",
        ),
        // Fits that fail: the reason, status 2, nothing written.
        csv(
            "flat design-load curve (no resonance)",
            &flat_curve(),
            "the fit to data failed: design-load fit: zeta",
        ),
        csv(
            "zero DTE where a load's STE is read",
            &zero_dte_at_lowest_speed(),
            "c.csv:83: field 'dte_pp_um': the STE at 945 N is read from its lowest speed",
        ),
        // Command-line edge values: each names the option.
        cli(
            "omega 1e-200",
            &format!("simulate {M} --omega 1e-200 --json"),
            "--omega",
        ),
        cli(
            "omega 1e3",
            &format!("simulate {M} --omega 1e3 --json"),
            "--omega",
        ),
        cli(
            "periods 1e12",
            &format!("simulate {M} --omega 0.5 --periods 1e12"),
            "--periods",
        ),
        cli(
            "periods -5",
            &format!("simulate {M} --omega 0.5 --periods -5"),
            "--periods",
        ),
        cli(
            "keep 1e9",
            &format!("simulate {M} --omega 0.5 --keep 1000000000"),
            "--keep",
        ),
        cli(
            "q0 1e300",
            &format!("simulate {M} --omega 0.5 --q0 1e300"),
            "--q0",
        ),
        cli(
            "negative F_ah",
            "simulate --fm 0.1 --fah -0.2 --zeta 0.02 --omega 0.5",
            "--fah",
        ),
        cli(
            "zeta 1e-6",
            "attractors --fm 0.1 --fah 0.2 --zeta 1e-6 --omega 0.5",
            "--zeta",
        ),
        cli(
            "horizon beyond the limit",
            &format!("attractors {M} --omega 1.0 --horizon 2000000"),
            "--horizon",
        ),
        cli(
            "max exposure 1e12",
            &format!("basins {M} --omega 1.0 --max-exposure 1e12 --out out"),
            "--max-exposure",
        ),
        cli(
            "target escapes 0",
            &format!("sweep {M} --omega 1.0 --direction all --target-escapes 0 --out out"),
            "--target-escapes",
        ),
        cli(
            "escape horizon 10",
            &format!("escape {M} --omega 1.0 --horizon 10 --out out"),
            "--horizon",
        ),
        cli(
            "rtol 0",
            &format!("simulate {M} --omega 0.5 --integrator dop853 --rtol 0"),
            "--rtol",
        ),
        cli(
            "1000 harmonics",
            &format!("hbm {M} --omega 0.5:0.6:0.1 --method aft --harmonics 1000 --out out"),
            "--harmonics",
        ),
        cli(
            "subharmonic 0",
            &format!("hbm {M} --omega 0.5:0.6:0.1 --method aft --subharmonic 0 --out out"),
            "--subharmonic",
        ),
        cli(
            "hbm F_m 1e300",
            "hbm --fm 1e300 --fah 0.2 --zeta 0.02 --omega 0.5 --out out",
            "--fm",
        ),
        cli(
            "hbm omega from 1e-300",
            &format!("hbm {M} --omega 1e-300:1:0.1 --out out"),
            "--omega",
        ),
        cli(
            "basin grid 4001",
            &format!("basins {M} --omega 0.5 --ic-grid -2:2:4001 --out out"),
            "ic-grid",
        ),
        cli(
            "sweep all over a huge grid",
            &format!("sweep {M} --omega 0.1:100:0.01 --direction all --ic-grid -2:2:101 --out out"),
            "--ic-grid",
        ),
        cli(
            "study points 100000",
            "study damping --points 100000 --out out",
            "--points",
        ),
        cli(
            "compare tolerance -1",
            &format!("compare {M} --omega 0.5 --tolerance -1 --out out"),
            "--tolerance",
        ),
        cli(
            "synth omega_n 0",
            "synth munro --omega-n-hz 0 --out out",
            "--omega-n-hz",
        ),
        cli(
            "synth noise -1",
            "synth munro --noise-um -1 --out out",
            "--noise-um",
        ),
        cli(
            "discover-study with too few replicates to ever detect",
            "discover-study --hidden none --seeds 1 --bootstrap 99 --out out/summary.json",
            "the bootstrap needs 100",
        ),
        cli(
            "validate given --rig",
            "validate munro --rig data --fits fits --reports reports",
            "give its folder as --data DIR",
        ),
        cli(
            "synth relative part on the constant family",
            "synth munro --noise constant --noise-relative 0.05 --out out",
            "--noise-relative applies to the level-dependent families",
        ),
        cli(
            "synth student-t with 2 dof",
            "synth munro --noise student-t --noise-dof 2 --out out",
            "--noise-dof",
        ),
        cli(
            "synth kubo zeta 1.5",
            "synth kubo --zeta 1.5 --out out",
            "--zeta",
        ),
        cli(
            "synth negative STE",
            "synth munro --loads 3780:-1 --out out",
            "--loads",
        ),
        cli(
            "validate-study 0 seeds",
            "validate-study --seeds 0 --out out/summary.json",
            "--seeds",
        ),
        cli(
            "bench basin grid 100000",
            "bench --basin-grid 100000",
            "--basin-grid",
        ),
        cli(
            "speed without a rig",
            &format!("simulate {M} --speed-rpm 1000"),
            "--rig",
        ),
        cli(
            "a load in newtons without a rig",
            &format!("basins {M} --omega 0.5 --load-n 945 --out out"),
            "--load-n is in the rig's units and needs --rig",
        ),
        cli(
            "a torque in newtons without a rig",
            &format!("sweep {M} --omega 0.5:0.7:0.1 --torque-n 100 --out out"),
            "--torque-n is in the rig's units and needs --rig",
        ),
        cli(
            "rig and a dimensionless torque",
            "simulate --rig rig.toml --fat 0.1 --speed-rpm 1000",
            "--fat",
        ),
        case(
            "torque 1e8 N: F_aT above its range",
            "simulate --rig data/rig.toml --ste-um 2.5 --zeta 0.02 --omega-n-hz 1600 --speed-rpm 3000 --torque-n 1e8",
            "--torque-n: gives F_aT",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        cli(
            "rig and a dimensionless load",
            "simulate --rig rig.toml --fm 0.1 --speed-rpm 1000",
            "--fm",
        ),
        cli(
            "load 0 N",
            "sweep --rig rig.toml --load-n 0 --speed-rpm 1000:2000:100 --out out",
            "--load-n",
        ),
        cli(
            "STE 1e6 um",
            "sweep --rig rig.toml --ste-um 1e6 --speed-rpm 1000:2000:100 --out out",
            "--ste-um",
        ),
        cli(
            "natural frequency 0 Hz",
            "hbm --rig rig.toml --omega-n-hz 0 --speed-rpm 1000:2000:100 --out out",
            "--omega-n-hz",
        ),
        case(
            "speed 1 rpm: Omega below its range",
            "sweep --rig data/rig.toml --ste-um 2.5 --zeta 0.02 --omega-n-hz 1600 --speed-rpm 1:100:1 --out out",
            "--speed-rpm: 1 rpm is Ω_h",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        case(
            "rig without zeta, no --zeta",
            "compare --rig data/rig.toml --ste-um 2.5 --omega-n-hz 1600 --speed-rpm 1000:2000:500 --out out",
            "--zeta is needed with --rig",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        case(
            "init-data over an existing set",
            "init-data data",
            "data/rig.toml exists",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        cli(
            "reproduce without the data sets",
            "reproduce --quick --out out",
            "--data data: data/munro/rig.toml not found",
        ),
        cli(
            "validate without data outside the repository",
            "validate munro --fits fits --reports reports",
            "give your data set with --data DIR",
        ),
        case(
            "mesh at a load of 1e9 N",
            "mesh --rig data/rig.toml --load-n 1e9 --tip-relief-design-load-n 3780 --out out",
            "--load-n '1e9': load 1000000000 must be in (0, 1e8] N",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        cli(
            "mesh 1e9 samples",
            "mesh --rig rig.toml --load-n 945 --tip-relief-um 10 --samples 1000000000 --out out",
            "--samples",
        ),
        cli(
            "sweep --excitation geometry without a rig",
            &format!("sweep {M} --omega 0.5 --excitation geometry --out out"),
            "--excitation geometry needs --rig",
        ),
        cli(
            "sweep --tip-relief-um without --excitation geometry",
            &format!("sweep {M} --omega 0.5 --tip-relief-um 10 --out out"),
            "--tip-relief-um applies to --excitation geometry only",
        ),
        case(
            "sweep --excitation geometry with --ste-um",
            "sweep --rig data/rig.toml --zeta 0.02 --omega-n-hz 1600 --ste-um 2 --excitation geometry --speed-rpm 1000 --out out",
            "--ste-um and --excitation geometry both give the STE",
            Setup::Data(format!("{HEADER}3780,1000,1.0\n"), RIG.to_string()),
        ),
        case(
            "profile table: unknown gear",
            PROFILE_CMD,
            "data/c.csv:2: field 'gear': 'wheel': expected pinion or gear",
            Setup::Data("gear,diameter_mm,relief_um\nwheel,200,1\n".into(), RIG.to_string()),
        ),
        case(
            "profile table: diameters not increasing",
            PROFILE_CMD,
            "data/c.csv:3: field 'diameter_mm'",
            Setup::Data(
                "gear,diameter_mm,relief_um\npinion,210,1\npinion,200,0\n".into(),
                RIG.to_string(),
            ),
        ),
        case(
            "profile table: relief of 5 mm",
            PROFILE_CMD,
            "data/c.csv:2: field 'relief_um'",
            Setup::Data(
                "gear,diameter_mm,relief_um\npinion,190,5000\npinion,216,0\n".into(),
                RIG.to_string(),
            ),
        ),
        case(
            "profile table short of the flank in contact",
            PROFILE_CMD,
            "extend the table",
            Setup::Data(
                "gear,diameter_mm,relief_um\npinion,200,0\npinion,210,3\n".into(),
                RIG.to_string(),
            ),
        ),
        // Values inside the old ranges that the model cannot work with, and derived quantities
        // that fail: each names the input that made it fail.
        rig(
            "backlash 1e-300 mm",
            "backlash_mm = 0.1",
            "backlash_mm = 1e-300",
            "rig.toml:9: field 'rig.backlash_mm': backlash_mm = 1e-300: a backlash below 0.001 mm",
        ),
        case(
            "a load the backlash cannot carry (F_m above 1e9)",
            VALIDATE,
            "rig.toml:8: field 'rig.design_load_n': design_load_n = 1e8: over the mesh stiffness",
            Setup::Data(
                format!("{HEADER}3780,1000,1.0\n"),
                RIG.replace("design_load_n = 3780.0", "design_load_n = 1e8").replace(
                    "backlash_mm = 0.1",
                    "backlash_mm = 0.001\nmesh_stiffness_n_per_um = 0.01",
                ),
            ),
        ),
        rig(
            "noise floor 1e-300 um",
            "[source]\n",
            "[noise]\nfloor_um = 1e-300\n\n[source]\n",
            "rig.toml:12: field 'noise.floor_um': floor_um = 1e-300",
        ),
        csv(
            "stated sd 1e-300 um",
            "load_n,speed_rpm,dte_pp_um,dte_pp_sd_um\n3780,1000,1.0,1e-300\n",
            "c.csv:2: field 'dte_pp_sd_um': 1e-300 is outside the plausible range [0.001, 1000]",
        ),
        case(
            "discover on an all-zero DTE",
            "discover --data data --out out",
            "c.csv: field 'dte_pp_um': every point of the design-load curve (3780 N) reads 0 um",
            Setup::Data(
                format!(
                    "{HEADER}{}",
                    (0..10)
                        .map(|i| format!("3780,{},0\n", 1000 + 100 * i))
                        .collect::<String>()
                ),
                RIG.to_string(),
            ),
        ),
        case(
            "validate --ste geometry: a bore wider than the root circle",
            "validate munro --data data --fits fits --reports reports --ste geometry",
            "rig.toml:12: field 'geometry.pinion_bore_diameter_mm': pinion_bore_diameter_mm = 1000",
            munro_with(rig_with_table("[geometry]\npinion_bore_diameter_mm = 1000\n")),
        ),
        case(
            "profile table: a point inside the base circle",
            PROFILE_CMD,
            "data/c.csv:2: field 'diameter_mm': profile table: the pinion point at 10 mm lies inside",
            Setup::Data(
                "gear,diameter_mm,relief_um\npinion,10.0,0.0\npinion,216,5\n".into(),
                RIG.to_string(),
            ),
        ),
        mesh_rig(
            "mesh: a pressure angle the default root fillet does not fit",
            "pressure_angle_deg = 20.0",
            "pressure_angle_deg = 34.9",
            "rig.toml:6: field 'rig.pressure_angle_deg': pressure_angle_deg = 34.9",
        ),
        mesh_rig(
            "mesh: face width 1e-9 mm",
            "face_width_mm = 12.7",
            "face_width_mm = 1e-9",
            "rig.toml:7: field 'rig.face_width_mm': face_width_mm = 1e-9",
        ),
        mesh_rig(
            "mesh: a design load that deflects a 0.1 mm face too far for a relief",
            "face_width_mm = 12.7",
            "face_width_mm = 0.1",
            "tip_relief_design_load_n = 3780: deflects the teeth further than a tip relief",
        ),
        mesh_rig(
            "mesh: a centre distance of 1 km",
            "[source]\n",
            "[geometry]\ncentre_distance_mm = 1e6\n\n[source]\n",
            "rig.toml:12: field 'geometry.centre_distance_mm': centre_distance_mm = 1000000",
        ),
        mesh_rig(
            "mesh: module 0.001 mm",
            "module_mm = 6.35",
            "module_mm = 0.001",
            "rig.toml:5: field 'rig.module_mm': module_mm = 0.001: a module below 0.05 mm",
        ),
        case(
            "mesh: a tip relief deeper than a tenth of the module",
            "mesh --rig data/rig.toml --load-n 945 --tip-relief-um 21 --out out",
            "tip_relief_um = 21: tip relief deeper than a tenth of the module",
            Setup::Data(
                format!("{HEADER}3780,1000,1.0\n"),
                RIG.replace("module_mm = 6.35", "module_mm = 0.1"),
            ),
        ),
        case(
            "discover: a stated STE without its uncertainty",
            "discover --data data --out out",
            "rig.toml:13: field 'ste.amplitude_um': the STE is stated at 3780 N without its uncertainty: add sd_um",
            munro_with(rig_with_table(
                "[ste]\nload_n = [3780.0]\namplitude_um = [50.0]\n",
            )),
        ),
        case(
            "validate munro: a stated STE's uncertainty below a nanometre",
            VALIDATE,
            "rig.toml:14: field 'ste.sd_um': entry 1 is 0.0000001: must be a positive finite number, at least 0.001",
            munro_with(rig_with_table(
                "[ste]\nload_n = [3780.0]\namplitude_um = [50.0]\nsd_um = 1e-7\n",
            )),
        ),
        case(
            "validate munro: a stated STE without its uncertainty",
            VALIDATE,
            "rig.toml:13: field 'ste.amplitude_um': the STE is stated at 3780 N without its uncertainty: add sd_um",
            munro_with(rig_with_table(
                "[ste]\nload_n = [3780.0]\namplitude_um = [50.0]\n",
            )),
        ),
        case(
            "validate kubo: min equals max on every row",
            "validate kubo --data data --fits fits --reports reports",
            "c.csv:2: field 'dynamic_factor_max': dynamic_factor_min equals dynamic_factor_max on every row",
            Setup::Data(
                "speed_rpm,dynamic_factor_min,dynamic_factor_max\n1000,1.0,1.0\n2000,1.1,1.1\n"
                    .into(),
                RIG.to_string(),
            ),
        ),
        cli(
            "--ic-grid of 1e300",
            &format!("basins {M} --omega 0.5 --ic-grid -1e300:1e300:5 --out out"),
            "--ic-grid '-1e300:1e300:5': -1e300 is refused",
        ),
        cli(
            "init-data where no folder can be made",
            "init-data /proc/x",
            "DIR /proc/x: cannot create the folder",
        ),
        cli(
            "init-data below a folder that does not exist",
            "init-data a/b/c",
            "DIR a/b/c: its folder a/b does not exist",
        ),
        // Output paths of the wrong kind: named, with what was expected, before any work.
        case(
            "simulate --out FILE",
            &format!("simulate {M} --omega 0.5 --out file.txt"),
            "--out file.txt: a folder was expected",
            Setup::File,
        ),
        case(
            "basins --out FILE",
            &format!("basins {M} --omega 0.5 --ic-grid -2:2:3 --out file.txt"),
            "--out file.txt: a folder was expected",
            Setup::File,
        ),
        case(
            "sweep --out below a FILE",
            &format!("sweep {M} --omega 0.5 --out file.txt/sweep"),
            "file.txt is a file",
            Setup::File,
        ),
        case(
            "validate --fits FILE",
            "validate munro --data data --fits file.txt --reports reports",
            "--fits file.txt: a folder was expected",
            Setup::File,
        ),
        case(
            "validate-study --out FOLDER",
            "validate-study --seeds 1 --out folder",
            "--out folder: a file was expected",
            Setup::Folder,
        ),
    ]
}

/// Names in `dir` (sorted).
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Run one case in a fresh folder; return a description of what went wrong, if anything.
fn run(c: &Case) -> Option<String> {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    match &c.setup {
        Setup::None => {}
        Setup::Data(csv, rig) => {
            std::fs::create_dir(d.join("data")).expect("mkdir");
            std::fs::write(d.join("data/rig.toml"), rig).expect("write rig");
            std::fs::write(d.join("data/c.csv"), csv).expect("write csv");
        }
        Setup::File => std::fs::write(d.join("file.txt"), "keep me\n").expect("write"),
        Setup::Folder => std::fs::create_dir(d.join("folder")).expect("mkdir"),
    }
    let before = entries(d);
    let out = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args(c.args.split_whitespace())
        .current_dir(d)
        .output()
        .expect("the geardyn binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    let mut problems = Vec::new();
    if out.status.success() {
        problems.push("exit status 0".to_string());
    }
    if err.contains("panicked") {
        problems.push("panicked".to_string());
    }
    if !err.contains(&c.needle) {
        problems.push(format!("message does not contain '{}'", c.needle));
    }
    if err.matches("error:").count() != 1 {
        problems.push("not exactly one error message".to_string());
    }
    if !out.stdout.is_empty() {
        problems.push("wrote to standard output".to_string());
    }
    let after = entries(d);
    if after != before {
        problems.push(format!("folder changed: {before:?} -> {after:?}"));
    }
    if matches!(c.setup, Setup::File)
        && std::fs::read_to_string(d.join("file.txt")).ok().as_deref() != Some("keep me\n")
    {
        problems.push("file.txt changed".to_string());
    }
    if matches!(c.setup, Setup::Folder) && !entries(&d.join("folder")).is_empty() {
        problems.push("wrote into folder/".to_string());
    }
    (!problems.is_empty()).then(|| format!("{}: {} (stderr: {err})", c.name, problems.join("; ")))
}

#[test]
fn bad_inputs_fail_cleanly_and_write_nothing() {
    let cases = table();
    assert!(cases.len() >= 40, "{} cases", cases.len());
    let failures: Vec<String> = cases.iter().filter_map(run).collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// Ctrl-C during a long run: exit status 130, and the staged outputs, scratch folder and
/// per-seed file under construction are removed (nothing half-written is left).
#[test]
fn interrupt_leaves_nothing_behind() {
    let dir = tempfile::tempdir().expect("temp dir");
    let child = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args([
            "validate-study",
            "--seeds",
            "2000",
            "--out",
            "out/summary.json",
        ])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    // Long enough for the study to have written its scratch set and first seeds (2000 seeds
    // take minutes).
    std::thread::sleep(std::time::Duration::from_secs(3));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let out = child.wait_with_output().expect("waits");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    let left = entries(&dir.path().join("out"));
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// The limits are in `--help`.
#[test]
fn limits_are_in_help() {
    for (cmd, text) in [
        ("simulate", "[0.001, 100]"),
        ("simulate", "1 to 100000"),
        ("basins", "at most 501"),
        ("hbm", "1 to 128"),
        ("study", "2 to 2001"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_geardyn"))
            .args([cmd, "--help"])
            .output()
            .expect("runs");
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(help.contains(text), "{cmd} --help lacks '{text}':\n{help}");
    }
}

/// A steady state cut by its transient budget says so (`"settled": false` and a warning) and is
/// not classified as aperiodic or chaotic (issue 22).
#[test]
fn unsettled_steady_state_is_reported() {
    let out = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args([
            "simulate", "--fm", "0.1", "--fah", "0.2", "--zeta", "0.001", "--omega", "100",
            "--json",
        ])
        .output()
        .expect("runs");
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["settled"], serde_json::json!(false));
    assert_eq!(v["motion"], serde_json::json!("unsettled"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("WARNING: not settled"));
}

/// `--out DIR` receives the outputs once they are all written, next to what DIR already held,
/// and no staging folder is left.
#[test]
fn outputs_are_merged_into_an_existing_folder() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).expect("mkdir");
    std::fs::write(out.join("notes.txt"), "mine\n").expect("write");
    let o = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args([
            "hbm",
            "--fm",
            "0.1",
            "--fah",
            "0.05",
            "--zeta",
            "0.05",
            "--omega",
            "0.5:0.7:0.1",
            "--out",
            "out",
        ])
        .current_dir(dir.path())
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        entries(&out),
        ["hbm.csv", "hbm.png", "hbm.svg", "notes.txt"],
        "outputs beside the user's file"
    );
    assert_eq!(entries(dir.path()), ["out"], "no staging folder left");
}
