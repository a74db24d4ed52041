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
use super::page::{Page, escape};
use super::timings::{TIMINGS_FILE, Timings};
use crate::run_folder::{METRICS_CSV, SHEET_PNG, UNFOLDED_PNG};

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
    let metrics = run.join(METRICS_CSV);
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
        &existing(&run, &[UNFOLDED_PNG, "synth/unfolded.png"]),
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
    let mut sheets = existing(run, &[SHEET_PNG]);
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
