//! The reproduction's report: REPRODUCTION.md and index.html (claim table, verdict counts,
//! figure index), claims.json and claims.csv, after every figure and study output.

use super::artifacts::{write_artifact, Artifact, FigureEntry};
use super::claims::{verdict_counts, Claim, Verdict};
use super::Reproduction;
use crate::error::{GearError, Result};
use crate::report::html::{Cell, Page};
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

/// CSS class of a verdict's cell (colours in the report's style sheet).
fn verdict_class(v: Verdict) -> &'static str {
    match v {
        Verdict::Agree => "agree",
        Verdict::Differ => "differ",
        Verdict::MoreThanPaper => "more",
        Verdict::BeyondPaper => "beyond",
        Verdict::NotTestableSynthetic => "untestable",
    }
}

/// What a verdict means.
fn verdict_meaning(v: Verdict) -> &'static str {
    match v {
        Verdict::Agree => "geardyn's number supports the claim within the stated tolerance",
        Verdict::Differ => "geardyn's number does not support the claim; the explanation says how it differs",
        Verdict::MoreThanPaper => "the paper's attractors plus further coexisting ones, each found again by the independent DOP853 integrator (rtol 1e-11) with q_a within 1e-6 in the same run",
        Verdict::BeyondPaper => "what the paper saw holds over the few hundred periods it integrated, but followed further (up to 40,000 periods) the chaotic set loses its trajectories to a periodic orbit at a measured escape rate: a chaotic transient, not a strange attractor, a finding of geardyn beyond the paper (the rate is measured again with DOP853 in the same run)",
        Verdict::NotTestableSynthetic => "a claim about agreement with measurements, which the shipped synthetic data cannot test",
    }
}

/// The paper's figure numbers named in a claim's figure field ("Fig. 15(a), 16(a)" gives 15
/// and 16; "eq. 14, Fig. 15(b)" gives 15; "Sec. 3 text" none): the numbers after the first
/// "Fig", outside parentheses.
pub(crate) fn figure_numbers(field: &str) -> Vec<u32> {
    let Some(at) = field.find("Fig") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let (mut depth, mut num) = (0, String::new());
    for c in field[at..].chars().chain([' ']) {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            d if d.is_ascii_digit() && depth == 0 => {
                num.push(d);
                continue;
            }
            _ => {}
        }
        if let Ok(n) = num.parse::<u32>() {
            if !out.contains(&n) {
                out.push(n);
            }
        }
        num.clear();
    }
    out
}

/// Write every output, then the report; returns the files written (sorted).
pub fn write_reproduction(r: &Reproduction, out: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out).map_err(GearError::io(out))?;
    let mut written = Vec::new();
    for a in &r.artifacts {
        written.extend(write_artifact(a, out)?);
    }
    let counts = verdict_counts(&r.claims);
    let banner = "The Sec. 7 rows and Figs 19-23 use the shipped SYNTHETIC data sets (data/munro, data/kubo made by geardyn synth), not Munro's or Kubo's measurements.";
    let mut page = Page::new(
        "Reproduction of Kahraman & Singh (1990), Non-linear dynamics of a spur gear pair",
        banner,
        true,
    );
    intro(&mut page, r);
    page.toc();
    verdicts_section(&mut page, r, &counts);
    claims_section(&mut page, r);
    tables_section(&mut page, r);
    page.heading("Figure index");
    let index = figure_index_of(r);
    figure_index_section(&mut page, &index);
    page.heading("Figures");
    figures_section(&mut page, &index);
    let (html, md) = page.finish("geardyn reproduction of Kahraman & Singh (1990)");
    for (name, text) in [
        ("REPRODUCTION.md", md),
        ("index.html", html),
        ("claims.csv", claims_csv(&r.claims)),
        ("claims.json", claims_json(r, &counts)?),
    ] {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(GearError::io(&p))?;
        written.push(p);
    }
    written.sort();
    Ok(written)
}

/// How the run was made: the command, the version and the resolution of every search.
fn intro(page: &mut Page, r: &Reproduction) {
    let res = &r.resolution;
    page.paragraph(&format!(
        "Generated by `geardyn reproduce{}` (geardyn {}). Every value below was computed in this run; nothing is typed in by hand. Resolution {}: attractor searches on a {n}x{n} grid of initial conditions in [-2, 2]², basin maps {b}x{b}, comparisons with Omega step {} and a {c}x{c} IC grid, study grids {}.",
        if res.name == "quick" { " --quick" } else { "" },
        env!("CARGO_PKG_VERSION"),
        res.name,
        res.omega_step,
        res.study_points.map_or("at their defaults".to_string(), |p| format!("of {p} frequencies")),
        n = res.ic_n,
        b = res.basin_n,
        c = res.compare_ic_n,
    ));
}

/// The verdicts, how many claims each, and what each means.
fn verdicts_section(page: &mut Page, r: &Reproduction, counts: &[(Verdict, usize)]) {
    page.heading("Verdicts");
    page.rich_table(
        &["verdict", "claims", "meaning"],
        &Verdict::ALL
            .iter()
            .map(|v| {
                let n = counts.iter().find(|(c, _)| c == v).map_or(0, |c| c.1);
                vec![
                    Cell {
                        text: v.name().into(),
                        class: Some(verdict_class(*v)),
                        ..Cell::default()
                    },
                    format!("{n} of {}", r.claims.len()).into(),
                    verdict_meaning(*v).to_string().into(),
                ]
            })
            .collect::<Vec<_>>(),
    );
}

/// One row per claim of the paper: where, what the paper says, what this run found, verdict.
fn claims_section(page: &mut Page, r: &Reproduction) {
    page.heading("Claims");
    page.paragraph("Each row links to the figure it is about (Figures, below); the verdict cell is coloured as in the table above.");
    let rows: Vec<Vec<Cell>> = r
        .claims
        .iter()
        .map(|c| {
            let figs = figure_numbers(&c.figure);
            vec![
                c.id.clone().into(),
                Cell {
                    text: format!("Sec. {}:", c.section),
                    links: figs
                        .iter()
                        .map(|f| (format!("Fig. {f}"), format!("#fig-{f}")))
                        .collect(),
                    class: None,
                },
                cell(&c.figure).into(),
                cell(&c.paper).into(),
                cell(&c.geardyn).into(),
                Cell {
                    text: c.verdict.name().into(),
                    class: Some(verdict_class(c.verdict)),
                    ..Cell::default()
                },
                cell(&c.explanation).into(),
            ]
        })
        .collect();
    page.rich_table(
        &[
            "id",
            "figure",
            "where in the paper",
            "paper",
            "geardyn (this run)",
            "verdict",
            "explanation",
        ],
        &rows,
    );
}

/// The sections' own tables.
fn tables_section(page: &mut Page, r: &Reproduction) {
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
}

/// Every figure of the paper with the files that show it.
fn figure_index_section(page: &mut Page, index: &[FigureEntry]) {
    let frows: Vec<Vec<Cell>> = index
        .iter()
        .map(|e| {
            vec![
                Cell {
                    links: vec![(format!("Fig. {}", e.figure), format!("#fig-{}", e.figure))],
                    ..Cell::default()
                },
                e.what.clone().into(),
                Cell {
                    text: if e.files.is_empty() {
                        "-".into()
                    } else {
                        String::new()
                    },
                    links: e
                        .files
                        .iter()
                        .flat_map(|f| {
                            let name = f.rsplit('/').next().unwrap_or(f);
                            [
                                (format!("{name}.png"), format!("{f}.png")),
                                ("SVG".to_string(), format!("{f}.svg")),
                            ]
                        })
                        .collect(),
                    class: None,
                },
                e.note.clone().into(),
            ]
        })
        .collect();
    page.rich_table(&["paper", "shows", "geardyn files", "how"], &frows);
}

/// The figures themselves, one heading per figure (figures sharing files shown once).
fn figures_section(page: &mut Page, index: &[FigureEntry]) {
    page.paragraph("Click a figure to open it at full size.");
    let mut shown: Vec<&String> = Vec::new();
    for e in index {
        if e.files.is_empty() {
            page.subheading(
                &format!("Fig. {}: {}", e.figure, e.what),
                &format!("fig-{}", e.figure),
            );
            page.paragraph(&e.note);
            continue;
        }
        if e.files.iter().all(|f| shown.contains(&f)) {
            // Shown with an earlier figure (e.g. Figs 24 and 25 share their files).
            continue;
        }
        let also: Vec<&str> = index
            .iter()
            .filter(|o| o.figure != e.figure && o.files == e.files)
            .map(|o| o.figure.as_str())
            .collect();
        let title = if also.is_empty() {
            format!("Fig. {}: {}", e.figure, e.what)
        } else {
            format!("Figs {}, {}: {}", e.figure, also.join(", "), e.what)
        };
        page.subheading(&title, &format!("fig-{}", e.figure));
        for o in &also {
            page.anchor(&format!("fig-{o}"));
        }
        for f in &e.files {
            if !shown.contains(&f) {
                shown.push(f);
                page.image(&format!("{f}.png"), &format!("{} ({})", e.note, f));
            }
        }
    }
}

/// claims.json: the resolution, the verdict counts, every claim and table.
fn claims_json(r: &Reproduction, counts: &[(Verdict, usize)]) -> Result<String> {
    let res = &r.resolution;
    Ok(format!(
        "{}\n",
        serde_json::to_string_pretty(&serde_json::json!({
            "resolution": res.name,
            "verdict_counts": counts.iter().map(|(v, n)| (v.name().to_string(), *n)).collect::<std::collections::BTreeMap<_, _>>(),
            "claims": r.claims,
            "tables": r.tables,
        }))
        .map_err(|e| GearError::Numerical(format!("JSON: {e}")))?
    ))
}

#[cfg(test)]
mod tests {
    use super::figure_numbers;

    #[test]
    fn figure_numbers_of_claim_fields() {
        assert_eq!(figure_numbers("Fig. 15(a), 16(a)"), [15, 16]);
        assert_eq!(figure_numbers("Fig. 2(b), 3"), [2, 3]);
        assert_eq!(figure_numbers("eq. 14, Fig. 15(b)"), [15]);
        assert_eq!(figure_numbers("Figs 24, 25"), [24, 25]);
        assert!(figure_numbers("Sec. 3 text").is_empty());
        assert!(figure_numbers("eq. 13").is_empty());
    }
}
