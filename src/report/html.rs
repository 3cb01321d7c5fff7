//! A self-contained HTML report page and its Markdown twin: a banner, headings (with a table of
//! contents), paragraphs, tables, definitions and figures that open full size when clicked.
//! Text goes through [`symbols`], and `code` spans become `<code>` in HTML.

use crate::plot::symbols;

/// Escape text for HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `s` with its backtick code spans passed through `code` and the text between through `text`.
fn spans(s: &str, code: impl Fn(&str) -> String, text: impl Fn(&str) -> String) -> String {
    s.split('`')
        .enumerate()
        .map(|(i, part)| if i % 2 == 1 { code(part) } else { text(part) })
        .collect()
}

/// Inline text: backtick spans become `<code>` (kept verbatim), the rest is escaped with the
/// paper's symbols.
fn inline_html(s: &str) -> String {
    spans(
        s,
        |c| format!("<code>{}</code>", esc(c)),
        |t| esc(&symbols(t)),
    )
}

/// Inline Markdown: the paper's symbols outside code spans.
fn inline_md(s: &str) -> String {
    spans(s, |c| format!("`{c}`"), symbols)
}

/// Anchor id of a heading: lower-case letters and digits, words joined by '-'.
pub fn slug(text: &str) -> String {
    let s: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                ' '
            }
        })
        .collect();
    s.split_whitespace().collect::<Vec<_>>().join("-")
}

/// One table cell: text, optional links after it (label, href) and an optional CSS class.
#[derive(Debug, Clone, Default)]
pub struct Cell {
    pub text: String,
    pub links: Vec<(String, String)>,
    pub class: Option<&'static str>,
}

impl From<String> for Cell {
    fn from(text: String) -> Self {
        Cell {
            text,
            ..Cell::default()
        }
    }
}

/// Style sheet: readable tables, verdict colours, figures as wide as the page.
const STYLE: &str = "body{font-family:sans-serif;max-width:1200px;margin:auto;padding:0 1em;line-height:1.4}\
table{border-collapse:collapse;margin:0.5em 0}th,td{border:1px solid #999;padding:4px 6px;vertical-align:top}\
th{background:#f0f0f0}code{background:#f4f4f4;padding:0 2px}\
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd;cursor:zoom-in}\
figcaption{color:#444;font-size:0.95em}dt{font-weight:bold}dd{margin:0 0 0.4em 1.5em}\
nav.toc{background:#f7f7f7;border:1px solid #ddd;padding:0.3em 1em}\
.agree{background:#d8f0d8}.differ{background:#fbdcd7}.more{background:#d9e8fb}.beyond{background:#fbefc9}.untestable{background:#e8e8e8}";

/// Builder of an HTML report.
#[derive(Default)]
pub struct Page {
    body: String,
    markdown: String,
    /// (level, text, id) of every heading, for the table of contents.
    headings: Vec<(u8, String, String)>,
    toc_at: Option<usize>,
}

impl Page {
    /// Start a page whose first line is the data-kind banner.
    pub fn new(title: &str, banner: &str, synthetic: bool) -> Self {
        let mut p = Page::default();
        let colour = if synthetic { "#fde2e2" } else { "#e2f0fd" };
        p.body.push_str(&format!(
            "<div style=\"background:{colour};padding:0.8em;font-weight:bold;border:2px solid #c00\">{}</div>\n<h1>{}</h1>\n",
            inline_html(banner),
            inline_html(title)
        ));
        p.markdown.push_str(&format!(
            "**{}**\n\n# {}\n\n",
            inline_md(banner),
            inline_md(title)
        ));
        p
    }

    /// A table of contents of the headings (level 2 and 3) goes here when the page is finished.
    pub fn toc(&mut self) {
        self.toc_at = Some(self.body.len());
    }

    fn heading_at(&mut self, level: u8, text: &str, id: &str) {
        self.body.push_str(&format!(
            "<h{level} id=\"{}\">{}</h{level}>\n",
            esc(id),
            inline_html(text)
        ));
        self.markdown.push_str(&format!(
            "<a id=\"{}\"></a>\n{} {}\n\n",
            esc(id),
            "#".repeat(usize::from(level)),
            inline_md(text)
        ));
        self.headings
            .push((level, symbols(text).replace('`', ""), id.to_string()));
    }

    /// A section heading (anchor id from its text).
    pub fn heading(&mut self, text: &str) {
        self.heading_at(2, text, &slug(text));
    }

    /// A sub-section heading with the given anchor id.
    pub fn subheading(&mut self, text: &str, id: &str) {
        self.heading_at(3, text, id);
    }

    /// An empty anchor, the target of links to `id`.
    pub fn anchor(&mut self, id: &str) {
        self.body.push_str(&format!("<a id=\"{}\"></a>\n", esc(id)));
        self.markdown
            .push_str(&format!("<a id=\"{}\"></a>\n", esc(id)));
    }

    pub fn paragraph(&mut self, text: &str) {
        self.body
            .push_str(&format!("<p>{}</p>\n", inline_html(text)));
        self.markdown.push_str(&format!("{}\n\n", inline_md(text)));
    }

    /// Terms and what they mean, e.g. the columns of a table.
    pub fn definitions(&mut self, items: &[(&str, &str)]) {
        self.body.push_str("<dl>\n");
        for (term, meaning) in items {
            self.body.push_str(&format!(
                "<dt>{}</dt><dd>{}</dd>\n",
                inline_html(term),
                inline_html(meaning)
            ));
            self.markdown.push_str(&format!(
                "- **{}**: {}\n",
                inline_md(term),
                inline_md(meaning)
            ));
        }
        self.body.push_str("</dl>\n");
        self.markdown.push('\n');
    }

    pub fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        let rows: Vec<Vec<Cell>> = rows
            .iter()
            .map(|r| r.iter().cloned().map(Cell::from).collect())
            .collect();
        self.rich_table(header, &rows);
    }

    /// A table whose cells may carry links and a CSS class.
    pub fn rich_table(&mut self, header: &[&str], rows: &[Vec<Cell>]) {
        self.body.push_str("<table>\n<tr>");
        for h in header {
            self.body.push_str(&format!("<th>{}</th>", inline_html(h)));
        }
        self.body.push_str("</tr>\n");
        let md_header: Vec<String> = header.iter().map(|h| inline_md(h)).collect();
        self.markdown.push_str(&format!(
            "| {} |\n|{}\n",
            md_header.join(" | "),
            "---|".repeat(header.len())
        ));
        for r in rows {
            self.body.push_str("<tr>");
            let mut md = Vec::new();
            for c in r {
                let class = c.class.map_or(String::new(), |k| format!(" class=\"{k}\""));
                let links: Vec<String> = c
                    .links
                    .iter()
                    .map(|(label, href)| {
                        format!("<a href=\"{}\">{}</a>", esc(href), inline_html(label))
                    })
                    .collect();
                let sep = if c.text.is_empty() || links.is_empty() {
                    ""
                } else {
                    " "
                };
                self.body.push_str(&format!(
                    "<td{class}>{}{sep}{}</td>",
                    inline_html(&c.text),
                    links.join(", ")
                ));
                let md_links: Vec<String> = c
                    .links
                    .iter()
                    .map(|(label, href)| format!("[{}]({href})", inline_md(label)))
                    .collect();
                md.push(
                    format!("{}{sep}{}", inline_md(&c.text), md_links.join(", ")).replace('|', "/"),
                );
            }
            self.body.push_str("</tr>\n");
            self.markdown.push_str(&format!("| {} |\n", md.join(" | ")));
        }
        self.body.push_str("</table>\n");
        self.markdown.push('\n');
    }

    /// A figure: the image at the page's width, opening full size when clicked, with a caption.
    pub fn image(&mut self, file: &str, alt: &str) {
        self.body.push_str(&format!(
            "<figure><a href=\"{f}\" title=\"open full size\"><img src=\"{f}\" alt=\"{a}\" loading=\"lazy\"></a><figcaption>{c}</figcaption></figure>\n",
            f = esc(file),
            a = esc(&symbols(alt)),
            c = inline_html(alt),
        ));
        self.markdown
            .push_str(&format!("![{}]({file})\n\n", inline_md(alt)));
    }

    pub fn preformatted(&mut self, text: &str) {
        self.body.push_str(&format!("<pre>{}</pre>\n", esc(text)));
        self.markdown.push_str(&format!("```\n{text}\n```\n\n"));
    }

    /// The contents list of the headings, in HTML.
    fn toc_html(&self) -> String {
        let mut s = String::from("<nav class=\"toc\"><strong>Contents</strong>\n<ul>\n");
        let mut open_sub = false;
        for (level, text, id) in &self.headings {
            match (level, open_sub) {
                (3, false) => {
                    s.push_str("<ul>\n");
                    open_sub = true;
                }
                (2, true) => {
                    s.push_str("</ul>\n");
                    open_sub = false;
                }
                _ => {}
            }
            s.push_str(&format!(
                "<li><a href=\"#{}\">{}</a></li>\n",
                esc(id),
                esc(text)
            ));
        }
        if open_sub {
            s.push_str("</ul>\n");
        }
        s.push_str("</ul></nav>\n");
        s
    }

    /// The full HTML document and the Markdown twin.
    pub fn finish(mut self, title: &str) -> (String, String) {
        if let Some(at) = self.toc_at {
            let toc = self.toc_html();
            self.body.insert_str(at, &toc);
        }
        (
            format!(
                "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width\"><title>{}</title><style>{STYLE}</style></head>\n<body>\n{}</body></html>\n",
                esc(&symbols(title)),
                self.body
            ),
            self.markdown,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_spans_and_symbols() {
        assert_eq!(
            inline_html("run `geardyn validate munro` at zeta < 1"),
            "run <code>geardyn validate munro</code> at ζ &lt; 1"
        );
        assert_eq!(inline_md("`zeta` zeta"), "`zeta` ζ");
        assert_eq!(slug("Errors per load (3780 N)"), "errors-per-load-3780-n");
    }

    #[test]
    fn page_has_contents_links_and_no_backticks() {
        let mut p = Page::new("T", "banner", true);
        p.toc();
        p.paragraph("made by `geardyn reproduce`");
        p.heading("Claims");
        p.rich_table(
            &["id", "verdict"],
            &[vec![
                Cell {
                    text: "S3-01".into(),
                    links: vec![("Fig. 2".into(), "#fig-2".into())],
                    class: None,
                },
                Cell {
                    text: "agree".into(),
                    class: Some("agree"),
                    ..Cell::default()
                },
            ]],
        );
        p.subheading("Fig. 2", "fig-2");
        p.image("a.png", "phase planes");
        let (html, md) = p.finish("T");
        assert!(html.contains("<a href=\"#claims\">Claims</a>"));
        assert!(html.contains("<a href=\"#fig-2\">Fig. 2</a>"));
        assert!(html.contains("<h3 id=\"fig-2\">"));
        assert!(html.contains("<td class=\"agree\">agree</td>"));
        assert!(html.contains("<a href=\"a.png\" title=\"open full size\"><img src=\"a.png\""));
        assert!(!html.contains('`'), "{html}");
        assert!(md.contains("[Fig. 2](#fig-2)") && md.contains("`geardyn reproduce`"));
    }
}
