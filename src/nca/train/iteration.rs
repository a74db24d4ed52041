//! One training iteration and the state it carries (DESIGN section 6):
//! 1. draw the unroll length, the pool slot, the region (a crop) and the seed key from
//!    the iteration's own random stream (`Rng::substream(seed, iteration)`), so a resumed run
//!    draws exactly what an uninterrupted one would;
//! 2. start from a fresh seed or the pool slot's state;
//! 3. unroll with segment checkpointing and backpropagate
//!    style(faces of B + state[0..3]) + w mean|S - clamp(S, -1, 1)|, in the fused kernels
//!    (`nca::fused`, the default) or in burn (`compute.engine = "burn"`, the reference);
//!    burn differentiates the loss either way;
//! 4. normalise each parameter's gradient, g / (|g| + 1e-8), and take an Adam step with the
//!    scheduled learning rate;
//! 5. write the final state back to the pool slot.

use std::collections::HashMap;

use burn::module::{Module, Param};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::tensor::{Device, Tensor};

use super::face_guides::{GUIDE_CHANNELS, phase_channels, phase_guides};
use super::loss::FaceLoss;
use super::loss_log::LossRow;
use super::low_band::{LowBand, phase_bins};
use super::placement::draw_fresh;
use super::pool::{Pool, Start};
use super::targets::{face_targets, match_base_means};
use crate::device::DeviceKind;
use crate::error::Result;
use crate::frame::Face;
use crate::image2::Image2;
use crate::nca::checkpoint::{Objective, UnrollGradients, unroll_gradients};
use crate::nca::colour_axes::colour_projection;
use crate::nca::conditioning::{Conditioning, Normalisation};
use crate::nca::config::{Engine, LowBandReference, TargetColour, TrainConfig};
use crate::nca::faces::{
    FacePatch, face_patches, inner_patches, layout, nearest_face_planes, nearest_faces,
};
use crate::nca::fit_source::FitRecord;
use crate::nca::fused::{FixedInputs, Isa, MlpWeights, Stepper, burn_bridge};
use crate::nca::model::{Nca, StepInputs};
use crate::nca::readout::Readout;
use crate::nca::region::Region;
use crate::nca::tensors::{tensor_from, to_vec};
use crate::nca::unroll::{seed_state, unroll};
use crate::rng::Rng;
use crate::sample::Sample;

/// Tag of the training random streams.
const TRAIN_STREAM: u64 = 0x4E43_415F_5452_4149; // "NCA_TRAI"
/// Tag of the streams drawing the depths of the planes inside the crop.
const PLANE_STREAM: u64 = 0x4E43_415F_504C_414E; // "NCA_PLAN"

/// What training learns from: targets, B and G, their normalisation.
pub struct TrainData {
    pub faces: Vec<Face>,
    /// Targets in the NCA's colour space at the training grid side (`None` for unused faces;
    /// see `TargetColour`).
    pub targets: [Option<Image2>; 6],
    /// Ring-phase guides of the used faces at the same size (`face_guides`).
    pub guides: [Option<Image2>; 6],
    pub fit: FitRecord,
    pub conditioning: Conditioning,
    pub normalisation: Normalisation,
}

impl TrainData {
    /// Targets from the sample's photos, B and G from the fit (`fit_source::load_fit`), at the
    /// config's grid side and in its target colour.
    pub fn prepare(sample: &Sample, fit: FitRecord, config: &TrainConfig) -> Self {
        let grid = config.volume.size;
        let (mut targets, photo_mean) = face_targets(sample, grid);
        let conditioning = fit
            .conditioning()
            .for_model(&config.model, config.seed, 1.0);
        let mut normalisation = conditioning.normalisation(photo_mean);
        let mean_source = match config.loss.target_colour {
            TargetColour::Base => Some(conditioning.colour.clone()),
            TargetColour::Shown => Some(fit.shown_colour()),
            TargetColour::Face => None,
        };
        if let Some(source) = mean_source {
            match_base_means(&mut targets, source.as_ref(), &normalisation, grid);
        }
        normalisation.colour_projection = colour_projection(&targets, config.model.colour_axes);
        let guides = phase_guides(conditioning.growth.as_ref(), &sample.faces, grid);
        Self {
            faces: sample.faces.clone(),
            targets,
            guides,
            fit,
            conditioning,
            normalisation,
        }
    }
}

/// The fixed step inputs of a region in the form the engine wants.
enum EngineInputs {
    Burn(StepInputs),
    Fused(FixedInputs),
}

/// Per region, everything that is fixed during training (no autodiff).
struct RegionInputs {
    region: Region,
    step: EngineInputs,
    /// The used faces this region touches.
    faces: Vec<Face>,
    /// For a region that touches none, with `[loss] interior_style`: the used face nearest
    /// on each axis (`faces::nearest_faces`), whose photos its inner planes are compared with.
    nearest: Vec<Face>,
    /// White-balanced B over the region, `[3, X, Y, Z]`.
    colour: Tensor<4>,
    /// Ring-phase guide over the region, `[2, X, Y, Z]` (planes inside the crop).
    guide: Tensor<4>,
    /// The colour readout.
    readout: Readout,
    /// The white balance and colour projection the readout and the residual need.
    normalisation: Normalisation,
    /// Ring-phase bin of every voxel (`low_band::phase_bins`), `[X * Y * Z]`; empty unless
    /// the low band's reference is the ring phase.
    phase_bins: Vec<u8>,
}

/// What an iteration starts from.
struct Draw {
    steps: usize,
    /// Steps run without gradients on a fresh seed before the iteration's unroll (0 for a
    /// state from the pool).
    burn_in: usize,
    region: Region,
    /// `[C, X, Y, Z]`, no autodiff.
    start: Tensor<4>,
    /// The pool slot the result is written back to.
    slot: Option<usize>,
}

/// What the trainer keeps of the training data to build a region's inputs.
struct RegionSource {
    faces: Vec<Face>,
    conditioning: Conditioning,
    normalisation: Normalisation,
}

/// The training state: model, optimiser, pool, iteration.
pub struct Trainer {
    pub config: TrainConfig,
    pub model: Nca,
    pub optimiser: ModuleOptimizer,
    pub pool: Pool,
    pub iteration: usize,
    pub kind: DeviceKind,
    /// Instruction set of the fused kernels.
    pub isa: Isa,
    source: RegionSource,
    /// Inputs of the regions the pool holds (sampling B and G again costs ~10 ms a crop).
    inputs: HashMap<Region, RegionInputs>,
    /// Plain device (no autodiff) for seeds and pool states.
    device: Device,
}

/// Adam as DESIGN section 6 sets it (PyTorch's defaults: betas 0.9, 0.999, epsilon 1e-8).
pub fn adam() -> ModuleOptimizer {
    AdamConfig::new().with_epsilon(1e-8).init()
}

impl Trainer {
    /// A fresh trainer: model initialised from the config seed, empty pool, iteration 0.
    pub fn new(config: &TrainConfig, data: &TrainData, kind: DeviceKind) -> Result<Self> {
        let device = kind.device();
        let model = Nca::init(&config.model, config.seed, &kind.autodiff_device());
        let optimiser = adam();
        if data.faces.is_empty() {
            return Err(crate::XylemError::input(
                "training data",
                "no face to train on",
            ));
        }
        check_training_memory(config)?;
        Ok(Self {
            config: config.clone(),
            model,
            optimiser,
            pool: Pool::new(config.pool.size),
            iteration: 0,
            kind,
            isa: Isa::best(),
            source: RegionSource {
                faces: data.faces.clone(),
                conditioning: data.conditioning.clone(),
                normalisation: data.normalisation.clone(),
            },
            inputs: HashMap::new(),
            device,
        })
    }

    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Shape `[C, X, Y, Z]` of the states trained on (every region has the crop's size).
    pub fn state_dims(&self) -> [usize; 4] {
        let side = self.config.volume.crop_side();
        [self.config.model.state_channels, side, side, side]
    }

    /// The model without autodiff (for saving and synthesis).
    pub(crate) fn plain_model(&self) -> Nca {
        self.model.valid()
    }

    /// The random choices of iteration `it`: unroll length, region, start state, pool slot.
    fn draw(&self, it: usize) -> Draw {
        let cfg = &self.config;
        let mut rng = Rng::substream(cfg.seed ^ TRAIN_STREAM, it as u64);
        let [lo, hi] = cfg.schedule.steps;
        let steps = lo + rng.below(hi - lo + 1);
        let slot_draw = rng.below(self.pool.len().max(1));
        let fresh_region = draw_fresh(&cfg.volume, &self.source.faces, &mut rng);
        let seed_key = rng.next_u64();
        let [b_lo, b_hi] = cfg.schedule.burn_in;
        let burn_in = b_lo + rng.below(b_hi - b_lo + 1);
        let fresh = it.is_multiple_of(cfg.pool.fresh_every);
        let (region, start, slot, burn_in) = match self.pool.start(slot_draw, fresh) {
            Start::Fresh { slot } => {
                let seed = seed_state(
                    cfg.model.state_channels,
                    cfg.model.seed_amplitude,
                    &fresh_region,
                    seed_key,
                    &self.device,
                );
                (fresh_region, seed, slot, burn_in)
            }
            Start::Continue { slot, from } => (from.region, from.state, Some(slot), 0),
        };
        Draw {
            steps,
            burn_in,
            region,
            start,
            slot,
        }
    }

    /// The inputs of `region`, built on first use.
    fn region_inputs(&mut self, region: Region) -> Result<&RegionInputs> {
        if !self.inputs.contains_key(&region) {
            let inputs = region_inputs(region, &self.config, &self.source, &self.device)?;
            self.inputs.insert(region, inputs);
        }
        Ok(&self.inputs[&region])
    }

    /// Runs iteration `self.iteration` and returns its log row.
    pub fn iterate(&mut self, loss: &dyn FaceLoss) -> Result<LossRow> {
        let it = self.iteration;
        let Draw {
            steps,
            burn_in,
            region,
            start,
            slot,
        } = self.draw(it);
        let weights = TermWeights {
            overflow: self.config.loss.overflow,
            low_band: self.config.loss.low_band,
            low_band_shape: LowBand {
                block: self.config.loss.low_band_block,
                reference: self.config.loss.low_band_reference,
            },
        };
        let segment = self.config.memory.segment_steps;
        let (isa, device) = (self.isa, self.device.clone());
        let model = self.model.clone();
        let depths = plane_depths(&self.config, it);
        let inputs = self.region_inputs(region)?;
        let start = burn_in_state(&model, start, inputs, isa, burn_in, &device)?;
        let loss_of = |state| objective(state, inputs, loss, it, &depths, &weights);
        let out: UnrollGradients = match &inputs.step {
            EngineInputs::Burn(step) => {
                unroll_gradients(&model, start, step, steps, segment, loss_of)
            }
            EngineInputs::Fused(fixed) => burn_bridge::unroll_gradients(
                &model, &device, isa, start, fixed, steps, segment, loss_of,
            )?,
        };
        let lr = self.config.learning_rate(it);
        // A non-finite loss (a pool state that ran away, or a spike) would turn every weight
        // into NaN: its update is skipped and its pool slot emptied, so the slot starts from
        // a fresh seed when it is drawn again. The session decides when that is too often.
        let finite = out.loss.is_finite();
        let term = |name: &str| {
            out.terms
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(0.0, |t| t.1)
        };
        // A finite state that ran away still teaches the rule (its overflow gradient), but
        // continued it only grows: it is not stored back.
        let keep = finite && !self.config.pool.ran_away(term("overflow"));
        if finite {
            let grads = normalise_gradients(&self.model, out.grads);
            self.model = self.optimiser.step(lr, self.model.clone(), grads);
        }
        match slot {
            Some(slot) if keep => self.pool.put(slot, region, out.final_state),
            Some(slot) => self.pool.clear(slot),
            None => {}
        }
        let kept: Vec<Region> = self.pool.regions().copied().collect();
        self.inputs.retain(|r, _| kept.contains(r));
        self.iteration += 1;
        Ok(LossRow {
            iteration: it,
            steps,
            loss: out.loss,
            style: term("style"),
            overflow: term("overflow"),
            low_band: term("low_band"),
            learning_rate: lr,
        })
    }
}

/// Refuses a crop and unroll whose autodiff tape would not fit in memory.
fn check_training_memory(config: &TrainConfig) -> Result<()> {
    let crop = config.volume.crop_side();
    let [_, longest] = config.schedule.steps;
    let segment = config.memory.segment_steps;
    let tape = if segment == 0 {
        longest
    } else {
        segment.min(longest)
    };
    crate::memory::check_fits(
        "training config [volume] crop",
        crate::memory::training_bytes(crop, tape.max(1)),
        &format!(
            "{crop}^3 crops with {tape} steps on the tape; use a smaller crop or set \
             [memory] segment_steps"
        ),
    )
}

/// Conditioning, positions and B's face patches of one region.
fn region_inputs(
    region: Region,
    cfg: &TrainConfig,
    data: &RegionSource,
    device: &Device,
) -> Result<RegionInputs> {
    let vols = data.conditioning.sample(&region);
    let channels = &cfg.model.conditioning;
    let cond = data.normalisation.cond_data(channels, &vols);
    let k = cfg.model.cond_channels();
    let step = match cfg.compute.engine {
        Engine::Fused => EngineInputs::Fused(
            FixedInputs::new(&region, cond, k)?.with_positions(cfg.model.positions),
        ),
        Engine::Burn => {
            let [x, y, z] = region.dims;
            let cond = (k > 0).then(|| tensor_from(cond, [k, x, y, z], device));
            let positions = region.position_inputs(cfg.model.positions, device);
            EngineInputs::Burn(StepInputs::new(cond, positions, cfg.model.perception))
        }
    };
    let colour = data.normalisation.colour_tensor(&vols, device);
    let faces: Vec<Face> = data
        .faces
        .iter()
        .copied()
        .filter(|&f| layout(f).touches(&region))
        .collect();
    let nearest = if faces.is_empty() && cfg.loss.interior_style {
        nearest_faces(&region, &data.faces)
    } else {
        Vec::new()
    };
    let phase_bins =
        if cfg.loss.low_band > 0.0 && cfg.loss.low_band_reference == LowBandReference::RingPhase {
            phase_bins(&vols.g.data)
        } else {
            Vec::new()
        };
    let [x, y, z] = region.dims;
    let guide = tensor_from(
        phase_channels(&vols.g.data),
        [GUIDE_CHANNELS, x, y, z],
        device,
    );
    Ok(RegionInputs {
        region,
        step,
        faces,
        nearest,
        colour,
        readout: cfg.model.readout,
        normalisation: data.normalisation.clone(),
        guide,
        phase_bins,
    })
}

/// `steps` steps of `model` from `start` without gradients (the burn-in of a fresh seed).
fn burn_in_state(
    model: &Nca,
    start: Tensor<4>,
    inputs: &RegionInputs,
    isa: Isa,
    steps: usize,
    device: &Device,
) -> Result<Tensor<4>> {
    if steps == 0 {
        return Ok(start);
    }
    let plain = model.valid();
    Ok(match &inputs.step {
        EngineInputs::Burn(step) => unroll(&plain, start, step, steps, usize::MAX, |_| {}),
        EngineInputs::Fused(fixed) => {
            let weights = MlpWeights::from_model(&plain)?;
            let stepper = Stepper::new(isa, &weights, fixed)?;
            let dims = start.dims();
            let state = stepper.unroll(to_vec(start)?, steps, |_| {});
            tensor_from(state, dims, device)
        }
    })
}

/// Depths (voxels from the face) of the planes inside the crop that iteration `it` also
/// compares with the photos: `inner_planes` of them, uniform in [1, crop - 2].
fn plane_depths(cfg: &TrainConfig, it: usize) -> Vec<usize> {
    let side = cfg.volume.crop_side();
    if side < 3 {
        return Vec::new();
    }
    let mut rng = Rng::substream(cfg.seed ^ PLANE_STREAM, it as u64);
    (0..cfg.loss.inner_planes)
        .map(|_| 1 + rng.below(side - 2))
        .collect()
}

/// The weights of the terms beside the face loss (`[loss]`).
struct TermWeights {
    overflow: f32,
    low_band: f32,
    low_band_shape: LowBand,
}

/// style(faces of B + state RGB, and the planes at `depths` parallel to them)
/// + w_o x mean |S - clamp(S, -1, 1)| + w_l x low_band(residual).
fn objective(
    state: Tensor<4>,
    inputs: &RegionInputs,
    loss: &dyn FaceLoss,
    iteration: usize,
    depths: &[usize],
    weights: &TermWeights,
) -> Objective {
    let device = state.device();
    let norm = &inputs.normalisation;
    let residual = norm.residual_tensor(state.clone().narrow(0, 0, 3), &device); // [3, X, Y, Z]
    let low_band = (weights.low_band > 0.0).then(|| {
        weights
            .low_band_shape
            .term(residual.clone(), &inputs.phase_bins)
    });
    let sum = residual + inputs.colour.clone(); // [3, X, Y, Z]
    let rgb = inputs
        .readout
        .white_balanced(sum, norm.white_balance, &device);
    let mut faces: Vec<FacePatch> = face_patches(&rgb, &inputs.region, &inputs.faces);
    for &depth in depths {
        faces.extend(inner_patches(
            &rgb,
            &inputs.guide,
            &inputs.region,
            &inputs.faces,
            depth,
        ));
    }
    if !inputs.nearest.is_empty() {
        let side = inputs.region.dims[0];
        let interior_depths = if depths.is_empty() {
            vec![side / 2]
        } else {
            depths.to_vec()
        };
        for depth in interior_depths {
            faces.extend(nearest_face_planes(
                &rgb,
                &inputs.guide,
                &inputs.region,
                &inputs.nearest,
                depth,
            ));
        }
    }
    // A crop inside the cube without `interior_style` has no face to compare: only the
    // overflow and low-band terms judge it.
    let style = if faces.is_empty() {
        Tensor::zeros([1], &device)
    } else {
        loss.loss(&faces, iteration)
    };
    let overflow = (state.clone() - state.clamp(-1.0, 1.0)).abs().mean();
    let mut terms = vec![
        ("style", style.clone().inner().into_scalar::<f32>()),
        ("overflow", overflow.clone().inner().into_scalar::<f32>()),
    ];
    let mut total = style + overflow.mul_scalar(weights.overflow);
    if let Some(low_band) = low_band {
        terms.push(("low_band", low_band.clone().inner().into_scalar::<f32>()));
        total = total + low_band.mul_scalar(weights.low_band);
    }
    Objective { total, terms }
}

/// g / (|g| + 1e-8) for each parameter tensor (Mordvintsev et al.): every parameter moves by
/// about the learning rate whatever the loss scale.
fn normalise_gradients(model: &Nca, mut grads: GradientsParams) -> GradientsParams {
    fn norm_one<const D: usize>(grads: &mut GradientsParams, param: &Param<Tensor<D>>) {
        if let Some(g) = grads.remove::<D>(param.id) {
            let norm = g.clone().square().sum().sqrt().add_scalar(1e-8); // [1]
            let shape = [1; D];
            grads.register(param.id, g / norm.reshape(shape));
        }
    }
    norm_one(&mut grads, &model.w1);
    norm_one(&mut grads, &model.b1);
    norm_one(&mut grads, &model.w2);
    grads
}

/// Checks the model can be trained: at least one used face must have a target.
pub(crate) fn check_data(data: &TrainData) -> Result<()> {
    if data.targets.iter().all(Option::is_none) {
        return Err(crate::XylemError::input(
            "training data",
            "no face photo to train on",
        ));
    }
    Ok(())
}
