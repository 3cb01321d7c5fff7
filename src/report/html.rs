//! A minimal self-contained HTML page: a banner, paragraphs, tables and images.

/// Escape text for HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Builder of an HTML report.
#[derive(Default)]
pub struct Page {
    body: String,
    markdown: String,
}

impl Page {
    /// Start a page whose first line is the data-kind banner.
    pub fn new(title: &str, banner: &str, synthetic: bool) -> Self {
        let mut p = Page::default();
        let colour = if synthetic { "#fde2e2" } else { "#e2f0fd" };
        p.body.push_str(&format!(
            "<div style=\"background:{colour};padding:0.8em;font-weight:bold;border:2px solid #c00\">{}</div>\n<h1>{}</h1>\n",
            esc(banner),
            esc(title)
        ));
        p.markdown
            .push_str(&format!("**{banner}**\n\n# {title}\n\n"));
        p
    }

    pub fn heading(&mut self, text: &str) {
        self.body.push_str(&format!("<h2>{}</h2>\n", esc(text)));
        self.markdown.push_str(&format!("## {text}\n\n"));
    }

    pub fn paragraph(&mut self, text: &str) {
        self.body.push_str(&format!("<p>{}</p>\n", esc(text)));
        self.markdown.push_str(&format!("{text}\n\n"));
    }

    pub fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        self.body.push_str(
            "<table border=\"1\" cellpadding=\"4\" style=\"border-collapse:collapse\">\n<tr>",
        );
        for h in header {
            self.body.push_str(&format!("<th>{}</th>", esc(h)));
        }
        self.body.push_str("</tr>\n");
        self.markdown.push_str(&format!(
            "| {} |\n|{}\n",
            header.join(" | "),
            "---|".repeat(header.len())
        ));
        for r in rows {
            self.body.push_str("<tr>");
            for c in r {
                self.body.push_str(&format!("<td>{}</td>", esc(c)));
            }
            self.body.push_str("</tr>\n");
            self.markdown.push_str(&format!("| {} |\n", r.join(" | ")));
        }
        self.body.push_str("</table>\n");
        self.markdown.push('\n');
    }

    pub fn image(&mut self, file: &str, alt: &str) {
        self.body.push_str(&format!(
            "<p><img src=\"{}\" alt=\"{}\" style=\"max-width:100%\"></p>\n",
            esc(file),
            esc(alt)
        ));
        self.markdown.push_str(&format!("![{alt}]({file})\n\n"));
    }

    pub fn preformatted(&mut self, text: &str) {
        self.body.push_str(&format!("<pre>{}</pre>\n", esc(text)));
        self.markdown.push_str(&format!("```\n{text}\n```\n\n"));
    }

    /// The full HTML document and the Markdown twin.
    pub fn finish(self, title: &str) -> (String, String) {
        (
            format!(
                "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{}</title></head>\n<body style=\"font-family:sans-serif;max-width:1100px;margin:auto\">\n{}</body></html>\n",
                esc(title),
                self.body
            ),
            self.markdown,
        )
    }
}
