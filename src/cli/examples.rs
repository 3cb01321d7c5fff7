//! The examples at the end of each command's `--help`, run from the repository root (the
//! shipped `data/` sets). A test parses every example line with the command definitions, so an
//! option renamed or removed fails it.

pub const SIMULATE: &str = "\
Examples:
  geardyn simulate --fm 0.1 --fah 0.2 --zeta 0.02 --omega 1.0 --out fig4   # chaos (Fig. 4)
  geardyn simulate --rig data/munro/rig.toml --load-n 1890 --ste-um 2.5 --zeta 0.0175 --omega-n-hz 1600 --speed-rpm 3000 --json";

pub const ATTRACTORS: &str = "\
Examples:
  geardyn attractors --fm 0.1 --fah 0.2 --zeta 0.02 --omega 0.5   # three period-1 attractors (Sec. 3)
  geardyn attractors --rig data/munro/rig.toml --load-n 945 --ste-um 3.5 --zeta 0.0175 --omega-n-hz 1600 --speed-rpm 3000";

pub const BASINS: &str = "\
Examples:
  geardyn basins --fm 0.1 --fah 0.2 --zeta 0.02 --omega 0.5 --out fig3   # Fig. 3, 101 x 101, ~4 s
  geardyn basins --rig data/munro/rig.toml --load-n 945 --ste-um 3.5 --zeta 0.0175 --omega-n-hz 1600 --speed-rpm 3000 --ic-grid -2:2:51 --out basins-945";

pub const SWEEP: &str = "\
Examples:
  geardyn sweep --fm 0.1 --fah 0.05 --zeta 0.05 --omega 0.2:1.6:0.01 --direction both > sweep.csv
  geardyn sweep --rig data/munro/rig.toml --load-n 1890 --speed-rpm 1000:5000:50 --ste-um 2.5 --zeta 0.0175 --omega-n-hz 1600 > sweep-1890.csv";

pub const HBM: &str = "\
Examples:
  geardyn hbm --fm 0.1 --fah 0.05 --zeta 0.05 --omega 0.2:1.6:0.01 --method aft --harmonics 15 > aft.csv
  geardyn hbm --fm 0.1 --fah 0.05 --fat 0.05 --zeta 0.05 --omega 0.2:1.6:0.01 > both.csv   # STE and torque (eq. 4)
  geardyn hbm --rig data/munro/rig.toml --load-n 1890 --speed-rpm 1000:5000:20 --ste-um 2.5 --zeta 0.0175 --omega-n-hz 1600";

pub const COMPARE: &str = "\
Examples:
  geardyn compare --fm 0.1 --fah 0.05 --zeta 0.05 --omega 0.2:1.6:0.02 --out compare   # Figs 11-13, ~1 min
  geardyn compare --rig data/munro/rig.toml --load-n 1890 --speed-rpm 1000:5000:100 --ste-um 2.5 --zeta 0.0175 --omega-n-hz 1600";

pub const BIFURCATION: &str = "\
Examples:
  geardyn bifurcation --fm 0.1 --fah 0.2 --zeta 0.02 --vary omega --range 0.3:1.5:0.02 --out bif   # ~30 s
  geardyn bifurcation --fm 0.1 --fah 0.2 --omega 1.0 --vary zeta --range 0.02:0.06:0.002 --mode grid --out bif-zeta";

pub const ESCAPE: &str = "\
Example:
  geardyn escape --fm 0.1 --fah 0.2 --zeta 0.02 --omega 1.0 --out escape-fig4   # Fig. 4's chaotic transient, ~1 min";

pub const STUDY: &str = "\
Example:
  geardyn study damping --out study   # Fig. 18, a few seconds";

pub const REPRODUCE: &str = "\
Example:
  geardyn reproduce --quick --out /tmp/q   # ~15 s; without --quick about 2 minutes";

pub const MESH: &str = "\
Example:
  geardyn mesh --rig data/munro/rig.toml --load-n 945:4725:945 --tip-relief-design-load-n 3780 --out mesh";

pub const VALIDATE: &str = "\
Examples:
  geardyn validate munro                            # the shipped set: fits/munro.json, reports/munro/
  geardyn validate munro --data my-rig --fits my-fits --reports my-reports
  geardyn validate kubo";

pub const VALIDATE_MUNRO: &str = "\
Examples:
  geardyn validate munro                            # the shipped set: fits/munro.json, reports/munro/
  geardyn validate munro --data my-rig --fits my-fits --reports my-reports
  geardyn validate munro --data data/munro-geometry --ste geometry --fits fits/geometry --reports reports/geometry";

pub const VALIDATE_KUBO: &str = "\
Examples:
  geardyn validate kubo                             # the shipped set: fits/kubo.json, reports/kubo/
  geardyn validate kubo --data my-envelope --fit whole   # zeta and omega_n from the whole curve (~10 s)
  geardyn validate kubo --hold-ste                  # the STE held at rig.toml's value";

pub const INIT_DATA: &str = "\
Example:
  geardyn init-data my-rig   # then fill in my-rig/rig.toml and my-rig/dte.csv and run
  geardyn validate munro --data my-rig";

pub const SYNTH: &str = "\
Examples:
  geardyn synth munro --out /tmp/m                          # data/munro's truth again (its 15 chaotic points at 945 N differ: that set is from the first build)
  geardyn synth munro --ste2-ratio 0.4 --out /tmp/munro-r2  # hide a 2nd STE harmonic (40%)";

pub const BENCH: &str = "\
Example:
  geardyn bench   # under half a minute; prints the timings";

pub const DIGITIZE: &str = "\
Example:
  geardyn digitize --image fig21.png --x-cal 212:1000:1893:4000 --y-cal 1405:0:260:60 --color 000000 --tolerance 80 --mode markers --crop 215:250:1890:1400 --columns speed_rpm,dte_pp_um --const load_n=1890 --out data/my-digitized/load_1890.csv";

pub const DISCOVER: &str = "\
Example:
  geardyn discover --data data/munro --out discover   # names the effect the model misses, if any";

pub const DISCOVER_STUDY: &str = "\
Example:
  geardyn discover-study --hidden none --seeds 20   # null rate over 20 seeds";

pub const VALIDATE_STUDY: &str = "\
Example:
  geardyn validate-study --noise relative --grid nonuniform --seeds 200   # ~1 min, coverage table";

/// Every example text, for the test.
#[cfg(test)]
pub const ALL: [&str; 21] = [
    SIMULATE,
    ATTRACTORS,
    BASINS,
    SWEEP,
    HBM,
    COMPARE,
    BIFURCATION,
    ESCAPE,
    STUDY,
    REPRODUCE,
    MESH,
    VALIDATE,
    VALIDATE_MUNRO,
    VALIDATE_KUBO,
    INIT_DATA,
    SYNTH,
    BENCH,
    DIGITIZE,
    DISCOVER,
    DISCOVER_STUDY,
    VALIDATE_STUDY,
];

#[cfg(test)]
mod tests {
    use super::super::Cli;
    use clap::Parser;

    /// Each example line parses (options and values), without running the command.
    #[test]
    fn examples_parse() {
        let mut lines = 0;
        for text in super::ALL {
            for line in text
                .lines()
                .filter(|l| l.trim_start().starts_with("geardyn "))
            {
                let command = line.split('#').next().unwrap_or("");
                let command = command.split('>').next().unwrap_or("");
                let words: Vec<&str> = command.split_whitespace().collect();
                if let Err(e) = Cli::try_parse_from(&words) {
                    panic!("example does not parse: {line}\n{e}");
                }
                lines += 1;
            }
        }
        assert!(lines >= 25, "{lines} example lines");
    }
}
