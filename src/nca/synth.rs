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

use super::conditioning::{CondVolumes, to_photo_colour};
use super::config::Engine;
use super::fused::{FixedInputs, Isa, MlpWeights, Stepper};
use super::grain_noise::cell_scale;
use super::model::StepInputs;
use super::model_dir::TrainedModel;
use super::readout::Readout;
use super::region::Region;
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

/// Refuses a volume the machine cannot hold while it unrolls.
fn check_synthesis_memory(size: usize) -> Result<()> {
    crate::memory::check_fits(
        "synthesis size",
        crate::memory::synthesis_bytes(size),
        &format!("a {size}^3 volume; use a smaller $size"),
    )
}

/// B, G and the model's grain noise (realisation `options.seed`) at the voxels of `region`.
fn conditioning_volumes(
    trained: &TrainedModel,
    options: &SynthOptions,
    region: &Region,
) -> CondVolumes {
    let scale = cell_scale(trained.meta.grid, options.size);
    trained
        .fit
        .conditioning()
        .for_model(&trained.meta.spec, options.seed, scale)
        .sample(region)
}

/// Unrolls `trained` into an RGB volume (photo colours), calling `progress(step)`.
/// Denormal floats are flushed to zero from here on in this process (see
/// [`flush_denormals_to_zero`](super::denormals::flush_denormals_to_zero)).
pub fn synthesise(
    trained: &TrainedModel,
    options: &SynthOptions,
    device: &Device,
    progress: impl FnMut(usize),
) -> Result<Volume> {
    if options.engine == Engine::Fused {
        return synthesise_fused(trained, options, progress); // flushes in synthesise_at
    }
    super::denormals::flush_denormals_to_zero();
    check_synthesis_memory(options.size)?;
    let spec = &trained.meta.spec;
    let norm = &trained.meta.normalisation;
    let region = Region::whole(options.size);
    let vols = conditioning_volumes(trained, options, &region);
    let cond = (!spec.conditioning.is_empty())
        .then(|| norm.cond_tensor(&spec.conditioning, &vols, device));
    let inputs = StepInputs::new(
        cond,
        region.position_inputs(spec.positions, device),
        spec.perception,
    );
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
    let sum =
        norm.residual_tensor(state.narrow(0, 0, 3), device) + norm.colour_tensor(&vols, device);
    let rgb = spec.readout.white_balanced(sum, norm.white_balance, device);
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
    let mut volumes = synthesise_at(trained, options, &[options.steps], progress)?;
    Ok(volumes.remove(0))
}

/// One fused unroll of `options.size`^3 from the seed, returning the colour volume after
/// each step count in `at` (ascending; `options.steps` is ignored): e.g. 24, 90 and 256
/// steps in one run, to see whether the texture holds past the training horizon.
pub fn synthesise_at(
    trained: &TrainedModel,
    options: &SynthOptions,
    at: &[usize],
    mut progress: impl FnMut(usize),
) -> Result<Vec<Volume>> {
    super::denormals::flush_denormals_to_zero();
    check_synthesis_memory(options.size)?;
    if at.windows(2).any(|w| w[0] > w[1]) {
        return Err(crate::XylemError::input(
            "synthesis step counts",
            format!("{at:?}: expected ascending step counts"),
        ));
    }
    let spec = &trained.meta.spec;
    let norm = &trained.meta.normalisation;
    let region = Region::whole(options.size);
    let (cond, colour) = {
        let vols = conditioning_volumes(trained, options, &region);
        (
            norm.cond_data(&spec.conditioning, &vols),
            norm.colour_data(&vols),
        )
    };
    let fixed =
        FixedInputs::new(&region, cond, spec.cond_channels())?.with_positions(spec.positions);
    let weights = MlpWeights::from_model(&trained.model)?;
    let stepper = Stepper::new(Isa::best(), &weights, &fixed)?;
    let mut state = seed_data(
        spec.state_channels,
        spec.seed_amplitude,
        &region,
        options.seed,
    );
    let mut done = 0;
    let mut volumes = Vec::with_capacity(at.len());
    for &target in at {
        state = stepper.unroll(state, target - done, |s| progress(done + s));
        done = target;
        volumes.push(colour_volume(
            &state,
            &colour,
            norm,
            spec.readout,
            region.dims,
        )?);
    }
    Ok(volumes)
}

/// `[X, Y, Z, 3]` = white-balanced B + state RGB, back to photo colours, read out.
fn colour_volume(
    state: &[f32],
    colour: &[f32],
    norm: &super::conditioning::Normalisation,
    readout: Readout,
    dims: [usize; 3],
) -> Result<Volume> {
    let n = dims.iter().product::<usize>();
    let mut data = vec![0.0f32; 3 * n];
    for (v, px) in data.chunks_exact_mut(3).enumerate() {
        let residual = norm.residual([0, 1, 2].map(|c| state[c * n + v]));
        for (c, value) in px.iter_mut().enumerate() {
            *value = residual[c] + colour[c * n + v];
        }
        to_photo_colour(norm, px);
        for value in px.iter_mut() {
            *value = readout.photo(*value);
        }
    }
    Volume::from_data(dims, 3, data)
}

/// The spread of a colour volume's values: an NCA that stays on its attractor keeps every
/// value in [0, 1] on its own (nothing is clamped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValueRange {
    pub min: f32,
    pub max: f32,
    /// Number of values below 0 or above 1 (a fraction alone rounds rare ones away).
    pub outside_count: usize,
    /// Number of values within [`PIN_MARGIN`] of 0 or 1 (or beyond): where a bounded readout
    /// hides a state that ran away (BENCHMARKS "a runaway knot on H11 F").
    pub pinned_count: usize,
    /// Number of values looked at.
    pub values: usize,
}

/// How close to 0 or 1 a value counts as pinned by the readout's bounds.
pub const PIN_MARGIN: f32 = 0.005;
/// Share of pinned values above which a volume is reported as run away: measured at most
/// 2.3e-6 on the good 256^3 volumes of the held-out runs (90 and 256 steps) and 5.1e-2 and
/// 1.1e-1 on the two that ran away (BENCHMARKS "a runaway knot on H11 F", "a runaway
/// interior on H11 B"), so the bar sits well between.
pub const RUNAWAY_FRACTION: f64 = 1e-4;

impl ValueRange {
    pub fn of(values: &[f32]) -> Self {
        let (mut min, mut max, mut outside) = (f32::INFINITY, f32::NEG_INFINITY, 0usize);
        let mut pinned = 0usize;
        for &v in values {
            min = min.min(v);
            max = max.max(v);
            if !(0.0..=1.0).contains(&v) {
                outside += 1;
            }
            if !(PIN_MARGIN..=1.0 - PIN_MARGIN).contains(&v) {
                pinned += 1;
            }
        }
        Self {
            min,
            max,
            outside_count: outside,
            pinned_count: pinned,
            values: values.len(),
        }
    }

    /// Whether so many values sit at the bounds that the state has probably run away
    /// somewhere (a bounded readout keeps such a volume inside [0, 1]).
    pub fn ran_away(&self) -> bool {
        self.share(self.pinned_count) > RUNAWAY_FRACTION
    }

    /// Fraction of values below 0 or above 1.
    pub(crate) fn outside_fraction(&self) -> f64 {
        self.share(self.outside_count)
    }

    /// `count` as a fraction of the values looked at (0 for an empty volume).
    fn share(&self, count: usize) -> f64 {
        count as f64 / self.values.max(1) as f64
    }
}

/// `[min, max], N of M (fraction) outside [0, 1], P within 0.005 of 0 or 1`.
impl std::fmt::Display for ValueRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "[{:.3}, {:.3}], {} of {} ({:.2e}) outside [0, 1], {} within {} of 0 or 1",
            self.min,
            self.max,
            self.outside_count,
            self.values,
            self.outside_fraction(),
            self.pinned_count,
            PIN_MARGIN
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A volume with a blown-out blob (5 % of its values at the bounds, as the H11 F model at
    /// 90 steps) is reported as run away; one with a few dark pore values near 0 is not.
    #[test]
    fn values_pinned_at_the_bounds_mark_a_runaway() {
        let mut good: Vec<f32> = (0..100_000)
            .map(|i| 0.2 + 0.6 * (i % 97) as f32 / 96.0)
            .collect();
        good[7] = 0.001;
        good[11] = 0.999;
        let range = ValueRange::of(&good);
        assert_eq!((range.pinned_count, range.outside_count), (2, 0));
        assert!(!range.ran_away());
        let mut blob = good.clone();
        blob.iter_mut().step_by(20).for_each(|v| *v = 1.0);
        let range = ValueRange::of(&blob);
        assert_eq!(range.outside_count, 0);
        assert!(range.ran_away(), "{range}");
        assert!(range.to_string().contains("within 0.005 of 0 or 1"));
    }
}
