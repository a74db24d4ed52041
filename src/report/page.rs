//! One HTML page being written: its sections and table of contents, images and links
//! relative to the page, escaping, and the style sheet.

use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The xylem that writes the page, so a reader can tell which code made it.
pub(crate) const XYLEM_VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit xylem was built from (set by build.rs; "unknown" outside a checkout).
pub(crate) const XYLEM_COMMIT: &str = env!("XYLEM_GIT_COMMIT");

const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:0;background:#fafafa;color:#222;line-height:1.4}
main{max-width:1160px;margin:0 auto;padding:1em 2em 3em}
h1{margin:.3em 0 .1em}h2{margin-top:1.8em;border-bottom:1px solid #ddd;padding-bottom:.15em}
.meta{color:#555;font-size:.9em;margin:.2em 0}
nav{font-size:.9em;margin:.8em 0}nav a{margin-right:1em;white-space:nowrap}
img{max-width:100%;border:1px solid #ccc;background:#fff}
figure img{max-height:1000px}
figure{margin:1em 0}figcaption{font-size:.85em;color:#555}
table{border-collapse:collapse;font-size:.9em;background:#fff;margin:.5em 0}
td,th{border:1px solid #bbb;padding:.25em .5em;text-align:left}
th{background:#eee}td.num{text-align:right;font-variant-numeric:tabular-nums}
#metrics th,#metrics td,table.legend td:first-child{white-space:nowrap}table.legend{margin-top:1.2em}
tr.first-of-image td{border-top:2px solid #777}
td.best{background:#bfe3b4;font-weight:600}
tr.truth td{color:#777;font-style:italic}
table.cuts td,table.cuts th{text-align:center;vertical-align:middle}
.scroll{overflow-x:auto}
table.cuts img{width:220px;height:220px;max-width:none;box-sizing:border-box;object-fit:contain;display:block;margin:0 auto}
.missing{width:220px;height:220px;display:flex;align-items:center;justify-content:center;background:#eee;color:#777;font-size:.85em}
details{margin:.4em 0;background:#fff;border:1px solid #ccc;padding:.3em .7em}
summary{cursor:pointer}details pre{overflow:auto;max-height:32em;font-size:.82em;margin:.4em 0}
svg.plot{max-width:100%;height:auto;border:1px solid #ccc;display:block}
.note{color:#7a5200}
";

/// The page being written: body, table of contents and the folders links are made from.
pub struct Page {
    pub(super) body: String,
    contents: Vec<(String, String)>,
    pub images: usize,
    run: PathBuf,
    out_dir: PathBuf,
}

impl Page {
    pub fn new(run: PathBuf, out_dir: PathBuf) -> Self {
        Self {
            body: String::new(),
            contents: Vec::new(),
            images: 0,
            run,
            out_dir,
        }
    }

    pub fn run(&self) -> &Path {
        &self.run
    }

    /// Appends markup.
    pub fn push(&mut self, html: &str) {
        self.body += html;
    }

    /// Starts a section listed in the table of contents.
    pub fn section(&mut self, id: &str, title: &str) {
        self.contents.push((id.into(), title.into()));
        let _ = writeln!(self.body, "<h2 id=\"{id}\">{}</h2>", escape(title));
    }

    /// The escaped link from the page to `target`.
    pub fn href(&self, target: &Path) -> String {
        escape(&relative(&self.out_dir, target))
    }

    /// `target`'s path inside the run folder, escaped, for captions.
    pub fn name(&self, target: &Path) -> String {
        escape(&relative(&self.run, target))
    }

    /// A link to a file of the run folder, named by its path in it.
    pub(crate) fn file_link(&self, target: &Path) -> String {
        format!(
            "<a href=\"{}\"><code>{}</code></a>",
            self.href(target),
            self.name(target)
        )
    }

    /// An image at its own size (up to the page width), linked to itself.
    pub fn figure(&mut self, image: &Path) {
        let (href, name) = (self.href(image), self.name(image));
        let _ = writeln!(
            self.body,
            "<figure><a href=\"{href}\"><img src=\"{href}\" alt=\"{name}\" loading=\"lazy\"></a>\
             <figcaption>{name}</figcaption></figure>"
        );
        self.images += 1;
    }

    /// An image at the fixed tile size, linked to the full-size file.
    pub fn tile(&mut self, image: &Path, alt: &str) -> String {
        self.images += 1;
        let href = self.href(image);
        format!(
            "<a href=\"{href}\" title=\"{name} (full size)\"><img src=\"{href}\" alt=\"{}\"></a>",
            escape(alt),
            name = self.name(image)
        )
    }

    /// The whole page, titled.
    pub fn finish(&self, title: &str) -> String {
        let mut html = String::new();
        let _ = write!(
            html,
            "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\
             <meta name=\"generator\" content=\"xylem {XYLEM_VERSION} ({XYLEM_COMMIT})\">\
             <title>{t}</title>\n<style>\n{STYLE}</style></head><body><main>\n<h1>{t}</h1>\n\
             <p class=\"meta\" id=\"version\">Written by xylem {XYLEM_VERSION}, git commit \
             <code>{commit}</code>. Links are relative to this page: the run folder can be \
             moved or served as a whole.</p>\n<nav>",
            t = escape(title),
            commit = escape(XYLEM_COMMIT),
        );
        for (id, title) in &self.contents {
            let _ = writeln!(html, "<a href=\"#{id}\">{}</a>", escape(title));
        }
        html += "</nav>\n";
        html += &self.body;
        html += "</main></body></html>\n";
        html
    }
}

/// Text for HTML content and attribute values.
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Path of `target` relative to the folder `from` (both canonical), with `/`.
fn relative(from: &Path, target: &Path) -> String {
    let from: Vec<_> = from.components().collect();
    let to: Vec<_> = target.components().collect();
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); from.len() - common];
    parts.extend(
        to[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}
