//! The fused CPU NCA: one step (perception, MLP, residual update) and its adjoint as
//! hand-written, cache-blocked, multi-threaded kernels over plain `f32` buffers
//! `[C, X, Y, Z]`, computing exactly what the burn model (`nca::model::Nca`) computes.
//! burn stays the reference and keeps the parameters, the optimiser and the loss.
//!
//! Files, one concept each:
//! - [`lanes`]: lane arrays (16 cells), the unit of SIMD work.
//! - [`simd`]: explicit vectors of a lane array per instruction set, behind CPU tokens.
//! - [`gemm`]: the two register-tiled matrix kernels (weights x block, block x block^T).
//! - [`isa`]: the instruction-set levels and run-time detection of what this CPU has.
//! - [`dispatch`]: one compiled copy of each kernel per instruction set.
//! - [`layout`]: buffer layouts, x-plane tasks, blocks, padded shapes.
//! - [`inputs`]: the fixed inputs of a region (conditioning, positions).
//! - [`weights`]: the MLP's weights as arrays, and packed for the kernels.
//! - [`perceive`]: the depthwise perception of a block into its input matrix.
//! - [`perceive_adjoint`]: the transpose of the perception (replicate padding's border sums).
//! - [`mlp`]: the MLP of a block, forward and backward.
//! - [`forward`]: a step over a volume, and an unroll over two buffers.
//! - [`adjoint`]: the adjoint of a step: weight gradients and the state gradient.
//! - [`train_step`]: gradients through an unroll with segment checkpointing.
//! - [`burn_bridge`]: training with burn's loss and optimiser around the fused unroll.

pub mod adjoint;
pub mod burn_bridge;
pub mod dispatch;
pub mod forward;
pub mod gemm;
pub mod inputs;
pub mod isa;
pub mod lanes;
pub mod layout;
pub mod mlp;
pub mod perceive;
pub mod perceive_adjoint;
pub mod simd;
pub mod train_step;
pub mod weights;

pub use adjoint::Gradients;
pub use forward::Stepper;
pub use inputs::FixedInputs;
pub use isa::Isa;
pub use weights::MlpWeights;
