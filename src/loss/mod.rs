//! The VGG-free style loss (differentiable, burn tensors).
//!
//! Pretrained VGG weights are not available here, so the features come from fixed filters
//! that need no training: a pyramid of each image ([`pyramid`]), a bank of random and
//! oriented filters at every level, optionally rectified ([`filters`], [`features`]). On those
//! features the loss compares Gram matrices ([`gram`]), means and covariances ([`moments`])
//! and, the term that carries the texture, sliced Wasserstein distances ([`sliced_wasserstein`])
//! with the target's; a colour term ([`colour`]) matches the pixel colour distribution. Every
//! term is relative to the target's own scale ([`distance`]) and weighted by the config
//! ([`config`], `configs/loss/default.toml`). [`style::StyleLoss`] is the entry point:
//!
//! ```no_run
//! # use xylem::loss::{LossConfig, StyleLoss, image_to_tensor};
//! # use burn::tensor::Device;
//! # fn demo(faces: &[xylem::Image2]) -> xylem::Result<()> {
//! let device = Device::flex().autodiff();
//! let loss = StyleLoss::new(&LossConfig::default_config(), &device);
//! let targets = loss.targets(faces)?; // once: statistics of the whole faces
//! let patch = image_to_tensor(&faces[0], &device).require_grad(); // [3, h, w]
//! let value = loss.loss(&[patch.clone()], &targets, &[0])?; // [1]
//! let grads = value.backward();
//! # Ok(()) }
//! ```
//!
//! Which statistics won, and the evidence, is in `docs/DESIGN.md` ("Style loss").

pub mod colour;
pub mod config;
pub mod distance;
pub mod features;
pub mod filters;
pub(crate) mod fine_energy;
pub mod gram;
pub mod guided;
pub(crate) mod guided_config;
pub(crate) mod image_tensor;
pub mod moments;
pub(crate) mod phase_bins;
pub mod pyramid;
pub(crate) mod ring_profile;
pub mod sliced_wasserstein;
pub mod style;
pub mod texture2d;

pub use config::{LossConfig, Nonlinearity};
pub use guided::GuidedTarget;
pub use guided::{GuidedLoss, GuidedPatch, GuidedTerms};
pub use guided_config::{GuidedConfig, ProfileAxes};
pub use image_tensor::{image_to_tensor, tensor_to_image};
pub use style::{LossTerms, StyleLoss, StyleTargets};
pub use texture2d::{Synthesis, Texture2dConfig, synthesize};
