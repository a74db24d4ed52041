//! The built-in default job, needing no external data: a synthetic sample cube from a
//! species preset (with its hidden truth) written into the run folder, then the whole
//! pipeline on it with the quick NCA config.

use std::path::PathBuf;

use super::reporter::Reporter;
use super::run::{RunOutcome, run};
use super::run_options::{NcaSource, RunOptions};
use crate::Result;
use crate::device::DeviceKind;
use crate::io::OutputDir;
use crate::nca::config::Engine;
use crate::presets::{NcaPreset, load_species_preset};
use crate::procedural::write_sample;
use crate::rings::RingSource;
use crate::run_folder::RunLayout;

/// Options of the demo.
#[derive(Clone, Debug)]
pub struct DemoOptions {
    /// Species preset of the synthetic sample.
    pub species: String,
    /// Face image side of the synthetic sample, in pixels.
    pub size: usize,
    /// NCA training config (default: the built-in quick config).
    pub nca_config: Option<PathBuf>,
    pub synth_steps: usize,
    pub device: DeviceKind,
    pub engine: Engine,
}

/// Tile size of the demo's sheet and renders.
const DEMO_TILE: usize = 160;

/// Writes the sample (unless an earlier call did) and runs the pipeline on it.
pub fn demo(
    layout: &RunLayout,
    options: &DemoOptions,
    reporter: &dyn Reporter,
) -> Result<RunOutcome> {
    OutputDir::prepare(layout.root())?;
    let sample = layout.demo_sample();
    if !sample.join("truth/species.toml").is_file() {
        reporter.note(&format!("== sample ({})", options.species));
        let cfg = load_species_preset(&options.species)?;
        let origin = format!("built-in species preset {}", options.species);
        write_sample(&cfg, &origin, options.size, &OutputDir::prepare(&sample)?)
            .map_err(|e| e.during(format!("writing the synthetic sample of {origin}")))?;
    }
    let run_options = RunOptions {
        sample,
        faces: crate::frame::Face::ALL.to_vec(),
        nca: match &options.nca_config {
            Some(path) => NcaSource::File(path.clone()),
            None => NcaSource::Preset(NcaPreset::Quick),
        },
        fit_config: None,
        rings: RingSource::Auto,
        species: options.species.clone(),
        synth_steps: options.synth_steps,
        image_size: DEMO_TILE,
        device: options.device,
        engine: options.engine,
    };
    run(layout, &run_options, reporter)
}
