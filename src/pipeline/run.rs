//! The whole pipeline on one sample folder: fit -> NCA training -> synthesis -> comparison
//! sheet, renders, metrics -> HTML report, all inside one run folder ([`RunLayout`]). Stages
//! whose outputs are complete are skipped and an interrupted training resumes, so calling it
//! again continues a killed run. Each stage's wall time and peak memory go into
//! `timings.csv` as it finishes.

use std::path::{Path, PathBuf};

use super::compared::Compared;
use super::fit_stage::{FitOptions, fit_into};
use super::metrics::{metrics_table, phase_table};
use super::reporter::Reporter;
use super::run_images::{write_renders, write_sheet, write_unfolded};
use super::run_options::{NcaSource, RunOptions};
use super::run_record::{check_or_record, is_done, mark_done};
use super::stage_log::StageLog;
use super::synth_stage::{SynthStageOptions, synth_into};
use super::train_stage::{TrainStageOptions, TrainStart, train_into};
use crate::Result;
use crate::fit::FitConfig;
use crate::io::{OutputDir, write_bytes_atomic};
use crate::nca::model_dir::WEIGHTS_FILE;
use crate::nca::train::snapshot;
use crate::report::{MetricsTable, StageClock, Timings, default_title, write_report};
use crate::run_folder::RunLayout;
use crate::texture::SolidTexture;

/// What a finished run measured.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// The stages' cost: a skipped stage keeps the row of the call that ran it (as
    /// `timings.csv` does).
    pub timings: Timings,
    /// Every method against every fair reference (`metrics.csv`).
    pub metrics: MetricsTable,
}

/// Runs every stage into `layout`'s folder.
pub fn run(
    layout: &RunLayout,
    options: &RunOptions,
    reporter: &dyn Reporter,
) -> Result<RunOutcome> {
    OutputDir::prepare(layout.root())?;
    check_or_record(layout, options)?;
    let mut log = StageLog::open(layout, reporter);
    let clock = StageClock::start();
    let skipped = fit_step(layout, options, reporter)?;
    log.finish(clock, "fit", skipped)?;
    let clock = StageClock::start();
    let skipped = train_step(layout, options, reporter)?;
    log.finish(clock, "train", skipped)?;
    let clock = StageClock::start();
    let skipped = synth_step(layout, options, reporter)?;
    log.finish(clock, "synth", skipped)?;

    reporter.note("== sheet");
    let clock = StageClock::start();
    let compared = Compared::load(layout, &options.sample, &options.species)?;
    write_sheet(layout, &compared, options.image_size)?;
    write_unfolded(layout, &compared, options.image_size)?;
    log.finish(clock, "sheet", false)?;

    reporter.note("== renders");
    let clock = StageClock::start();
    write_renders(layout, &compared, options.image_size)?;
    log.finish(clock, "renders", false)?;

    reporter.note("== metrics");
    let clock = StageClock::start();
    let metrics = write_metrics(layout, options, &compared)?;
    log.finish(clock, "metrics", false)?;

    reporter.note("== report");
    let clock = StageClock::start();
    write_run_report(layout)?;
    log.finish(clock, "report", false)?;
    // Again, so that the page shows the report's own row: the same page `xylem report`
    // writes from the finished folder.
    let images = write_run_report(layout)?;
    reporter.say(&format!(
        "wrote {} ({images} images)",
        layout.report_page().display()
    ));
    Ok(RunOutcome {
        timings: log.into_timings(),
        metrics,
    })
}

/// `metrics.csv` and `phase.csv`; returns the metrics table.
fn write_metrics(
    layout: &RunLayout,
    options: &RunOptions,
    compared: &Compared,
) -> Result<MetricsTable> {
    let table = metrics_table(
        &options.sample,
        &options.faces,
        &compared.fit,
        &compared.procedural,
        &compared.nca,
        &options.device.device(),
    )?;
    write_bytes_atomic(&layout.metrics(), table.to_csv().as_bytes())?;
    let textures: [(&str, &dyn SolidTexture); 2] =
        [("nca", &compared.nca), ("procedural", &compared.procedural)];
    let phase = phase_table(&compared.reference, &compared.fit, &textures, 256)?;
    write_bytes_atomic(&layout.phase(), phase.to_csv().as_bytes())?;
    Ok(table)
}

/// The report of the run folder, titled from its record like `xylem report` does; returns
/// how many images it shows.
fn write_run_report(layout: &RunLayout) -> Result<usize> {
    let title = default_title(layout.root());
    write_report(layout.root(), &layout.report_page(), &title)
}

/// Whether the stage in `dir` is complete, saying that it is skipped.
fn skip_if_done(dir: &Path, stage: &str, reporter: &dyn Reporter) -> bool {
    let done = is_done(dir);
    if done {
        reporter.note(&format!("== {stage} (done, skipped)"));
    }
    done
}

/// Runs the stage `stage` into `dir` by `work` unless it is done, then marks it done;
/// returns whether it was skipped. (Training decides when it is done itself.)
fn unless_done(
    dir: &Path,
    stage: &str,
    reporter: &dyn Reporter,
    work: impl FnOnce() -> Result<()>,
) -> Result<bool> {
    if skip_if_done(dir, stage, reporter) {
        return Ok(true);
    }
    reporter.note(&format!("== {stage}"));
    work()?;
    mark_done(dir)?;
    Ok(false)
}

/// Runs the fit unless it is done; returns whether it was skipped (as for the other
/// reusable stages).
fn fit_step(layout: &RunLayout, options: &RunOptions, reporter: &dyn Reporter) -> Result<bool> {
    let dir = layout.fit_dir();
    unless_done(&dir, "fit", reporter, || {
        let config = FitConfig::load_or_default(options.fit_config.as_deref())?;
        let fit = FitOptions {
            sample: &options.sample,
            faces: &options.faces,
            config: &config,
            rings: options.rings,
        };
        fit_into(&fit, &dir, reporter).map(drop)
    })
}

fn train_step(layout: &RunLayout, options: &RunOptions, reporter: &dyn Reporter) -> Result<bool> {
    let dir = layout.train_dir();
    // Training writes model.bpk, then model.toml, loss.csv and loss.png: only the marker
    // written after all of them says the stage is complete (a kill between them resumes
    // from the final checkpoint and writes the rest).
    if skip_if_done(&dir, "train", reporter) {
        return Ok(true);
    }
    let resume = snapshot::exists(&dir);
    reporter.note(if resume {
        "== train (resuming)"
    } else {
        "== train"
    });
    let start = if resume {
        TrainStart::Resume
    } else {
        TrainStart::Fresh {
            fit: layout.fit_dir(),
            config: nca_config_file(layout, &options.nca)?,
            faces: options.faces.clone(),
        }
    };
    let train = TrainStageOptions {
        sample: &options.sample,
        start,
        device: options.device,
        stop_after: None,
    };
    train_into(&train, &dir, reporter)?;
    if dir.join(WEIGHTS_FILE).is_file() {
        mark_done(&dir)?;
    }
    Ok(false)
}

/// The NCA config file the training reads: the given one, or a copy of the built-in one
/// in the run folder.
fn nca_config_file(layout: &RunLayout, nca: &NcaSource) -> Result<PathBuf> {
    Ok(match nca {
        NcaSource::File(path) => path.clone(),
        NcaSource::Preset(preset) => {
            let path = layout.preset_copy(preset.name());
            write_bytes_atomic(&path, preset.text().as_bytes())?;
            path
        }
    })
}

fn synth_step(layout: &RunLayout, options: &RunOptions, reporter: &dyn Reporter) -> Result<bool> {
    let dir = layout.synth_dir();
    unless_done(&dir, "synth", reporter, || {
        let synth = SynthStageOptions {
            size: None,
            steps: options.synth_steps,
            seed: None,
            device: options.device,
            engine: options.engine,
        };
        synth_into(&layout.train_dir(), &synth, &dir, reporter)
    })
}
