//! Synthesis: unroll a trained model over a whole n^3 volume and return its colours.
//!
//! The seed state is a hash of (seed, voxel), B and G are sampled at the voxel centres, the
//! unroll runs slab by slab (`unroll`), and the colour is B + state[0..3] in white-balanced
//! space, divided by the white balance to return to photo colours: a `[N, N, N, 3]` volume in
//! the foundation's axis order, itself a solid texture (trilinear lookup).
//!
//! Scale: the NCA learnt its texture per voxel of the training grid (`model.toml` `grid`).
//! Synthesising at another size changes the size of pores and rays relative to the cube by
//! size / grid; the CLI defaults to the training grid.

use burn::tensor::Device;

use super::model::StepInputs;
use super::model_dir::TrainedModel;
use super::region::Region;
use super::targets::to_photo_colour;
use super::tensors::tensor_to_volume;
use super::unroll::{seed_state, unroll};
use crate::error::Result;
use crate::volume::Volume;

/// What to synthesise.
#[derive(Clone, Debug)]
pub struct SynthOptions {
    pub size: usize,
    pub steps: usize,
    /// Seed of the initial state.
    pub seed: u64,
    /// Largest number of voxels updated at once.
    pub slab_voxels: usize,
}

/// Unrolls `trained` into an RGB volume (photo colours), calling `progress(step)`.
pub fn synthesise(
    trained: &TrainedModel,
    options: &SynthOptions,
    device: &Device,
    progress: impl FnMut(usize),
) -> Result<Volume> {
    let spec = &trained.meta.spec;
    let norm = &trained.meta.normalisation;
    let region = Region::whole(options.size);
    let vols = trained.fit.conditioning().sample(&region);
    let cond = (!spec.conditioning.is_empty())
        .then(|| norm.cond_tensor(&spec.conditioning, &vols, device));
    let inputs = StepInputs::new(cond, region.positions(device), spec.perception);
    let seed = seed_state(
        spec.state_channels,
        spec.seed_amplitude,
        &region,
        options.seed,
        device,
    );
    let state = unroll(
        &trained.model,
        seed,
        &inputs,
        options.steps,
        options.slab_voxels,
        progress,
    );
    let rgb = state.narrow(0, 0, 3) + norm.colour_tensor(&vols, device);
    let mut volume = tensor_to_volume(rgb)?;
    for px in volume.data.chunks_exact_mut(3) {
        to_photo_colour(norm, px);
    }
    Ok(volume)
}
