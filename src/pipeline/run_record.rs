//! What makes a run folder resumable: `run.toml` records everything that decides the reused
//! stages (fit, train, synth) and refuses a re-run with other inputs, and each stage folder
//! gets a completion marker after its last output, so a killed stage is redone.

use std::path::Path;

use super::run_options::{NcaSource, RunOptions};
use crate::Result;
use crate::io::{Provenance, write_bytes_atomic};
use crate::rings::RingSource;
use crate::run_folder::{DONE_MARKER, RunLayout, STAGE_DIRS};

/// Records the run's inputs in a new folder, or checks them against the record of a started
/// one (the error names every difference).
pub(super) fn check_or_record(layout: &RunLayout, options: &RunOptions) -> Result<()> {
    let started = STAGE_DIRS.iter().any(|d| layout.path(d).exists());
    provenance(options)?.check_or_record(&layout.record(), started)
}

/// Everything that decides the reused stages; the sheet, renders, metrics and report are
/// redone on every call.
fn provenance(options: &RunOptions) -> Result<Provenance> {
    let letters: Vec<String> = options
        .faces
        .iter()
        .map(|f| f.letter().to_string())
        .collect();
    let mut record = Provenance::default()
        .with_folder("sample", &options.sample)?
        .with("faces", letters.join(","))
        .with("synth_steps", options.synth_steps.to_string())
        .with("engine", format!("{:?}", options.engine))
        .with("device", format!("{:?}", options.device));
    record = match &options.nca {
        NcaSource::File(path) => record.with_file("nca_config", path)?,
        NcaSource::Preset(preset) => record
            .with("nca_config", format!("built-in {}", preset.name()))
            .with_text("nca_config_hash", preset.text()),
    };
    // Recorded only when not the default, so run folders made before `rings` existed resume.
    if options.rings != RingSource::Auto {
        record = record.with("rings", options.rings.to_string());
    }
    Ok(match &options.fit_config {
        Some(path) => record.with_file("fit_config", path)?,
        None => record.with("fit_config", "built-in defaults"),
    })
}

/// Whether the stage in `dir` finished (its completion marker exists).
pub(crate) fn is_done(dir: &Path) -> bool {
    dir.join(DONE_MARKER).is_file()
}

/// Marks the stage in `dir` complete.
pub(crate) fn mark_done(dir: &Path) -> Result<()> {
    write_bytes_atomic(&dir.join(DONE_MARKER), b"complete\n")
}
