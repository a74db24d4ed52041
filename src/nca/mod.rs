//! The 3D neural cellular automaton (Mokume 5.3.2; DESIGN section 6), written with burn.
//!
//! A state of `state_channels` (12) values per voxel is updated in place by the same small
//! network at every voxel and every step: fixed depthwise perception (identity, Sobel x/y/z,
//! 27-point Laplacian, replicate padding) of the state and of the conditioning channels (base
//! colour B and growth field G), plus 3 position channels, feed a 1x1x1 MLP
//! (73 -> 128 -> 12) whose output is added to the state. The first three state channels are an
//! RGB residual on top of B: the colour of a voxel is B + state[0..3].
//!
//! Tensors are `[C, X, Y, Z]` (burn's `[C, D, H, W]` with D = x), no batch dimension: training
//! uses batch 1 (DESIGN) and the unroll of a large volume is split into slabs along x instead.
//!
//! Files, one concept each:
//! - [`config`]: the training config (`configs/nca/*.toml`) and the model's architecture.
//! - [`tensors`]: moving data between `Vec`/`Volume` and tensors.
//! - [`region`]: a box of voxels of the training grid (whole volume or a corner crop) and its
//!   position channels.
//! - [`conditioning`]: B and G as solid textures, sampled into conditioning channels.
//! - [`fit_source`]: where B and G come from (a stand-in until the fit of issue 4 lands; the
//!   one place it plugs in).
//! - [`denormals`]: flush-to-zero on the compute threads (denormals made long backward
//!   passes 2x slower).
//! - [`perception`]: the fixed depthwise filters, as shifted slices or as `conv3d`.
//! - [`model`]: the burn `Module` (the MLP) and one update step.
//! - [`unroll`]: many steps, slab by slab for large volumes, seeds.
//! - [`checkpoint`]: gradients through long unrolls by segment recomputation.
//! - [`faces`]: the six cube faces (or the face patches of a crop) of a state tensor.
//! - [`loss`]: the seam to the face losses (`FaceLoss`) and the moment baseline.
//! - [`style_face_loss`]: the style loss of `crate::loss` as a `FaceLoss` (the default).
//! - [`targets`]: white-balanced face photos at the training resolution.
//! - [`pool`]: the pool of states training continues from.
//! - [`train`]: one training iteration (Adam, schedule, gradient normalisation, overflow
//!   loss) and the state it carries.
//! - [`loss_log`]: the per-iteration log (`loss.csv`).
//! - [`snapshot`]: training checkpoints on disk for `--resume`.
//! - [`session`]: a whole training run into a model folder, checkpoints, resume.
//! - [`model_dir`]: the trained-model folder (`model.bpk`, `model.toml`, conditioning).
//! - [`synth`]: unrolling a trained model into a colour volume.
//! - [`plot`]: the loss curve as an image.

pub mod checkpoint;
pub mod cond_channel;
pub mod conditioning;
pub mod config;
pub mod denormals;
pub mod face_guides;
pub mod faces;
pub mod fit_source;
pub mod fused;
pub mod grain_noise;
pub mod guided_face_loss;
pub mod loss;
pub mod loss_log;
pub mod model;
pub mod model_dir;
pub mod perception;
pub mod placement;
pub mod plot;
pub mod pool;
pub mod readout;
pub mod region;
pub mod session;
pub mod snapshot;
pub mod style_face_loss;
pub mod synth;
pub mod targets;
pub mod tensors;
pub mod train;
pub mod unroll;

pub use cond_channel::CondChannel;
pub use conditioning::Conditioning;
pub use config::{FaceLossKind, ModelSpec, TrainConfig};
pub use faces::{FacePatch, face_patches};
pub use loss::{FaceLoss, MomentLoss};
pub use model::Nca;
pub use region::Region;
pub use style_face_loss::{StyleFaceLoss, face_loss};
