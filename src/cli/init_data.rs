//! `geardyn init-data DIR`: a new data set folder with a commented rig.toml template and a CSV
//! file holding the header, for one's own measurements.

use super::common::{check_out_dir, commit, stage, write_text};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::data::{csv_template, rig_template, Layout};
use std::path::{Path, PathBuf};

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// The new data set folder (created; a folder that already has a rig.toml is refused).
    dir: PathBuf,
    /// Layout of the curves: munro (pp DTE in µm against speed, one curve per load) or kubo
    /// (dynamic-factor envelope against speed at one load).
    #[arg(long, value_enum, default_value_t = CliLayout::Munro)]
    layout: CliLayout,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum CliLayout {
    Munro,
    Kubo,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("DIR", &a.dir)?;
    check_parent_exists(&a.dir)?;
    let layout = match a.layout {
        CliLayout::Munro => Layout::Munro,
        CliLayout::Kubo => Layout::Kubo,
    };
    for name in ["rig.toml", layout.csv_name()] {
        if a.dir.join(name).exists() {
            anyhow::bail!(
                "{} exists: init-data writes a new data set and overwrites nothing",
                a.dir.join(name).display()
            );
        }
    }
    let stage = stage("DIR", &a.dir)?;
    let d = stage.dir().to_path_buf();
    write_text(&d.join("rig.toml"), &rig_template(layout))?;
    write_text(&d.join(layout.csv_name()), csv_template(layout))?;
    let written = commit(stage, &[d.join("rig.toml"), d.join(layout.csv_name())])?;
    for p in &written {
        eprintln!("wrote {}", p.display());
    }
    eprintln!(
        "next: fill in the REQUIRED lines of rig.toml, add your points to {}, then run\n  \
         geardyn validate {} --data {}",
        layout.csv_name(),
        layout.command(),
        a.dir.display()
    );
    Ok(())
}

/// init-data makes one new folder, in a folder that exists: a mistyped path would otherwise
/// create a tree of folders without a word.
fn check_parent_exists(dir: &Path) -> anyhow::Result<()> {
    if dir.is_dir() {
        return Ok(());
    }
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        anyhow::bail!(
            "DIR {}: its folder {} does not exist; init-data makes one new folder in an existing \
             one (create {} first if it is meant)",
            dir.display(),
            parent.display(),
            parent.display()
        );
    }
    Ok(())
}
