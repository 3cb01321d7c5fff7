//! The reproduction's report: REPRODUCTION.md and index.html (claim table, verdict counts,
//! figure index), claims.json and claims.csv, after every figure and study output.

use super::artifacts::{write_artifact, Artifact, FigureEntry};
use super::claims::{verdict_counts, Claim};
use super::Reproduction;
use crate::error::{GearError, Result};
use crate::report::html::Page;
use std::path::{Path, PathBuf};

/// Sub-folder of the studies' outputs (Figs 15-18, 24-29).
pub const STUDY_DIR: &str = "sec6-8-studies";

fn entry(figure: &str, what: &str, files: &[String], note: &str) -> FigureEntry {
    FigureEntry {
        figure: figure.into(),
        what: what.into(),
        files: files.to_vec(),
        note: note.into(),
    }
}

/// Every figure of the paper with the files (PNG + SVG, stem given) that reproduce it.
pub fn figure_index() -> Vec<FigureEntry> {
    let s3 = |f: &str| format!("{}/{f}", super::sec3::DIR);
    let s4 = |f: &str| format!("{}/{f}", super::sec4_6::DIR);
    let st = |d: &str, f: &str| format!("{STUDY_DIR}/{d}/{f}");
    let v = |f: &str| format!("{}/{f}", super::sec7::DIR);
    vec![
        entry(
            "1",
            "gear pair model (schematic)",
            &[],
            "a drawing, no result to compute; the model is eq. 3",
        ),
        entry(
            "2",
            "phase planes, F_hat 0.5",
            &[s3("fig02-phase-planes")],
            "exact simulation, every attractor of the IC grid",
        ),
        entry(
            "3",
            "domains of attraction, Omega 0.5",
            &[s3("fig03-basins")],
            "basin map",
        ),
        entry(
            "4",
            "chaos: time history and Poincare map",
            &[s3("fig04-chaos")],
            "exact simulation, Omega 1.0",
        ),
        entry(
            "5",
            "phase planes, F_hat 2",
            &[s3("fig05-phase-planes")],
            "exact simulation",
        ),
        entry(
            "6",
            "domains of attraction, F_hat 2, Omega 0.6",
            &[s3("fig06-basins")],
            "basin map",
        ),
        entry(
            "7",
            "time histories for F_hat 0.75, 1, 1.5",
            &[s3("fig07-time-histories")],
            "chaotic set (else the dominant attractor) at Omega 1.0, plus F_hat 0.5",
        ),
        entry(
            "8",
            "time histories for zeta 0.05, 0.1",
            &[s3("fig08-time-histories")],
            "period-8 (if found) and period-2 attractors",
        ),
        entry(
            "9",
            "impact regimes (illustration)",
            &[s3("fig09-impact-regimes")],
            "the three coexisting attractors of Fig. 2(b)",
        ),
        entry(
            "10",
            "typical HB response q_a, q_m",
            &[s4("fig10-df-response")],
            "df-exact, F_m 0.1, F_hat 0.5, zeta 0.02",
        ),
        entry(
            "11",
            "theory vs simulation, F_hat 2",
            &[s4("fig11-compare")],
            "df-exact, AFT, sweeps, attractors",
        ),
        entry(
            "12",
            "theory vs simulation, F_hat 0.5",
            &[s4("fig12-compare")],
            "df-exact, AFT, sweeps, attractors",
        ),
        entry(
            "13",
            "theory vs carried simulation",
            &[s4("fig13-carried-sweep")],
            "df-exact and the sweep carrying the last state",
        ),
        entry(
            "14",
            "case III domains, zeta 0.02, 0.03 (0.04)",
            &[
                s4("fig14a-case3-basins"),
                s4("fig14b-case3-basins"),
                s4("fig14c-case3-basins"),
            ],
            "basin maps",
        ),
        entry(
            "15",
            "q_a for F_hat 10, 2, 1, 0.5",
            &[st("parametric-load", "fig15-qa")],
            "df-exact",
        ),
        entry(
            "16",
            "q_m for F_hat 10, 2, 1, 0.5",
            &[st("parametric-load", "fig16-qm")],
            "df-exact",
        ),
        entry(
            "17",
            "q_a for F_hat 10, 4, 2, 1 (F_ah 0.05)",
            &[
                st("parametric-mean", "fig17-qa"),
                st("parametric-mean", "fig17-qm"),
            ],
            "df-exact",
        ),
        entry(
            "18",
            "q_a for zeta 0.025-0.1",
            &[st("damping", "fig18-qa"), st("damping", "fig18-qm")],
            "df-exact",
        ),
        entry(
            "19",
            "Munro, design load",
            &[v("munro/load_3780")],
            "SYNTHETIC data (shipped data/munro)",
        ),
        entry(
            "20",
            "Munro, 3/4 design load",
            &[v("munro/load_2835")],
            "SYNTHETIC data",
        ),
        entry(
            "21",
            "Munro, 1/2 design load",
            &[v("munro/load_1890")],
            "SYNTHETIC data",
        ),
        entry(
            "22",
            "Munro, 1/4 design load",
            &[v("munro/load_945")],
            "SYNTHETIC data",
        ),
        entry(
            "23",
            "Kubo, dynamic factor",
            &[v("kubo/dynamic_factor")],
            "SYNTHETIC data (shipped data/kubo)",
        ),
        entry(
            "24",
            "eq. 5 vs eq. 4, F_hat 10, 2",
            &[
                st("excitation", "fig24-25-qa"),
                st("excitation", "fig24-25-qm"),
            ],
            "AFT H 15 and df-exact",
        ),
        entry(
            "25",
            "eq. 5 vs eq. 4, F_hat 1, 0.5",
            &[
                st("excitation", "fig24-25-qa"),
                st("excitation", "fig24-25-qm"),
            ],
            "AFT H 15 and df-exact",
        ),
        entry(
            "26",
            "three STE harmonics, simultaneous and separate",
            &[st("superposition", "fig26-27-superposition")],
            "simulation sweeps",
        ),
        entry(
            "27",
            "superposition with phases",
            &[st("superposition", "fig26-27-superposition")],
            "simulation sweeps",
        ),
        entry(
            "28",
            "HB superposition of three harmonics",
            &[st("superposition-hb", "fig28-superposition-hb")],
            "df-exact superposed vs AFT simultaneous",
        ),
        entry(
            "29",
            "torque + STE, Omega_h = 2 Omega_T",
            &[st("combined", "fig29-combined")],
            "AFT superposed vs simultaneous",
        ),
    ]
}

/// [`figure_index`] with Figs 19-22 pointing at the Munro curves actually validated (design
/// load first, then decreasing loads), for data sets other than the shipped one.
fn figure_index_of(r: &Reproduction) -> Vec<FigureEntry> {
    let mut index = figure_index();
    let loads: Vec<f64> = r
        .artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Munro { result, .. } => {
                let mut l: Vec<f64> = result.loads.iter().map(|l| l.load_n).collect();
                l.sort_by(|a, b| b.total_cmp(a));
                Some(l)
            }
            _ => None,
        })
        .unwrap_or_default();
    for (k, e) in index
        .iter_mut()
        .filter(|e| matches!(e.figure.as_str(), "19" | "20" | "21" | "22"))
        .enumerate()
    {
        e.files = loads
            .get(k)
            .map(|l| vec![format!("{}/munro/load_{l:.0}", super::sec7::DIR)])
            .unwrap_or_default();
    }
    index
}

/// One CSV field, quoted.
fn quote(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "'"))
}

/// claims.csv text.
pub fn claims_csv(claims: &[Claim]) -> String {
    let mut s = String::from("id,section,figure,paper,geardyn,verdict,explanation\n");
    for c in claims {
        s.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            c.id,
            quote(&c.section),
            quote(&c.figure),
            quote(&c.paper),
            quote(&c.geardyn),
            c.verdict.name(),
            quote(&c.explanation)
        ));
    }
    s
}

/// Markdown-safe cell text (no pipes, no line breaks).
fn cell(s: &str) -> String {
    s.replace('|', "/").replace('\n', " ")
}

/// Write every output, then the report; returns the files written (sorted).
pub fn write_reproduction(r: &Reproduction, out: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out).map_err(GearError::io(out))?;
    let mut written = Vec::new();
    for a in &r.artifacts {
        written.extend(write_artifact(a, out)?);
    }
    let counts = verdict_counts(&r.claims);
    let count_text = counts
        .iter()
        .map(|(v, n)| format!("{} {n}", v.name()))
        .collect::<Vec<_>>()
        .join(", ");
    let res = &r.resolution;
    let banner = "The Sec. 7 rows and Figs 19-23 use the shipped SYNTHETIC data sets (data/munro, data/kubo made by geardyn synth), not Munro's or Kubo's measurements.";
    let mut page = Page::new(
        "Reproduction of Kahraman & Singh (1990), Non-linear dynamics of a spur gear pair",
        banner,
        true,
    );
    page.paragraph(&format!(
        "Generated by `geardyn reproduce{}` (geardyn {}). Every value below was computed in this run; nothing is typed in by hand. Resolution `{}`: attractor searches on a {n}x{n} grid of initial conditions in [-2, 2]^2, basin maps {b}x{b}, comparisons with Omega step {} and a {c}x{c} IC grid, study grids {}.",
        if res.name == "quick" { " --quick" } else { "" },
        env!("CARGO_PKG_VERSION"),
        res.name,
        res.omega_step,
        res.study_points.map_or("at their defaults".to_string(), |p| format!("of {p} frequencies")),
        n = res.ic_n,
        b = res.basin_n,
        c = res.compare_ic_n,
    ));
    page.paragraph(&format!(
        "Verdicts ({} claims): {count_text}.",
        r.claims.len()
    ));
    page.paragraph("Verdicts: agree = geardyn's number supports the claim within the stated tolerance; differ = it does not; more than the paper = the paper's attractors plus further coexisting ones, each found again by the independent DOP853 integrator (rtol 1e-11) with q_a within 1e-6 in the same run; beyond the paper (transient chaos) = what the paper saw holds over the few hundred periods it integrated, but followed further (up to 40,000 periods) the chaotic set loses its trajectories to a periodic orbit at a measured escape rate: a chaotic transient, not a strange attractor, a finding of geardyn beyond the paper (the rate is measured again with DOP853 in the same run); not testable (synthetic data) = a claim about agreement with measurements, which synthetic data cannot test.");
    page.heading("Claims");
    let rows: Vec<Vec<String>> = r
        .claims
        .iter()
        .map(|c| {
            vec![
                c.id.clone(),
                cell(&format!("{} ({})", c.section, c.figure)),
                cell(&c.paper),
                cell(&c.geardyn),
                c.verdict.name().to_string(),
                cell(&c.explanation),
            ]
        })
        .collect();
    page.table(
        &[
            "id",
            "section (figure)",
            "paper",
            "geardyn (this run)",
            "verdict",
            "explanation",
        ],
        &rows,
    );
    for t in &r.tables {
        page.heading(&t.heading);
        page.paragraph(&t.intro);
        let header: Vec<&str> = t.header.iter().map(String::as_str).collect();
        let rows: Vec<Vec<String>> = t
            .rows
            .iter()
            .map(|row| row.iter().map(|c| cell(c)).collect())
            .collect();
        page.table(&header, &rows);
    }
    page.heading("Figures");
    let index = figure_index_of(r);
    let frows: Vec<Vec<String>> = index
        .iter()
        .map(|e| {
            vec![
                format!("Fig. {}", e.figure),
                e.what.clone(),
                if e.files.is_empty() {
                    "-".into()
                } else {
                    e.files
                        .iter()
                        .map(|f| format!("{f}.png, {f}.svg"))
                        .collect::<Vec<_>>()
                        .join("; ")
                },
                e.note.clone(),
            ]
        })
        .collect();
    page.table(&["paper", "shows", "geardyn files", "how"], &frows);
    let mut shown: Vec<&String> = Vec::new();
    for e in &index {
        for f in &e.files {
            if !shown.contains(&f) {
                shown.push(f);
                page.image(
                    &format!("{f}.png"),
                    &format!("Fig. {}: {}", e.figure, e.what),
                );
            }
        }
    }
    let (html, md) = page.finish("geardyn reproduction of Kahraman & Singh (1990)");
    for (name, text) in [
        ("REPRODUCTION.md", md),
        ("index.html", html),
        ("claims.csv", claims_csv(&r.claims)),
        (
            "claims.json",
            format!(
                "{}\n",
                serde_json::to_string_pretty(&serde_json::json!({
                    "resolution": res.name,
                    "verdict_counts": counts.iter().map(|(v, n)| (v.name().to_string(), *n)).collect::<std::collections::BTreeMap<_, _>>(),
                    "claims": r.claims,
                    "tables": r.tables,
                }))
                .map_err(|e| GearError::Numerical(format!("JSON: {e}")))?
            ),
        ),
    ] {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(GearError::io(&p))?;
        written.push(p);
    }
    written.sort();
    Ok(written)
}
