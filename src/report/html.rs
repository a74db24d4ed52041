//! The static HTML report of a run folder: sheets, renders, loss curves and the metrics table
//! in one page with relative links (the page lives in `RUN/report/`, images stay where the
//! pipeline wrote them).
//!
//! Run folder layout (written by `xylem demo` and `xylem run`; the report shows whatever of
//! it exists):
//! - `sheet.png`, `sheets/*.png`: comparison sheets;
//! - `renders/*.png`: lit cubes, carved objects, turntables;
//! - `fit/sheet.png`, `fit/loss.csv`; `train/loss.png`, `train/loss.csv`;
//! - `unfolded.png` (reference and NCA crosses), `synth/unfolded.png`, `sample/truth/cut1.png`,
//!   `sample/truth/cut2.png`;
//! - `metrics.csv`: one row per (method, image), first columns `method` and `image`, then
//!   numeric metrics (as `xylem compare` names them).

use std::fmt::Write;
use std::path::{Path, PathBuf};

use crate::error::{Result, XylemError};
use crate::io::write_bytes_atomic;

/// A metrics table read from `metrics.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricsTable {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl MetricsTable {
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| XylemError::io(path, e))?;
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header: Vec<String> = lines
            .next()
            .ok_or_else(|| XylemError::input(path.display().to_string(), "metrics table is empty"))?
            .split(',')
            .map(|s| s.trim().to_string())
            .collect();
        let rows: Vec<Vec<String>> = lines
            .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
            .collect();
        if let Some(bad) = rows.iter().position(|r| r.len() != header.len()) {
            return Err(XylemError::input(
                path.display().to_string(),
                format!(
                    "row {} has {} fields; the header has {}",
                    bad + 2,
                    rows[bad].len(),
                    header.len()
                ),
            ));
        }
        Ok(Self { header, rows })
    }

    /// CSV text of the table.
    pub fn to_csv(&self) -> String {
        let mut s = self.header.join(",") + "\n";
        for row in &self.rows {
            s += &(row.join(",") + "\n");
        }
        s
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
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

struct Section {
    title: &'static str,
    images: Vec<PathBuf>,
}

fn sections(run: &Path) -> Vec<Section> {
    let existing = |rel: &[&str]| -> Vec<PathBuf> {
        rel.iter()
            .map(|r| run.join(r))
            .filter(|p| p.is_file())
            .collect()
    };
    let mut sheets = existing(&["sheet.png"]);
    sheets.extend(pngs_in(&run.join("sheets")));
    vec![
        Section {
            title: "Comparison sheets",
            images: sheets,
        },
        Section {
            title: "Renders",
            images: pngs_in(&run.join("renders")),
        },
        Section {
            title: "Unfolded faces and cuts",
            images: existing(&[
                "unfolded.png",
                "synth/unfolded.png",
                "sample/truth/cut1.png",
                "sample/truth/cut2.png",
                "synth/cuts/cut1.png",
                "synth/cuts/cut2.png",
            ]),
        },
        Section {
            title: "Growth-field fit",
            images: existing(&["fit/sheet.png", "fit/loss.png"]),
        },
        Section {
            title: "NCA training",
            images: existing(&["train/loss.png"]),
        },
    ]
}

/// Path of `target` relative to the folder `from` (both under the run folder).
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

/// Builds the report page for `run` into `out` (an `.html` path, normally
/// `RUN/report/index.html`). Returns the number of images linked.
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
    let mut html = String::new();
    let _ = write!(
        html,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{t}</title>\n<style>\
         body{{font-family:sans-serif;margin:2em;background:#fafafa;color:#222}}\
         img{{max-width:100%;border:1px solid #ccc;margin:.3em 0}}\
         figure{{margin:1em 0}} figcaption{{font-size:.85em;color:#555}}\
         table{{border-collapse:collapse;font-size:.9em}} td,th{{border:1px solid #bbb;padding:.25em .6em;text-align:right}}\
         th{{background:#eee}} td:first-child,td:nth-child(2){{text-align:left}}</style></head><body>\n<h1>{t}</h1>\n<p>Run folder: <code>{r}</code></p>\n",
        t = escape(title),
        r = escape(&run.display().to_string())
    );
    let mut count = 0;
    let metrics = run.join("metrics.csv");
    if metrics.is_file() {
        let table = MetricsTable::read(&metrics)?;
        html += "<h2>Metrics</h2>\n<table id=\"metrics\">\n<tr>";
        for h in &table.header {
            let _ = write!(html, "<th>{}</th>", escape(h));
        }
        html += "</tr>\n";
        for row in &table.rows {
            html += "<tr>";
            for v in row {
                let _ = write!(html, "<td>{}</td>", escape(v));
            }
            html += "</tr>\n";
        }
        let _ = writeln!(
            html,
            "</table>\n<p><a href=\"{}\">metrics.csv</a></p>",
            relative(&out_dir, &metrics)
        );
    }
    for section in sections(&run) {
        if section.images.is_empty() {
            continue;
        }
        let _ = writeln!(html, "<h2>{}</h2>", section.title);
        for img in section.images {
            let rel = relative(&out_dir, &img);
            let _ = writeln!(
                html,
                "<figure><a href=\"{r}\"><img src=\"{r}\" alt=\"{c}\"></a><figcaption>{c}</figcaption></figure>",
                r = escape(&rel),
                c = escape(&relative(&run, &img))
            );
            count += 1;
        }
    }
    if count == 0 && !metrics.is_file() {
        return Err(XylemError::input(
            run.display().to_string(),
            "holds no run outputs (metrics.csv, sheet.png, renders/, train/loss.png); expected \
             a folder written by `xylem run` or `xylem demo`",
        ));
    }
    html += "</body></html>\n";
    write_bytes_atomic(out, html.as_bytes())?;
    Ok(count)
}
