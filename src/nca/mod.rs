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
//! The model and its engines live here; training lives in [`train`], which builds on them
//! and which nothing here imports (as burn keeps `burn-train` apart from its model crates).
//!
//! Files, one concept each:
//! - [`config`]: the training config (`configs/nca/*.toml`), the model's architecture and the
//!   option enums training reads.
//! - [`tensors`]: moving data between `Vec`/`Volume` and tensors.
//! - [`region`]: a box of voxels of the training grid (whole volume or a crop) and its
//!   position channels.
//! - [`cond_channel`], [`conditioning`], [`grain_noise`], [`ray_noise`]: the conditioning
//!   inputs (B, G, ring phase, grain and ray noise) as solid textures sampled into channels,
//!   and the white balance.
//! - [`fit_source`]: where B and G come from (the fit of `xylem fit`, or a stand-in).
//! - [`denormals`]: flush-to-zero on the compute threads (denormals made long backward
//!   passes 2x slower).
//! - [`perception`]: the fixed depthwise filters, as shifted slices or as `conv3d`.
//! - [`model`]: the burn `Module` (the MLP) and one update step; [`readout`]: colour from
//!   the state.
//! - [`unroll`]: many steps, slab by slab for large volumes, seeds.
//! - [`checkpoint`]: gradients through long unrolls by segment recomputation (both engines).
//! - [`faces`]: the six cube faces (or the face patches of a crop) of a state tensor.
//! - [`fused`]: the hand-written CPU kernels (forward, adjoint, training step).
//! - [`model_dir`]: the trained-model folder (`model.bpk`, `model.toml`, conditioning).
//! - [`synth`]: unrolling a trained model into a colour volume.
//! - [`train`]: targets, face losses, crop placement, pool, one iteration, the log,
//!   checkpoints on disk and a whole training session.

pub mod checkpoint;
pub mod colour_axes;
pub mod cond_channel;
pub mod conditioning;
pub mod config;
pub mod denormals;
pub mod faces;
pub mod fit_source;
pub mod fused;
pub mod grain_noise;
pub mod model;
pub mod model_dir;
pub mod perception;
pub mod ray_noise;
pub mod readout;
pub mod region;
pub mod synth;
pub mod tensors;
pub mod train;
pub mod unroll;

pub use cond_channel::CondChannel;
pub use conditioning::Conditioning;
pub use config::{FaceLossKind, ModelSpec, TrainConfig};
pub use faces::face_patches;
pub use model::Nca;
pub use region::Region;
pub use train::loss::{FaceLoss, MomentLoss};
pub use train::style_face_loss::{StyleFaceLoss, face_loss};
