//! Synthesis: unroll a trained model over a whole n^3 volume and return its colours.
//!
//! The seed state is a hash of (seed, voxel), B and G are sampled at the voxel centres, the
//! unroll runs slab by slab (`unroll`), and the colour is B + state[0..3] in white-balanced
//! space, divided by the white balance to return to photo colours: a `[N, N, N, 3]` volume in
//! the foundation's axis order, itself a solid texture (trilinear lookup).
//!
//! The unroll runs in the fused kernels (`nca::fused`, default) or in burn
//! (`Engine::Burn`, the reference; slab by slab). The fused path never builds burn tensors of
//! the volume: at 256^3 the state is 0.8 GB and the unroll needs two of them.
//!
//! Scale: the NCA learnt its texture per voxel of the training grid (`model.toml` `grid`).
//! Synthesising at another size changes the size of pores and rays relative to the cube by
//! size / grid; the CLI defaults to the training grid.

use burn::tensor::Device;

use super::config::Engine;
use super::fused::{FixedInputs, Isa, MlpWeights, Stepper};
use super::model::StepInputs;
use super::model_dir::TrainedModel;
use super::region::Region;
use super::targets::to_photo_colour;
use super::tensors::tensor_to_volume;
use super::unroll::{seed_data, seed_state, unroll};
use crate::error::Result;
use crate::volume::Volume;

/// What to synthesise.
#[derive(Clone, Debug)]
pub struct SynthOptions {
    pub size: usize,
    pub steps: usize,
    /// Seed of the initial state.
    pub seed: u64,
    /// Largest number of voxels updated at once (burn engine).
    pub slab_voxels: usize,
    pub engine: Engine,
}

/// Unrolls `trained` into an RGB volume (photo colours), calling `progress(step)`.
pub fn synthesise(
    trained: &TrainedModel,
    options: &SynthOptions,
    device: &Device,
    progress: impl FnMut(usize),
) -> Result<Volume> {
    if options.engine == Engine::Fused {
        return synthesise_fused(trained, options, progress);
    }
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

/// [`synthesise`] with the fused kernels, on plain buffers.
fn synthesise_fused(
    trained: &TrainedModel,
    options: &SynthOptions,
    progress: impl FnMut(usize),
) -> Result<Volume> {
    let spec = &trained.meta.spec;
    let norm = &trained.meta.normalisation;
    let region = Region::whole(options.size);
    let (cond, colour) = {
        let vols = trained.fit.conditioning().sample(&region);
        (
            norm.cond_data(&spec.conditioning, &vols),
            norm.colour_data(&vols),
        )
    };
    let fixed = FixedInputs::new(&region, cond, spec.cond_channels())?;
    let weights = MlpWeights::from_model(&trained.model)?;
    let stepper = Stepper::new(Isa::best(), &weights, &fixed)?;
    let seed = seed_data(
        spec.state_channels,
        spec.seed_amplitude,
        &region,
        options.seed,
    );
    let state = stepper.unroll(seed, options.steps, progress);
    // [X, Y, Z, 3] = white-balanced B + state RGB, back to photo colours.
    let n = region.voxels();
    let mut data = vec![0.0f32; 3 * n];
    for (v, px) in data.chunks_exact_mut(3).enumerate() {
        for (c, value) in px.iter_mut().enumerate() {
            *value = state[c * n + v] + colour[c * n + v];
        }
        to_photo_colour(norm, px);
    }
    Volume::from_data(region.dims, 3, data)
}
