//! The synthesis stage: a trained NCA unrolled into a colour volume and its standard images
//! (`xylem synth`, and `synth/` of a run).

use std::path::Path;

use super::reporter::Reporter;
use crate::Result;
use crate::config::write_config_copy;
use crate::device::DeviceKind;
use crate::field::GrainShaded;
use crate::io::OutputDir;
use crate::io::npy::write_volume;
use crate::nca::config::Engine;
use crate::nca::model_dir::TrainedModel;
use crate::nca::synth::{SynthOptions, ValueRange, synthesise};
use crate::outputs::SliceSet;

/// How to unroll.
#[derive(Clone, Copy, Debug)]
pub struct SynthStageOptions {
    /// Volume side in voxels (default: the training grid).
    pub size: Option<usize>,
    /// Unroll steps.
    pub steps: usize,
    /// Seed of the initial state and the grain noise (default: the training seed).
    pub seed: Option<u64>,
    /// CPU backend of the burn engine (and for loading the weights).
    pub device: DeviceKind,
    pub engine: Engine,
}

/// Unrolls the model in `model_dir` and writes `volume.npy` (float32 [N, N, N, 3], RGB, not
/// clamped, the plain colour at the sample's white balance), the faces, cuts and cross (seen
/// with the fit's grain shading, when it has one), and `model.toml` into `out`.
pub fn synth_into(
    model_dir: &Path,
    options: &SynthStageOptions,
    out: &Path,
    reporter: &dyn Reporter,
) -> Result<()> {
    let device = options.device.device();
    let trained = TrainedModel::load(model_dir, &device)?;
    let dir = OutputDir::prepare(out)?;
    let size = options.size.unwrap_or(trained.meta.grid);
    let synth = SynthOptions {
        size,
        steps: options.steps,
        seed: options.seed.unwrap_or(trained.meta.seed),
        slab_voxels: 1 << 18,
        engine: options.engine,
    };
    let bar = reporter.counter("unroll", options.steps as u64);
    let volume = synthesise(&trained, &synth, &device, |s| bar.set_position(s as u64))?;
    bar.finish();
    let range = ValueRange::of(&volume.data);
    reporter.note(&format!("colour values in {range} (not clamped)"));
    if range.ran_away() {
        reporter.note(&format!(
            "warning: {} values sit at the colour bounds: the NCA state has probably run away \
             somewhere (a blown-out blob, often on a knot no training face showed); look at the \
             faces and cuts; a rare blob depends on the seed: synthesise again with another \
             (`xylem synth --model MODEL --seed 2`, MODEL = RUN/train after `xylem run`), or \
             unroll fewer steps (--steps 24)",
            range.pinned_count
        ));
    }
    write_volume(&dir.path("volume.npy"), &volume)?;
    let white_balance = trained
        .fit
        .field
        .base_colour
        .as_ref()
        .map(|c| &c.white_balance);
    SliceSet::render(&GrainShaded::new(&volume, white_balance), size).write(&dir, "")?;
    write_config_copy(
        &dir.path("model.toml"),
        &trained.meta,
        &model_dir.display().to_string(),
    )?;
    reporter.say(&format!(
        "wrote {}/volume.npy and its faces, cuts and unfolded.png",
        out.display()
    ));
    Ok(())
}
