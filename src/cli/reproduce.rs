//! `geardyn reproduce`: every figure of the paper and the claim-by-claim reproduction report.

use super::common::{check_out_dir, commit, print_text, stage};
use super::progress_bar::Bar;
use clap::Args as ClapArgs;
use geardyn::reproduce::{
    reproduce, verdict_counts, write_reproduction, ReproduceOptions, Resolution,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Output folder (figures, studies, validation reports, REPRODUCTION.md, index.html).
    #[arg(long, default_value = "reports/paper")]
    out: PathBuf,
    /// Reduced resolution (coarse IC grids, few frequencies): the same figures and claims in
    /// seconds, as the test suite runs it.
    #[arg(long)]
    quick: bool,
    /// Folder holding the munro/ and kubo/ data sets (the shipped ones: data/ of the
    /// repository).
    #[arg(long, default_value = "data")]
    data: PathBuf,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    for set in ["munro", "kubo"] {
        let rig = a.data.join(set).join("rig.toml");
        if !rig.is_file() {
            anyhow::bail!(
                "--data {}: {} not found: reproduce validates against the shipped munro/ and \
                 kubo/ data sets; run it from the geardyn repository or give their parent folder \
                 with --data",
                a.data.display(),
                rig.display()
            );
        }
    }
    let opts = ReproduceOptions {
        resolution: if a.quick {
            Resolution::quick()
        } else {
            Resolution::full()
        },
        data_dir: a.data,
    };
    let r = reproduce(&opts, &Bar::new())?;
    // Staged: a failure while writing leaves the output folder as it was.
    let stage = stage("--out", &a.out)?;
    let written = write_reproduction(&r, stage.dir())?;
    let written = commit(stage, &written)?;
    let mut text = format!("{} claims: ", r.claims.len());
    text.push_str(
        &verdict_counts(&r.claims)
            .iter()
            .map(|(v, n)| format!("{} {n}", v.name()))
            .collect::<Vec<_>>()
            .join(", "),
    );
    text.push_str(&format!(
        "\nwrote {} files; report {}\n",
        written.len(),
        a.out.join("REPRODUCTION.md").display()
    ));
    print_text(&text)
}
