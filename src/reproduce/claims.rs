//! The claim table: one row per quantitative or qualitative statement of the paper's text, with
//! geardyn's number from the same run and a verdict generated from that number.

use serde::Serialize;

/// Outcome of checking one claim of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// geardyn's numbers support the claim within the stated tolerance.
    Agree,
    /// geardyn's numbers contradict the claim.
    Differ,
    /// geardyn finds what the paper reports and more (e.g. additional coexisting orbits),
    /// confirmed by both integrators in the same run.
    MoreThanPaper,
    /// What the paper saw holds over the time it integrated, but geardyn followed it further and
    /// found it is something else in the long run (a chaotic transient, not a strange
    /// attractor); the finding and its numbers are in the explanation.
    BeyondPaper,
    /// The claim is about agreement with measurements; the shipped data are synthetic.
    NotTestableSynthetic,
}

impl Verdict {
    /// Every verdict, in table order.
    pub const ALL: [Verdict; 5] = [
        Verdict::Agree,
        Verdict::Differ,
        Verdict::MoreThanPaper,
        Verdict::BeyondPaper,
        Verdict::NotTestableSynthetic,
    ];

    /// Text used in the report.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Agree => "agree",
            Verdict::Differ => "differ",
            Verdict::MoreThanPaper => "more than the paper",
            Verdict::BeyondPaper => "beyond the paper (transient chaos)",
            Verdict::NotTestableSynthetic => "not testable (synthetic data)",
        }
    }
}

/// One row of the reproduction table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Claim {
    /// Stable identifier, e.g. `S3-omega-0.5`.
    pub id: String,
    /// Paper section, e.g. "3".
    pub section: String,
    /// Paper figure(s), e.g. "Fig. 2(b), 3".
    pub figure: String,
    /// The paper's claim, quoted or paraphrased briefly.
    pub paper: String,
    /// geardyn's computed value(s) in this run.
    pub geardyn: String,
    /// Verdict.
    pub verdict: Verdict,
    /// One line generated from the numbers.
    pub explanation: String,
}

impl Claim {
    /// A row; all text fields are owned copies.
    pub fn new(
        id: &str,
        section: &str,
        figure: &str,
        paper: &str,
        geardyn: String,
        verdict: Verdict,
        explanation: String,
    ) -> Self {
        Claim {
            id: id.to_string(),
            section: section.to_string(),
            figure: figure.to_string(),
            paper: paper.to_string(),
            geardyn,
            verdict,
            explanation,
        }
    }
}

/// Number of rows with each verdict, in [`Verdict::ALL`] order.
pub fn verdict_counts(claims: &[Claim]) -> Vec<(Verdict, usize)> {
    Verdict::ALL
        .iter()
        .map(|&v| (v, claims.iter().filter(|c| c.verdict == v).count()))
        .collect()
}

/// `agree` when `ok`, else `differ`.
pub fn agree_if(ok: bool) -> Verdict {
    if ok {
        Verdict::Agree
    } else {
        Verdict::Differ
    }
}

/// A number with 3 significant decimals, or "none".
pub fn fmt_opt(x: Option<f64>) -> String {
    x.map_or("none".to_string(), |v| format!("{v:.3}"))
}

/// A range "lo-hi" with 3 decimals, or "none".
pub fn fmt_range(r: Option<(f64, f64)>) -> String {
    r.map_or("none".to_string(), |(a, b)| format!("{a:.3}-{b:.3}"))
}

/// A table of evidence behind some claims, written after the claim table (e.g. the Sec. 3
/// attractor sets followed past the paper's time scale, the case III normalisation readings).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReportTable {
    /// Section heading.
    pub heading: String,
    /// Paragraph before the table: what was computed and how to read it.
    pub intro: String,
    /// Column names.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}
