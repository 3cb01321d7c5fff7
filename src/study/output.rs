//! What a study produces and how it is written: figures (PNG + SVG), `NAME.csv`, `NAME.json`.

use super::figures::Figure;
use crate::error::{GearError, Result};
use crate::hb::{DfSolution, HbPoint};
use crate::model::Impact;
use crate::plot::write_panels;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One computed point of a study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StudyRow {
    /// Curve it belongs to (parameters and method).
    pub series: String,
    /// Excitation frequency Omega (the fundamental).
    pub omega: f64,
    /// Half range of q.
    pub qa: f64,
    /// Mid range of q (`None` where not defined, e.g. a superposition).
    pub qm: Option<f64>,
    /// Impact regime (Fig. 9) when known.
    pub case: Option<Impact>,
    /// Stability when known.
    pub stable: Option<bool>,
    /// Period in forcing periods when known.
    pub period: Option<u32>,
}

impl StudyRow {
    /// A row from a period-1 harmonic-balance (AFT) point.
    pub fn from_hb(series: impl Into<String>, p: &HbPoint) -> Self {
        StudyRow {
            series: series.into(),
            omega: p.omega,
            qa: p.qa,
            qm: Some(p.qm),
            case: Some(p.case),
            stable: p.stable,
            period: Some(1),
        }
    }

    /// A row from a describing-function solution (period 1).
    pub fn from_df(series: impl Into<String>, s: &DfSolution) -> Self {
        StudyRow {
            series: series.into(),
            omega: s.omega,
            qa: s.qa,
            qm: Some(s.qm),
            case: Some(s.case),
            stable: s.stable,
            period: Some(1),
        }
    }
}

/// Everything a study computed.
#[derive(Clone, Debug)]
pub struct StudyOutput {
    /// Study name (file stem of the CSV and JSON).
    pub name: String,
    /// Figures.
    pub figures: Vec<Figure>,
    /// Every computed point.
    pub rows: Vec<StudyRow>,
    /// Findings (JSON).
    pub summary: serde_json::Value,
}

impl StudyOutput {
    /// The CSV text: `study,series,omega,qa,qm,case,stable,period`.
    pub fn csv(&self) -> String {
        let mut s = String::from("study,series,omega,qa,qm,case,stable,period\n");
        for r in &self.rows {
            s.push_str(&format!(
                "{},\"{}\",{},{:.10},{},{},{},{}\n",
                self.name,
                r.series.replace('"', "'"),
                crate::numeric::to_significant(r.omega, 10),
                r.qa,
                r.qm.map_or(String::new(), |v| format!("{v:.10}")),
                r.case.map_or(String::new(), |c| c.case().to_string()),
                r.stable.map_or(String::new(), |b| b.to_string()),
                r.period.map_or(String::new(), |p| p.to_string()),
            ));
        }
        s
    }
}

/// Write the figures, `NAME.csv` and `NAME.json` into `dir`; return the paths written.
pub fn write_outputs(out: &StudyOutput, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(GearError::io(dir))?;
    let mut written = Vec::new();
    for f in &out.figures {
        written.extend(write_panels(
            &f.title,
            &f.panels,
            f.cols,
            &dir.join(&f.name),
        )?);
    }
    let csv = dir.join(format!("{}.csv", out.name));
    std::fs::write(&csv, out.csv()).map_err(GearError::io(&csv))?;
    written.push(csv);
    let json = dir.join(format!("{}.json", out.name));
    let text = serde_json::to_string_pretty(&out.summary)
        .map_err(|e| GearError::Numerical(format!("JSON: {e}")))?;
    std::fs::write(&json, format!("{text}\n")).map_err(GearError::io(&json))?;
    written.push(json);
    Ok(written)
}
