//! Unrolling the NCA: seeds and many steps.
//!
//! Large volumes are updated slab by slab along x: the hidden layer holds `hidden` floats per
//! voxel (1 GB for 128^3 at once), so each step pads the state once and runs the MLP on slabs
//! of at most `slab_voxels` voxels, each reading its one-voxel halo from the padded state. The
//! result is the same as one whole-volume step (tested), only the peak memory differs.
//! Training uses whole-region steps (`Nca::step`), which the autodiff tape needs anyway.

use burn::tensor::{Device, Tensor};
use rayon::prelude::*;

use super::model::{Nca, StepInputs};
use super::perception::pad_replicate;
use super::region::Region;
use super::tensors::tensor_from;
use crate::rng::{hash3, mix64, unit};

/// The seed state of a region `[C, X, Y, Z]`: uniform in [-amplitude, amplitude], a hash of
/// (key, channel, global voxel index), so a crop's seed equals the same part of the whole
/// volume's seed and nothing depends on thread scheduling.
pub fn seed_state(
    channels: usize,
    amplitude: f32,
    region: &Region,
    key: u64,
    device: &Device,
) -> Tensor<4> {
    let [dx, dy, dz] = region.dims;
    let data = seed_data(channels, amplitude, region, key);
    tensor_from(data, [channels, dx, dy, dz], device)
}

/// [`seed_state`] as plain data `[C, X, Y, Z]`.
pub(crate) fn seed_data(channels: usize, amplitude: f32, region: &Region, key: u64) -> Vec<f32> {
    let [dx, dy, dz] = region.dims;
    let n = dx * dy * dz;
    let mut data = vec![0.0f32; channels * n];
    data.par_chunks_mut(n).enumerate().for_each(|(c, plane)| {
        let channel_key = mix64(key ^ (c as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        for i in 0..dx {
            for j in 0..dy {
                for k in 0..dz {
                    let g = [
                        (region.offset[0] + i) as i32,
                        (region.offset[1] + j) as i32,
                        (region.offset[2] + k) as i32,
                    ];
                    let u = unit(hash3(channel_key, g[0], g[1], g[2]));
                    plane[(i * dy + j) * dz + k] = amplitude * (2.0 * u - 1.0);
                }
            }
        }
    });
    data
}

/// x-slabs `(start, len)` covering `x` voxels with at most `slab_voxels` voxels each.
pub fn slabs(dims: [usize; 3], slab_voxels: usize) -> Vec<(usize, usize)> {
    let plane = (dims[1] * dims[2]).max(1);
    let len = (slab_voxels / plane).clamp(1, dims[0]);
    (0..dims[0])
        .step_by(len)
        .map(|s| (s, len.min(dims[0] - s)))
        .collect()
}

/// One step, slab by slab. Same result as [`Nca::step`] with less memory.
pub fn step_in_slabs(
    model: &Nca,
    state: Tensor<4>,
    inputs: &StepInputs,
    slab_voxels: usize,
) -> Tensor<4> {
    let [_, x, y, z] = state.dims();
    let parts = slabs([x, y, z], slab_voxels);
    if parts.len() == 1 {
        return model.step(state, inputs);
    }
    let padded = pad_replicate(state.clone());
    let updated: Vec<Tensor<4>> = parts
        .into_iter()
        .map(|(start, len)| {
            let delta = model.delta(
                padded.clone().narrow(1, start, len + 2),
                inputs.slab(start, len),
                inputs.perception,
            );
            state.clone().narrow(1, start, len) + delta
        })
        .collect();
    Tensor::cat(updated, 1)
}

/// `steps` steps from `state`, calling `progress` after each.
pub fn unroll(
    model: &Nca,
    mut state: Tensor<4>,
    inputs: &StepInputs,
    steps: usize,
    slab_voxels: usize,
    mut progress: impl FnMut(usize),
) -> Tensor<4> {
    for s in 0..steps {
        state = step_in_slabs(model, state, inputs, slab_voxels);
        progress(s + 1);
    }
    state
}
