//! One training iteration and the state it carries (DESIGN section 6):
//! 1. draw the unroll length, the pool slot, the region (corner crop) and the seed key from
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

use burn::module::{Module, Param};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::tensor::{Device, Tensor};

use super::checkpoint::{Objective, UnrollGradients, unroll_gradients};
use super::conditioning::{Conditioning, Normalisation};
use super::config::{Engine, TrainConfig};
use super::faces::{FacePatch, face_patches};
use super::fit_source::FitRecord;
use super::fused::{FixedInputs, Isa, burn_bridge};
use super::loss::FaceLoss;
use super::loss_log::LossRow;
use super::model::{Nca, StepInputs};
use super::pool::{Pool, Start};
use super::region::Region;
use super::targets::face_targets;
use super::tensors::tensor_from;
use super::unroll::seed_state;
use crate::device::DeviceKind;
use crate::error::Result;
use crate::frame::Face;
use crate::image2::Image2;
use crate::rng::Rng;
use crate::sample::Sample;

/// Tag of the training random streams.
const TRAIN_STREAM: u64 = 0x4E43_415F_5452_4149; // "NCA_TRAI"

/// What training learns from: targets, B and G, their normalisation.
pub struct TrainData {
    pub faces: Vec<Face>,
    /// White-balanced targets at the training grid side (`None` for unused faces).
    pub targets: [Option<Image2>; 6],
    pub fit: FitRecord,
    pub conditioning: Conditioning,
    pub normalisation: Normalisation,
}

impl TrainData {
    /// Targets from the sample's photos, B and G from the fit (`fit_source::load_fit`).
    pub fn prepare(sample: &Sample, fit: FitRecord, grid: usize) -> Self {
        let (targets, photo_mean) = face_targets(sample, grid);
        let conditioning = fit.conditioning();
        let normalisation = conditioning.normalisation(photo_mean);
        Self {
            faces: sample.faces.clone(),
            targets,
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
    /// Their patches of white-balanced B, `[3, h, w]` each, in the same order.
    colour_faces: Vec<FacePatch>,
}

/// What an iteration starts from.
struct Draw {
    steps: usize,
    /// Index into the trainer's regions.
    region: usize,
    /// `[C, X, Y, Z]`, no autodiff.
    start: Tensor<4>,
    /// The pool slot the result is written back to.
    slot: Option<usize>,
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
    regions: Vec<RegionInputs>,
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
        let regions = Region::training_regions(config.volume.size, config.volume.crop)
            .into_iter()
            .map(|r| region_inputs(r, config, data, &device))
            .collect::<Result<_>>()?;
        Ok(Self {
            config: config.clone(),
            model,
            optimiser,
            pool: Pool::new(config.pool.size),
            iteration: 0,
            kind,
            isa: Isa::best(),
            regions,
            device,
        })
    }

    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Shape `[C, X, Y, Z]` of the states trained on (all regions have the same size).
    pub fn state_dims(&self) -> [usize; 4] {
        let [x, y, z] = self.regions[0].region.dims;
        [self.config.model.state_channels, x, y, z]
    }

    /// The model without autodiff (for saving and synthesis).
    pub fn plain_model(&self) -> Nca {
        self.model.valid()
    }

    /// The random choices of iteration `it`: unroll length, region, start state, pool slot.
    fn draw(&self, it: usize) -> Draw {
        let cfg = &self.config;
        let mut rng = Rng::substream(cfg.seed ^ TRAIN_STREAM, it as u64);
        let [lo, hi] = cfg.schedule.steps;
        let steps = lo + rng.below(hi - lo + 1);
        let slot_draw = rng.below(self.pool.len().max(1));
        let region_draw = rng.below(self.regions.len());
        let seed_key = rng.next_u64();
        let fresh = it.is_multiple_of(cfg.pool.fresh_every);
        let (region, start, slot) = match self.pool.start(slot_draw, fresh) {
            Start::Fresh { slot } => {
                let seed = seed_state(
                    cfg.model.state_channels,
                    cfg.model.seed_amplitude,
                    &self.regions[region_draw].region,
                    seed_key,
                    &self.device,
                );
                (region_draw, seed, slot)
            }
            Start::Continue { slot, from } => (from.region, from.state, Some(slot)),
        };
        Draw {
            steps,
            region,
            start,
            slot,
        }
    }

    /// Runs iteration `self.iteration` and returns its log row.
    pub fn iterate(&mut self, loss: &dyn FaceLoss) -> Result<LossRow> {
        let it = self.iteration;
        let Draw {
            steps,
            region: region_index,
            start,
            slot,
        } = self.draw(it);
        let cfg = &self.config;
        let inputs = &self.regions[region_index];
        let overflow_weight = cfg.loss.overflow;
        let segment = cfg.memory.segment_steps;
        let loss_of = |state| objective(state, inputs, loss, it, overflow_weight);
        let out: UnrollGradients = match &inputs.step {
            EngineInputs::Burn(step) => {
                unroll_gradients(&self.model, start, step, steps, segment, loss_of)
            }
            EngineInputs::Fused(fixed) => burn_bridge::unroll_gradients(
                &self.model,
                &self.device,
                self.isa,
                start,
                fixed,
                steps,
                segment,
                loss_of,
            )?,
        };
        let lr = cfg.learning_rate(it);
        let grads = normalise_gradients(&self.model, out.grads);
        self.model = self.optimiser.step(lr, self.model.clone(), grads);
        if let Some(slot) = slot {
            self.pool.put(slot, region_index, out.final_state);
        }
        self.iteration += 1;
        let term = |name: &str| {
            out.terms
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(0.0, |t| t.1)
        };
        Ok(LossRow {
            iteration: it,
            steps,
            loss: out.loss,
            style: term("style"),
            overflow: term("overflow"),
            learning_rate: lr,
        })
    }
}

/// Conditioning, positions and B's face patches of one region.
fn region_inputs(
    region: Region,
    cfg: &TrainConfig,
    data: &TrainData,
    device: &Device,
) -> Result<RegionInputs> {
    let vols = data.conditioning.sample(&region);
    let channels = &cfg.model.conditioning;
    let cond = data.normalisation.cond_data(channels, &vols);
    let k = cfg.model.cond_channels();
    let step = match cfg.compute.engine {
        Engine::Fused => EngineInputs::Fused(FixedInputs::new(&region, cond, k)?),
        Engine::Burn => {
            let [x, y, z] = region.dims;
            let cond = (k > 0).then(|| tensor_from(cond, [k, x, y, z], device));
            let positions = region.positions(device);
            EngineInputs::Burn(StepInputs::new(cond, positions, cfg.model.perception))
        }
    };
    let colour = data.normalisation.colour_tensor(&vols, device);
    let colour_faces = face_patches(&colour, &region, &data.faces);
    Ok(RegionInputs {
        region,
        step,
        faces: colour_faces.iter().map(|p| p.face).collect(),
        colour_faces,
    })
}

/// style(faces of B + state RGB) + w x mean |S - clamp(S, -1, 1)|.
fn objective(
    state: Tensor<4>,
    inputs: &RegionInputs,
    loss: &dyn FaceLoss,
    iteration: usize,
    overflow_weight: f32,
) -> Objective {
    let rgb = state.clone().narrow(0, 0, 3);
    let faces: Vec<FacePatch> = face_patches(&rgb, &inputs.region, &inputs.faces)
        .into_iter()
        .zip(&inputs.colour_faces)
        .map(|(generated, colour)| FacePatch {
            image: generated.image + colour.image.clone(),
            ..generated
        })
        .collect();
    let style = loss.loss(&faces, iteration);
    let overflow = (state.clone() - state.clamp(-1.0, 1.0)).abs().mean();
    let terms = vec![
        ("style", style.clone().inner().into_scalar::<f32>()),
        ("overflow", overflow.clone().inner().into_scalar::<f32>()),
    ];
    Objective {
        total: style + overflow.mul_scalar(overflow_weight),
        terms,
    }
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
pub fn check_data(data: &TrainData) -> Result<()> {
    if data.targets.iter().all(Option::is_none) {
        return Err(crate::XylemError::input(
            "training data",
            "no face photo to train on",
        ));
    }
    Ok(())
}
