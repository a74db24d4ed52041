//! The static HTML report of a run folder, `RUN/report/index.html`: what a person opens to
//! judge a run without reading the folder file by file. One page, no script, no external
//! file; links are relative to the page, so the run folder can be moved, copied or served
//! as a whole, and the page holds no path of the machine it was made on. The same folder
//! (and the same xylem) always gives the same page: there is no date in it.
//!
//! What the page shows, each part only when the run folder has it:
//! - the metrics table (`metrics.csv`, [`super::metrics_html`]) with a legend;
//! - the hidden cuts, truth beside each candidate ([`super::cuts`]);
//! - comparison sheets (`sheet.png`, `sheets/*.png`) and renders (`renders/*.png`);
//! - loss curves of the training and the fit ([`super::loss_curves`]), `train/loss.png`;
//! - unfolded faces (`unfolded.png`, `synth/unfolded.png`), the fit's sheet;
//! - time and peak memory per stage (`timings.csv`, [`super::timings`]);
//! - the configs the run was made with ([`super::configs`]), collapsed.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use crate::error::{Result, XylemError};
use crate::io::write_bytes_atomic;

use super::configs::config_files;
use super::cuts::cut_rows;
use super::format::{duration, significant};
use super::loss_curves::{PlotOrNote, fit_plot, training_plot};
use super::metrics_html::metrics_section;
use super::metrics_table::MetricsTable;
use super::timings::{TIMINGS_FILE, Timings};

/// The xylem that writes the page, so a reader can tell which code made it.
pub const XYLEM_VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit xylem was built from (set by build.rs; "unknown" outside a checkout).
pub const XYLEM_COMMIT: &str = env!("XYLEM_GIT_COMMIT");

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

/// Builds the report page for `run` into `out` (an `.html` path, normally
/// `RUN/report/index.html`). Returns the number of images shown.
pub fn write_report(run: &Path, out: &Path, title: &str) -> Result<usize> {
    if !run.is_dir() {
        return Err(XylemError::input(
            run.display().to_string(),
            "run folder not found",
        ));
    }
    let run = run.canonicalize().map_err(|e| XylemError::io(run, e))?;
    let out_dir = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(out_dir).map_err(|e| XylemError::io(out_dir, e))?;
    let out_dir = out_dir
        .canonicalize()
        .map_err(|e| XylemError::io(out_dir, e))?;
    let mut page = Page::new(run.clone(), out_dir);
    let metrics = run.join("metrics.csv");
    let has_metrics = metrics.is_file();
    if has_metrics {
        let table = MetricsTable::read(&metrics)?;
        metrics_section(&mut page, &table);
    }
    cuts_section(&mut page);
    image_section(&mut page, "sheets", "Comparison sheets", &sheets(&run));
    image_section(
        &mut page,
        "renders",
        "Renders",
        &pngs_in(&run.join("renders")),
    );
    loss_section(&mut page);
    image_section(
        &mut page,
        "unfolded",
        "Unfolded faces",
        &existing(&run, &["unfolded.png", "synth/unfolded.png"]),
    );
    image_section(
        &mut page,
        "fit",
        "Growth-field fit",
        &existing(&run, &["fit/sheet.png", "fit/loss.png"]),
    );
    if page.images == 0 && !has_metrics {
        return Err(XylemError::input(
            run.display().to_string(),
            "holds no run outputs (metrics.csv, sheet.png, renders/, train/loss.png); expected \
             a folder written by `xylem run` or `xylem demo`",
        ));
    }
    timings_section(&mut page);
    configs_section(&mut page);
    write_bytes_atomic(out, page.finish(title).as_bytes())?;
    Ok(page.images)
}

/// The page being written: body, table of contents and the folders links are made from.
pub(super) struct Page {
    body: String,
    contents: Vec<(String, String)>,
    pub images: usize,
    run: PathBuf,
    out_dir: PathBuf,
}

impl Page {
    fn new(run: PathBuf, out_dir: PathBuf) -> Self {
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
    pub fn file_link(&self, target: &Path) -> String {
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

    fn finish(&self, title: &str) -> String {
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
pub fn escape(s: &str) -> String {
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

/// PNG files directly inside `dir`, sorted.
fn pngs_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    files.sort();
    files
}

fn existing(run: &Path, names: &[&str]) -> Vec<PathBuf> {
    names
        .iter()
        .map(|n| run.join(n))
        .filter(|p| p.is_file())
        .collect()
}

fn sheets(run: &Path) -> Vec<PathBuf> {
    let mut sheets = existing(run, &["sheet.png"]);
    sheets.extend(pngs_in(&run.join("sheets")));
    sheets
}

fn image_section(page: &mut Page, id: &str, title: &str, images: &[PathBuf]) {
    if images.is_empty() {
        return;
    }
    page.section(id, title);
    for image in images {
        page.figure(image);
    }
}

/// A row per hidden cut, the truth and every candidate's cut at one size.
fn cuts_section(page: &mut Page) {
    let (columns, rows) = cut_rows(page.run());
    if rows.is_empty() {
        return;
    }
    page.section("cuts", "Hidden cuts: truth and candidates");
    let note = if columns.first() == Some(&"truth") {
        "Cuts through the inside of the cube that neither the fit nor the training saw, each \
         shown at the same size; click an image for the full-size file."
    } else {
        "The sample has no true cuts (a real sample): each method's prediction of the inside, \
         at the same size; click an image for the full-size file."
    };
    let _ = writeln!(
        page.body,
        "<p>{note}</p>\n<div class=\"scroll\"><table class=\"cuts\"><tr><th>cut</th>"
    );
    for c in &columns {
        let _ = write!(page.body, "<th>{}</th>", escape(c));
    }
    page.push("</tr>\n");
    for row in &rows {
        let _ = write!(page.body, "<tr><th>{}</th>", escape(&row.cut));
        for (column, image) in columns.iter().zip(&row.images) {
            let cell = match image {
                Some(path) => page.tile(path, &format!("{}: {column}", row.cut)),
                None => "<div class=\"missing\">not in this run</div>".to_string(),
            };
            let _ = write!(page.body, "<td>{cell}</td>");
        }
        page.push("</tr>\n");
    }
    page.push("</table></div>\n");
}

/// The training and fit loss curves; a missing or damaged loss file is a note, not a
/// failed page.
fn loss_section(page: &mut Page) {
    let run = page.run().to_path_buf();
    let train = run.join("train/loss.csv");
    let fit = run.join("fit/loss.csv");
    let png = run.join("train/loss.png");
    if !train.is_file() && !fit.is_file() && !png.is_file() {
        return;
    }
    page.section("losses", "Loss curves");
    if train.is_file() {
        page.push("<h3>NCA training</h3>\n");
        plot_or_note(page, training_plot(&train), &train);
    }
    if png.is_file() {
        page.figure(&png);
    }
    if fit.is_file() {
        page.push("<h3>Growth-field fit</h3>\n");
        plot_or_note(page, fit_plot(&fit), &fit);
    }
}

fn plot_or_note(page: &mut Page, plot: PlotOrNote, data: &Path) {
    let svg = plot.and_then(|p| {
        p.to_svg()
            .ok_or_else(|| format!("{}: no positive loss to plot", page.name(data)))
    });
    match svg {
        Ok(svg) => {
            let _ = writeln!(
                page.body,
                "<figure>{svg}<figcaption>data: {}</figcaption></figure>",
                page.file_link(data)
            );
        }
        Err(note) => {
            let note = note.replace(&page.run().display().to_string(), "RUN");
            let _ = writeln!(
                page.body,
                "<p class=\"note\">Not plotted: {}</p>",
                escape(&note)
            );
        }
    }
}

/// Time and peak memory per stage, or why they are not known.
fn timings_section(page: &mut Page) {
    page.section("timings", "Time and memory per stage");
    let path = page.run().join(TIMINGS_FILE);
    if !path.is_file() {
        page.push(
            "<p class=\"note\">Timings were not recorded for this run (it has no timings.csv: \
             it was made by an older xylem, or not by <code>xylem run</code>).</p>\n",
        );
        return;
    }
    let timings = match Timings::read(&path) {
        Ok(t) => t,
        Err(e) => {
            let note = e
                .to_string()
                .replace(&page.run().display().to_string(), "RUN");
            let _ = writeln!(
                page.body,
                "<p class=\"note\">Not shown: {}</p>",
                escape(&note)
            );
            return;
        }
    };
    page.push(
        "<table id=\"timings\"><tr><th>stage</th><th>wall time</th><th>peak memory</th>\
         <th></th></tr>\n",
    );
    for s in &timings.stages {
        let peak = s
            .peak_mb
            .map(|mb| format!("{} MB", significant(mb, 3)))
            .unwrap_or_else(|| "not measured".into());
        let note = if s.skipped {
            "found done, skipped (time of the check)"
        } else {
            ""
        };
        let _ = writeln!(
            page.body,
            "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{peak}</td><td>{note}</td></tr>",
            escape(&s.stage),
            duration(s.seconds)
        );
    }
    let total: f64 = timings.stages.iter().map(|s| s.seconds).sum();
    let peak = timings
        .stages
        .iter()
        .filter_map(|s| s.peak_mb)
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))));
    let _ = writeln!(
        page.body,
        "<tr><th>total</th><th class=\"num\">{}</th><th class=\"num\">{}</th><th></th></tr></table>\n\
         <p class=\"meta\">Peak memory: the most resident memory the process held during the \
         stage (Linux VmHWM). A stage found done by an earlier call shows that call's time when \
         it was recorded. Data: {}</p>",
        duration(total),
        peak.map(|mb| format!("{} MB", significant(mb, 3)))
            .unwrap_or_default(),
        page.file_link(&path)
    );
}

/// Each config of the run in a collapsed block.
fn configs_section(page: &mut Page) {
    let configs = config_files(page.run());
    if configs.is_empty() {
        return;
    }
    page.section("configs", "Configs");
    page.push(
        "<p class=\"meta\">The TOML files the run was made with, as the run folder keeps them \
         (click to open). Absolute paths read <code>RUN/\u{2026}</code> inside this run \
         folder and <code>\u{2026}/parent/name</code> elsewhere.</p>\n",
    );
    for config in configs {
        let path = page.run().join(&config.name);
        let body = match &config.text {
            Ok(text) => format!("<pre>{}</pre>", escape(text)),
            Err(e) => format!("<p class=\"note\">{}</p>", escape(e)),
        };
        let _ = writeln!(
            page.body,
            "<details><summary>{}: {}</summary>{body}</details>",
            page.file_link(&path),
            escape(config.about)
        );
    }
}
