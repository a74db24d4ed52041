//! The NCA training config (`configs/nca/default.toml`, `configs/nca/quick.toml`).
//!
//! Plain serde structs (unknown keys are errors), every value range-checked by
//! [`TrainConfig::validate`] with messages naming the key. The model's architecture
//! ([`ModelSpec`]) is its own table because the trained-model folder stores it again: a
//! model can only be loaded with the architecture it was trained with.

use serde::{Deserialize, Serialize};

use super::cond_channel::CondChannel;
use super::grain_noise::GrainNoiseSpec;
use super::perception::{FILTERS, POSITION_CHANNELS, PerceptionImpl};
use super::ray_noise::RayNoiseSpec;
use super::readout::Readout;
use crate::config::{Checker, ConfigFile};
use crate::error::Result;
use crate::loss::{GuidedConfig, LossConfig};

/// Largest training volume side (`[volume] size`), so also the largest crop side.
const MAX_VOLUME_SIDE: usize = 1024;
/// Everything `xylem train` needs besides the sample and the fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainConfig {
    /// Seed of every random choice (initial weights, seeds, steps, crops, pool).
    pub seed: u64,
    #[serde(default)]
    pub model: ModelSpec,
    pub volume: VolumeConfig,
    pub schedule: ScheduleConfig,
    pub pool: PoolConfig,
    #[serde(default)]
    pub loss: LossWeights,
    #[serde(default)]
    pub memory: MemoryConfig,
    #[serde(default)]
    pub checkpoint: CheckpointConfig,
    #[serde(default)]
    pub compute: ComputeConfig,
}

/// The network: state size, hidden width, conditioning, perception implementation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelSpec {
    /// State channels per voxel; the first three are the RGB residual on B.
    pub state_channels: usize,
    /// Width of the hidden layer of the update MLP.
    pub hidden: usize,
    /// Conditioning channels, in order (empty: position only, the ablation).
    pub conditioning: Vec<CondChannel>,
    /// How the depthwise filters are computed (same result; speed differs by backend).
    pub perception: PerceptionImpl,
    /// Amplitude of the uniform seed state, [-a, a].
    pub seed_amplitude: f32,
    /// Cell sizes of the `grain_noise` conditioning channel.
    pub grain_noise: GrainNoiseSpec,
    /// Cell sizes of the `ray_noise` conditioning channel; left out of the stored spec when
    /// at their defaults, so models written before it existed are written alike.
    #[serde(skip_serializing_if = "is_default_rays")]
    pub ray_noise: RayNoiseSpec,
    /// How the colour is read from the state: `residual` (B + state RGB), or `bounded` /
    /// `saturating` (the same, softly bounded to [0, 1] in photo colour; `readout.rs`).
    pub readout: Readout,
    /// How many principal axes of the photos' fine-texture colour the state's RGB residual
    /// may move along (`colour_axes.rs`): 3 = any colour (the authors'), 2 = not the
    /// magenta-green axis the photos' texture barely has, 1 = light-dark wood colour only.
    #[serde(skip_serializing_if = "is_every_colour")]
    pub colour_axes: usize,
    /// Whether the rule sees its place in the grid (3 position channels in (-1, 1)). With
    /// `false` those channels are zero: the rule can only tell places apart by their
    /// conditioning, so a crop inside the cube is painted by the rule that paints the faces
    /// (BENCHMARKS "Without position channels"). Left out of the stored spec when true, so
    /// models written before it existed are written alike.
    #[serde(skip_serializing_if = "is_true")]
    pub positions: bool,
}

fn is_default_rays(spec: &RayNoiseSpec) -> bool {
    *spec == RayNoiseSpec::default()
}

/// Every colour axis (the default): left out of the model's stored spec so models trained
/// before the option existed and without it are written alike.
fn is_every_colour(axes: &usize) -> bool {
    *axes == 3
}

fn is_true(flag: &bool) -> bool {
    *flag
}

/// The training grid and the part of it each iteration unrolls.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeConfig {
    /// Side of the training volume in voxels; the face photos are resampled to size x size,
    /// so one voxel is 4 cm / size.
    pub size: usize,
    /// Side of the crops trained on. `crop = size` trains the whole volume against all six
    /// faces.
    pub crop: usize,
    /// Where the crops lie: `faces` (anywhere against a trained face, the default) or
    /// `corners` (the 8 corner crops of the first trial).
    #[serde(default)]
    pub placement: Placement,
    /// Share of the fresh crops drawn anywhere in the grid instead of by `placement`. Such
    /// a crop usually touches no trained face: only the overflow and low-band terms judge
    /// it, which teaches the rule to stay bounded where no photo is (the inside of the cube,
    /// a knot under a held-out face). 0 (the default) draws every crop by `placement`.
    #[serde(default)]
    pub interior_fraction: f32,
}

impl VolumeConfig {
    /// Side of the regions trained on: the crop, or the whole grid when the crop is larger.
    pub(crate) fn crop_side(&self) -> usize {
        self.crop.min(self.size)
    }
}

/// Iterations, unroll lengths and the learning-rate schedule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduleConfig {
    pub iterations: usize,
    /// Unroll length per iteration, drawn uniformly from [min, max].
    pub steps: [usize; 2],
    /// Steps a fresh seed is unrolled without gradients before its first training unroll,
    /// drawn uniformly from [min, max] ([0, 0]: none). Synthesis runs 90 steps, so the
    /// first few steps from the seed are never seen; with a burn-in the rule may take as
    /// long as it needs to grow structure, and the loss judges grown states only.
    #[serde(default)]
    pub burn_in: [usize; 2],
    /// Adam learning rate at the start.
    #[serde(default = "default_lr")]
    pub learning_rate: f64,
    /// Iterations at which the learning rate is multiplied by `decay_factor`.
    #[serde(default)]
    pub decay_at: Vec<usize>,
    #[serde(default = "default_decay_factor")]
    pub decay_factor: f64,
}

/// The pool of states (Mordvintsev et al.): iterations continue from earlier results so the
/// NCA learns to keep a stable texture over long unrolls.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoolConfig {
    /// Number of stored states; 0 starts every iteration from a fresh seed.
    pub size: usize,
    /// Every this many iterations the drawn state is replaced by a fresh seed.
    #[serde(default = "default_fresh_every")]
    pub fresh_every: usize,
    /// A state whose overflow term (mean excess of |state| over 1) passes this after its
    /// unroll has run away: it is not stored back, and its slot restarts from a fresh seed.
    /// Healthy states stay under about 0.35; kept, a runaway state is drawn again and
    /// again and grows (H11 without A, lrq: 0 -> 1.8e5 in one 16-step unroll, then up to
    /// 1.4e9 over the next 380 iterations; BENCHMARKS "H11 A held out with lrq, and
    /// runaway pool states").
    #[serde(default = "default_reseed_overflow")]
    pub reseed_overflow: f32,
}

impl PoolConfig {
    /// Whether a finite unroll whose final state has this overflow term ran away
    /// (`reseed_overflow`).
    pub fn ran_away(&self, overflow: f32) -> bool {
        overflow > self.reseed_overflow
    }
}

/// The face loss and the weights of the loss terms (the face term has weight 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LossWeights {
    /// Weight of mean |S - clamp(S, -1, 1)|, which keeps the state bounded.
    pub overflow: f32,
    /// Weight of the low-band term: the root mean square of the colour residual's means over
    /// blocks of `low_band_block`^3 voxels. B already carries the rings and the colour at
    /// those scales; the term asks the NCA to add texture that averages out within a block
    /// instead of repainting them (0 = off, the first versions).
    pub low_band: f32,
    /// Side in voxels of the low-band term's blocks; must divide the crop side.
    pub low_band_block: usize,
    /// What the block means are held to: `zero`, `crop_mean` (only their spread around
    /// the crop's own mean colour residual costs) or `ring_phase` (the residual less its
    /// mean per ring-phase bin over the crop); DESIGN "Low band reference and shown
    /// targets".
    pub low_band_reference: LowBandReference,
    /// Which loss compares the generated faces with the photos.
    pub face: FaceLossKind,
    /// The style loss's config (`[loss.style]`, same keys as `configs/loss/default.toml`,
    /// which is the default). The guided loss takes its features from here too.
    pub style: LossConfig,
    /// The guided loss's window and guide settings (`[loss.guided]`).
    pub guided: GuidedConfig,
    /// Planes inside each crop, parallel to the faces it touches, that are also compared
    /// with those faces' photos (guided loss: with their own ring phase). A plane parallel
    /// to a face cuts the fibres as the face does, so it should look like it; without them
    /// the inside of the cube is never seen by the loss. Their depths are drawn per
    /// iteration.
    pub inner_planes: usize,
    /// Whether a crop that touches no trained face (`[volume] interior_fraction`) compares
    /// planes parallel to the nearest trained face on each axis with that face's photo
    /// (guided loss, each plane with its own ring phase; depths as `inner_planes`, one at
    /// least). Without it such a crop is judged by the overflow and low-band terms only,
    /// and the rule may learn to paint nothing inside the cube.
    pub interior_style: bool,
    /// What colour the targets have: `base` (each face photo scaled so its mean is the base
    /// colour's mean on that face: the NCA adds texture, not a colour shift), `shown` (the
    /// same with the base colour's mean shift: the mean the photos have where the ground
    /// colour B has its median, so the NCA's dark pores may darken B to it) or `face` (each
    /// photo divided by twice its own mean, DESIGN section 6 as first written).
    pub target_colour: TargetColour,
}

/// What the low-band term holds the residual's block means to (see
/// [`LossWeights::low_band_reference`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LowBandReference {
    /// Every block mean at 0: the NCA adds no colour to B at the block's scale (variant lr).
    #[default]
    Zero,
    /// Every block mean at the mean over the crop's blocks (per channel): the residual may
    /// darken (or lighten) the whole crop, as dark pores on the ground colour must, but
    /// may not paint bands or blotches at the block's scale.
    CropMean,
    /// Every voxel's residual first less the crop's mean residual in its ring-phase bin
    /// (`nca::train::low_band`): the residual may also differ between earlywood and
    /// latewood, as pores packed in the earlywood make it, but not otherwise at the block's
    /// scale.
    RingPhase,
}

/// The colour of the training targets (see [`LossWeights::target_colour`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TargetColour {
    #[default]
    Base,
    Shown,
    Face,
}

/// Memory controls of the unroll.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MemoryConfig {
    /// Steps per recomputed segment in backpropagation (memory grows with this, time with
    /// its inverse); 0 keeps the whole unroll on the tape.
    pub segment_steps: usize,
    /// Largest number of voxels updated at once in an unroll without gradients (the hidden
    /// layer holds `hidden` floats per voxel).
    pub slab_voxels: usize,
}

/// When training writes checkpoints for `--resume`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CheckpointConfig {
    /// Wall-clock minutes between checkpoints (the last iteration is always saved).
    pub minutes: f32,
    /// Also checkpoint every this many iterations (0: only by time).
    pub every: usize,
}

/// Which implementation runs the unroll and its backward pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Engine {
    /// The fused CPU kernels (`nca::fused`): same numbers as burn to float rounding,
    /// several times faster (BENCHMARKS.md).
    #[default]
    Fused,
    /// burn's tensors and autodiff (`nca::checkpoint`): the reference; also the way to run
    /// on `--device ndarray`.
    Burn,
}

impl std::str::FromStr for Engine {
    type Err = crate::error::XylemError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "fused" => Ok(Engine::Fused),
            "burn" => Ok(Engine::Burn),
            other => Err(crate::error::XylemError::input(
                format!("engine {other:?}"),
                "expected `fused` (default) or `burn`",
            )),
        }
    }
}

/// How training computes; none of it changes the model, only speed (and float rounding).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComputeConfig {
    #[serde(default)]
    pub engine: Engine,
}

fn default_lr() -> f64 {
    1e-3
}
fn default_decay_factor() -> f64 {
    0.3
}
fn default_fresh_every() -> usize {
    32
}
fn default_reseed_overflow() -> f32 {
    1.0
}

impl Default for LossWeights {
    fn default() -> Self {
        Self {
            overflow: 1.0,
            low_band: 0.0,
            low_band_block: 8,
            low_band_reference: LowBandReference::default(),
            face: FaceLossKind::default(),
            style: LossConfig::default_config(),
            guided: GuidedConfig::default(),
            inner_planes: 0,
            interior_style: false,
            target_colour: TargetColour::default(),
        }
    }
}

impl Default for MemoryConfig {
    fn default() -> Self {
        Self {
            segment_steps: 8,
            slab_voxels: 1 << 18,
        }
    }
}

impl Default for CheckpointConfig {
    fn default() -> Self {
        Self {
            minutes: 5.0,
            every: 0,
        }
    }
}

impl Default for ModelSpec {
    fn default() -> Self {
        Self {
            state_channels: 12,
            hidden: 128,
            conditioning: vec![CondChannel::GreyB, CondChannel::G],
            perception: PerceptionImpl::default(),
            seed_amplitude: 0.05,
            grain_noise: GrainNoiseSpec::default(),
            ray_noise: RayNoiseSpec::default(),
            readout: Readout::default(),
            colour_axes: 3,
            positions: true,
        }
    }
}

impl ModelSpec {
    /// Conditioning channels fed through perception.
    pub fn cond_channels(&self) -> usize {
        self.conditioning.iter().map(|c| c.width()).sum()
    }

    /// Inputs of the MLP: 5 filters x (state + conditioning) + 3 positions (73 by default).
    pub fn inputs(&self) -> usize {
        FILTERS * (self.state_channels + self.cond_channels()) + POSITION_CHANNELS
    }

    /// Number of trainable parameters (first layer with bias, second without).
    pub fn parameters(&self) -> usize {
        self.hidden * self.inputs() + self.hidden + self.state_channels * self.hidden
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.count(
            "state_channels",
            self.state_channels,
            3,
            64,
            "state channels (the first 3 are RGB)",
        )?;
        check.count("hidden", self.hidden, 1, 1024, "hidden width")?;
        check.count(
            "colour_axes",
            self.colour_axes,
            1,
            3,
            "principal colour axes the state may paint along",
        )?;
        for (i, c) in self.conditioning.iter().enumerate() {
            if self.conditioning[..i].contains(c) {
                return Err(check.error(
                    "conditioning",
                    format!("lists {c:?} twice; expected each channel at most once"),
                ));
            }
        }
        check.range(
            "seed_amplitude",
            self.seed_amplitude,
            0.0,
            1.0,
            "seed amplitude",
        )?;
        self.grain_noise.validate(&check.nested("grain_noise"))?;
        self.ray_noise.validate(&check.nested("ray_noise"))
    }
}

impl TrainConfig {
    /// Learning rate at `iteration` (0-based): multiplied by `decay_factor` at each
    /// `decay_at` iteration reached.
    pub fn learning_rate(&self, iteration: usize) -> f64 {
        let decays = self
            .schedule
            .decay_at
            .iter()
            .filter(|&&at| iteration >= at)
            .count();
        self.schedule.learning_rate * self.schedule.decay_factor.powi(decays as i32)
    }

    /// Refuses `key` (under `at`) when it is `used` without the guided face loss, whose
    /// part it is.
    fn needs_guided_loss(
        &self,
        at: &Checker,
        key: &str,
        used: bool,
        message: String,
    ) -> Result<()> {
        if used && self.loss.face != FaceLossKind::Guided {
            return Err(at.error(key, message));
        }
        Ok(())
    }
}

impl ConfigFile for TrainConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        self.model.validate(&check.nested("model"))?;
        let v = check.nested("volume");
        v.count(
            "size",
            self.volume.size,
            4,
            MAX_VOLUME_SIDE,
            "training volume side",
        )?;
        v.count(
            "crop",
            self.volume.crop,
            4,
            self.volume.size,
            "crop side (at most volume.size)",
        )?;
        v.range(
            "interior_fraction",
            self.volume.interior_fraction,
            0.0,
            1.0,
            "share of the crops drawn anywhere in the grid",
        )?;
        let s = check.nested("schedule");
        s.count(
            "iterations",
            self.schedule.iterations,
            1,
            1_000_000,
            "iterations",
        )?;
        let [lo, hi] = self.schedule.steps;
        s.count("steps", lo, 1, 10_000, "the shortest unroll")?;
        if hi < lo || hi > 10_000 {
            return Err(s.error(
                "steps",
                format!("= [{lo}, {hi}]: expected [min, max] with min <= max <= 10000"),
            ));
        }
        let [b_lo, b_hi] = self.schedule.burn_in;
        if b_hi < b_lo || b_hi > 10_000 {
            return Err(s.error(
                "burn_in",
                format!("= [{b_lo}, {b_hi}]: expected [min, max] with min <= max <= 10000"),
            ));
        }
        s.positive(
            "learning_rate",
            self.schedule.learning_rate as f32,
            1.0,
            "Adam learning rate",
        )?;
        s.positive(
            "decay_factor",
            self.schedule.decay_factor as f32,
            1.0,
            "learning-rate factor",
        )?;
        let p = check.nested("pool");
        p.count("size", self.pool.size, 0, 4096, "pool size (0 = no pool)")?;
        p.count(
            "fresh_every",
            self.pool.fresh_every,
            1,
            1_000_000,
            "iterations between fresh seeds",
        )?;
        p.positive(
            "reseed_overflow",
            self.pool.reseed_overflow,
            1e30,
            "the overflow above which a pool state is reseeded",
        )?;
        let l = check.nested("loss");
        l.range(
            "overflow",
            self.loss.overflow,
            0.0,
            1000.0,
            "overflow-loss weight",
        )?;
        l.range(
            "low_band",
            self.loss.low_band,
            0.0,
            1000.0,
            "low-band loss weight",
        )?;
        let side = self.volume.crop_side();
        // The block matters only when the term is on (the default block need not fit the
        // tests' tiny crops); unused, it need only fit the largest crop there can be.
        let block_used = self.loss.low_band > 0.0;
        l.count(
            "low_band_block",
            self.loss.low_band_block,
            1,
            if block_used { side } else { MAX_VOLUME_SIDE },
            "block side in voxels, at most the crop side",
        )?;
        if block_used && !side.is_multiple_of(self.loss.low_band_block) {
            return Err(l.error(
                "low_band_block",
                format!(
                    "= {}: must divide the crop side {side}",
                    self.loss.low_band_block
                ),
            ));
        }
        self.loss.style.validate(&l.nested("style"))?;
        self.loss.guided.validate(&l.nested("guided"))?;
        l.count(
            "inner_planes",
            self.loss.inner_planes,
            0,
            64,
            "planes inside a crop compared with the photos",
        )?;
        // Parts of the guided loss (src/loss/guided.rs): refused with any other face loss.
        self.needs_guided_loss(
            &l,
            "inner_planes",
            self.loss.inner_planes > 0,
            format!(
                "= {}: planes inside the crop need the guided loss (face = \"guided\")",
                self.loss.inner_planes
            ),
        )?;
        self.needs_guided_loss(
            &l,
            "interior_style",
            self.loss.interior_style,
            "= true: planes inside the cube need the guided loss (face = \"guided\")".into(),
        )?;
        self.needs_guided_loss(
            &l.nested("guided"),
            "fine_weight",
            self.loss.guided.fine_weight > 0.0,
            format!(
                "= {}: the pixel-scale energy term is part of the guided loss \
                 (face = \"guided\"); use 0 with another face loss",
                self.loss.guided.fine_weight
            ),
        )?;
        self.needs_guided_loss(
            &l.nested("guided"),
            "profile_weight",
            self.loss.guided.profile_weight > 0.0,
            format!(
                "= {}: the ring-profile term is part of the guided loss \
                 (face = \"guided\"); use 0 with another face loss",
                self.loss.guided.profile_weight
            ),
        )?;
        let m = check.nested("memory");
        m.count(
            "segment_steps",
            self.memory.segment_steps,
            0,
            10_000,
            "steps per recomputed segment (0 = none)",
        )?;
        m.count(
            "slab_voxels",
            self.memory.slab_voxels,
            1024,
            1 << 30,
            "voxels per slab",
        )?;
        let c = check.nested("checkpoint");
        c.positive(
            "minutes",
            self.checkpoint.minutes,
            1e4,
            "minutes between checkpoints",
        )?;
        c.count(
            "every",
            self.checkpoint.every,
            0,
            1_000_000,
            "iterations between checkpoints",
        )
    }
}

/// Which loss compares generated faces with the photos.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FaceLossKind {
    /// The VGG-free style loss (`[loss.style]`, default `configs/loss/default.toml`).
    #[default]
    Style,
    /// Colour and gradient moments: cheap, blind to pores and rings (tests, ablation).
    Moments,
    /// The guided local loss (`[loss.guided]`): each patch against the photo around it,
    /// with the ring phase as a guide.
    Guided,
}

/// Where the training crops of an iteration lie (`[volume] placement`; drawn by
/// `nca::train::placement`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// The 8 corner crops (each touches three faces).
    Corners,
    /// A crop against a trained face, anywhere along it.
    #[default]
    Faces,
}
