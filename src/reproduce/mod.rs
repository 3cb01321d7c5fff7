//! `geardyn reproduce`: every figure of Kahraman & Singh (1990) regenerated, and a claim-by-claim
//! reproduction report whose every number is computed in the same run.
//!
//! | file | what |
//! |---|---|
//! | `claims.rs` | the claim table types and verdicts |
//! | `artifacts.rs` | the computed figures / studies / validation reports, written after the run |
//! | `summary_values.rs` | numbers read from the studies' JSON summaries |
//! | `attractor_set.rs` | attractor searches, matching against the paper, DOP853 confirmation |
//! | `steady_figures.rs` | time history / phase plane / Poincare figures of a steady state |
//! | `sec3.rs` | Figs 2-9 and the Sec. 3 claims (simulation) |
//! | `sec3_transients.rs` | the chaos claims and the Sec. 3 sets followed past the paper's time scale |
//! | `normalisation.rs` | the case III claims under each reading of the forcing (a table) |
//! | `sec4_6.rs` | Figs 10-14 and the Secs 4-6 claims (harmonic balance, comparison, studies) |
//! | `sec7.rs` | Figs 19-23 on the shipped data (labelled synthetic) |
//! | `sec8.rs` | the Sec. 8 claims (Figs 24-29 come from `src/study`) |
//! | `report.rs` | REPRODUCTION.md, index.html, claims.json / claims.csv, figure index |
//!
//! Everything is computed before the first file is written; outputs hold no timestamps or host
//! names and do not depend on the thread count (parallel results are collected in order).

mod artifacts;
mod attractor_set;
mod claims;
mod normalisation;
mod report;
mod sec3;
mod sec3_transients;
mod sec4_6;
mod sec7;
mod sec8;
mod steady_figures;
mod summary_values;

pub use artifacts::{write_artifact, Artifact, FigureEntry};
pub use attractor_set::{describe as describe_attractor, name as attractor_name};
pub use claims::{verdict_counts, Claim, ReportTable, Verdict};
pub use report::{figure_index, write_reproduction};
pub use steady_figures::{steady_figures, SteadyFigures};

use crate::error::Result;
use crate::progress::Progress;
use crate::study::{run_study, StudyName, StudyOptions, StudyOutput};
use crate::validate::{KuboOptions, MunroOptions};
use rayon::prelude::*;
use std::path::PathBuf;

/// Resolution of a reproduction run.
#[derive(Clone, Debug)]
pub struct Resolution {
    /// Name shown in the report ("full" or "quick").
    pub name: &'static str,
    /// Initial conditions per axis of the attractor searches behind the claims (the paper's
    /// increment 0.2 on [-2, 2] is 21).
    pub ic_n: usize,
    /// Initial conditions per axis of the basin maps (Figs 3, 6, 14).
    pub basin_n: usize,
    /// Omega step of the comparisons of Figs 11-13.
    pub omega_step: f64,
    /// Omega step of S3-07's scan for periodic windows over 1.0-1.5 (the period-3 window of
    /// Fig. 4's parameters is about 0.08 wide).
    pub window_step: f64,
    /// Initial conditions per axis of the comparisons' attractor search.
    pub compare_ic_n: usize,
    /// Frequencies of the studies' grids (`None`: each study's default).
    pub study_points: Option<usize>,
    /// Munro pipeline settings.
    pub munro: MunroOptions,
    /// Kubo pipeline settings.
    pub kubo: KuboOptions,
}

impl Resolution {
    /// The full reproduction (paper's IC increment, Omega step 0.01, studies at default grids).
    pub fn full() -> Self {
        Resolution {
            name: "full",
            ic_n: 21,
            basin_n: 101,
            omega_step: 0.01,
            window_step: 0.01,
            compare_ic_n: 11,
            study_points: None,
            munro: MunroOptions::default(),
            kubo: KuboOptions::default(),
        }
    }

    /// A reduced run for tests and CI (coarse grids, few points): the same figures and claims.
    pub fn quick() -> Self {
        Resolution {
            name: "quick",
            ic_n: 9,
            basin_n: 21,
            omega_step: 0.05,
            window_step: 0.04,
            compare_ic_n: 3,
            study_points: Some(57),
            munro: MunroOptions {
                dense_points: 41,
                attractor_speeds: 5,
                ic_per_axis: 3,
                ..MunroOptions::default()
            },
            kubo: KuboOptions {
                dense_points: 61,
                ..KuboOptions::default()
            },
        }
    }
}

/// Options of [`reproduce`].
#[derive(Clone, Debug)]
pub struct ReproduceOptions {
    /// Grid sizes.
    pub resolution: Resolution,
    /// Folder holding the `munro` and `kubo` data sets.
    pub data_dir: PathBuf,
}

/// Everything a reproduction computed.
#[derive(Clone, Debug)]
pub struct Reproduction {
    /// The resolution used.
    pub resolution: Resolution,
    /// Claim rows, by section.
    pub claims: Vec<Claim>,
    /// Evidence tables behind some claims, written after the claim table.
    pub tables: Vec<ReportTable>,
    /// Outputs to write (figures, studies, validation reports).
    pub artifacts: Vec<Artifact>,
}

/// Number of progress units of a run.
pub fn progress_units(res: &Resolution) -> Result<u64> {
    // Searches, one DOP853 stage, S3-07's window scan, two comparisons, the studies, two
    // validations.
    Ok(sec3::plan(res)?.len() as u64 + 1 + 1 + 2 + StudyName::ALL.len() as u64 + 2)
}

/// Compute every figure and claim of the paper.
pub fn reproduce(opts: &ReproduceOptions, progress: &dyn Progress) -> Result<Reproduction> {
    let res = &opts.resolution;
    // Bad data fail before the long computation starts.
    let data = sec7::load(&opts.data_dir)?;
    progress.start(progress_units(res)?, "reproduce");
    // The independent computations run side by side (each is parallel inside); results are
    // collected in a fixed order, so the outputs do not depend on the schedule.
    let run_studies = || -> Result<Vec<StudyOutput>> {
        let studies: Vec<Result<StudyOutput>> = StudyName::ALL
            .par_iter()
            .map(|&name| {
                let r = run_study(
                    name,
                    &StudyOptions {
                        points: res.study_points,
                    },
                );
                progress.advance(1);
                r
            })
            .collect();
        studies.into_iter().collect()
    };
    let (searches, (comparisons, (studies, validation))) = rayon::join(
        || sec3::run_searches(res, progress),
        || {
            rayon::join(
                || sec4_6::run_comparisons(res, progress),
                || rayon::join(run_studies, || sec7::build(res, data, progress)),
            )
        },
    );
    let (searches, comparisons, studies, (c7, f7)) =
        (searches?, comparisons?, studies?, validation?);
    let (c3, f3, confirmations, t3) = sec3::build(res, &searches, progress)?;
    let (c46, f46) = sec4_6::build(res, &comparisons, &searches, &confirmations, &studies)?;
    let c8 = sec8::claims(&studies)?;
    let mut tables = t3;
    tables.push(normalisation::normalisation_table()?);
    progress.finish();
    let mut artifacts = f3;
    artifacts.extend(f46);
    artifacts.extend(studies.into_iter().map(|s| Artifact::Study {
        dir: report::STUDY_DIR.into(),
        output: Box::new(s),
    }));
    artifacts.extend(f7);
    let mut claims = c3;
    claims.extend(c46);
    claims.extend(c7);
    claims.extend(c8);
    Ok(Reproduction {
        resolution: res.clone(),
        claims,
        tables,
        artifacts,
    })
}
