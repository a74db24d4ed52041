//! The options of a whole run (`xylem run`): what decides its stages and its pictures.

use std::path::PathBuf;

use crate::device::DeviceKind;
use crate::frame::Face;
use crate::nca::config::Engine;
use crate::presets::NcaPreset;
use crate::rings::RingSource;

/// The NCA training config of a run.
#[derive(Clone, Debug)]
pub enum NcaSource {
    /// A config file.
    File(PathBuf),
    /// A built-in config (copied into the run folder for the training).
    Preset(NcaPreset),
}

/// Everything a run needs besides its folder.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Sample folder (Mokume layout; a `truth/` folder adds the true cuts).
    pub sample: PathBuf,
    /// Faces fitted and trained on (the others are held out and judged).
    pub faces: Vec<Face>,
    pub nca: NcaSource,
    /// Fit config file (default: the built-in defaults).
    pub fit_config: Option<PathBuf>,
    /// Where the fit's ring images come from.
    pub rings: RingSource,
    /// Species preset shown on the fitted field (a synthetic sample shows its truth).
    pub species: String,
    /// NCA unroll steps of the synthesis.
    pub synth_steps: usize,
    /// Tile size of the sheet and side of the renders, in pixels.
    pub image_size: usize,
    /// CPU backend of the NCA's burn parts and of the metrics' features.
    pub device: DeviceKind,
    /// Synthesis unroll engine.
    pub engine: Engine,
}
