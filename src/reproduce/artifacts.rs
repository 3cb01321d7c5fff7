//! The figure jobs' products: every output of the reproduction is computed into an [`Artifact`]
//! first and written only when the whole run has succeeded.

use crate::data::{KuboData, MunroData};
use crate::error::Result;
use crate::plot::{write_category_map, write_panels, CategoryMap, XyPlot};
use crate::report::{write_kubo_report, write_munro_report, MunroFigures};
use crate::study::{write_outputs, StudyOutput};
use crate::validate::{KuboValidation, MunroValidation};
use std::path::{Path, PathBuf};

/// What is written for one or more of the paper's figures.
#[derive(Clone, Debug)]
pub enum Artifact {
    /// A grid of x-y panels, `dir/stem.png` and `.svg`.
    Panels {
        /// Sub-folder of the output folder.
        dir: String,
        /// File stem.
        stem: String,
        /// Common title.
        title: String,
        /// Panels row by row.
        panels: Vec<XyPlot>,
        /// Panels per row.
        cols: usize,
    },
    /// A basin map, `dir/stem.png` and `.svg`.
    Map {
        /// Sub-folder.
        dir: String,
        /// File stem.
        stem: String,
        /// The map.
        map: CategoryMap,
    },
    /// A study of `src/study` (figures, CSV, JSON) in `dir/NAME/`.
    Study {
        /// Sub-folder.
        dir: String,
        /// The study's output.
        output: Box<StudyOutput>,
    },
    /// The Munro validation report (Figs 19-22) in `dir/munro`, fitted parameters in `dir/fits`.
    Munro {
        /// Sub-folder.
        dir: String,
        /// The data set.
        data: Box<MunroData>,
        /// The validation.
        result: Box<MunroValidation>,
    },
    /// The Kubo validation report (Fig. 23) in `dir/kubo`, fitted parameters in `dir/fits`.
    Kubo {
        /// Sub-folder.
        dir: String,
        /// The data set.
        data: Box<KuboData>,
        /// The validation.
        result: Box<KuboValidation>,
    },
    /// A text file (CSV, JSON).
    Text {
        /// Path relative to the output folder.
        path: String,
        /// Contents.
        text: String,
    },
}

/// A paper figure and the files that reproduce it.
#[derive(Clone, Debug, PartialEq)]
pub struct FigureEntry {
    /// The paper's figure number(s), e.g. "2" or "15".
    pub figure: String,
    /// What the paper's figure shows.
    pub what: String,
    /// geardyn's file(s), relative to the output folder (without extension for PNG+SVG pairs).
    pub files: Vec<String>,
    /// Parameters and method of geardyn's counterpart.
    pub note: String,
}

/// Write one artifact under `out`; returns the files written.
pub fn write_artifact(a: &Artifact, out: &Path) -> Result<Vec<PathBuf>> {
    match a {
        Artifact::Panels {
            dir,
            stem,
            title,
            panels,
            cols,
        } => {
            let d = out.join(dir);
            std::fs::create_dir_all(&d).map_err(crate::error::GearError::io(&d))?;
            write_panels(title, panels, *cols, &d.join(stem))
        }
        Artifact::Map { dir, stem, map } => {
            let d = out.join(dir);
            std::fs::create_dir_all(&d).map_err(crate::error::GearError::io(&d))?;
            write_category_map(map, &d.join(stem))
        }
        Artifact::Study { dir, output } => write_outputs(output, &out.join(dir).join(&output.name)),
        Artifact::Munro { dir, data, result } => {
            let d = out.join(dir);
            write_munro_report(
                data,
                result,
                &MunroFigures::default(),
                &d.join("fits"),
                &d.join("munro"),
            )
        }
        Artifact::Kubo { dir, data, result } => {
            let d = out.join(dir);
            write_kubo_report(data, result, &d.join("fits"), &d.join("kubo"))
        }
        Artifact::Text { path, text } => {
            let p = out.join(path);
            if let Some(parent) = p.parent() {
                std::fs::create_dir_all(parent).map_err(crate::error::GearError::io(parent))?;
            }
            std::fs::write(&p, text).map_err(crate::error::GearError::io(&p))?;
            Ok(vec![p])
        }
    }
}
