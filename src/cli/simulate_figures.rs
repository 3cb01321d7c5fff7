//! Figures of `geardyn simulate --out DIR`: time history, phase plane and Poincare map of the
//! steady state (as the paper's Figs 2, 4, 5, 7, 8), with the sampled history as CSV. The figures
//! are built by the library ([`geardyn::reproduce::steady_figures`]); this writes them.

use super::common::{commit, stage, write_text};
use geardyn::plot::write_xy;
use geardyn::reproduce::steady_figures;
use geardyn::sim::{PeriodFlow, SteadyState};
use std::path::{Path, PathBuf};

/// Write the steady state's figures and CSV into `dir`; returns the files written.
pub fn write(
    flow: &dyn PeriodFlow,
    s: &SteadyState,
    caption: &str,
    dir: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let f = steady_figures(flow, s, caption)?;
    // Staged: the folder receives the files only when all of them were written.
    let stage = stage("--out", dir)?;
    let d = stage.dir().to_path_buf();
    let mut written = Vec::new();
    written.extend(write_xy(&f.history, &d.join("time_history"))?);
    written.extend(write_xy(&f.phase, &d.join("phase_plane"))?);
    written.extend(write_xy(&f.poincare, &d.join("poincare"))?);
    write_text(&d.join("time_history.csv"), &f.csv)?;
    written.push(d.join("time_history.csv"));
    commit(stage, &written)
}
