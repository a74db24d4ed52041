//! Comparison metrics (plain Rust on [`Image2`], no autodiff): every comparison in the project
//! (faces, held-out faces, cuts; NCA, procedural and baselines alike) reports the same numbers.
//!
//! - [`ring`]: ring alignment `ring_ncc` (band-passed luminance, best over small shifts);
//! - [`orientation`]: grain-direction agreement `orient` (structure tensor);
//! - [`patch_swd`]: patch texture distance `swd`, and `swd_L` / `swd_chroma` on lightness and
//!   chroma alone (sliced Wasserstein of Lab patches at two scales);
//! - [`anisotropy`]: pore-scale anisotropy `aniso` of the candidate (and `aniso_ref` of the
//!   reference): dashes vs dots;
//! - [`speckle`]: pixel-scale speckle `speckle` of the candidate (and `speckle_ref`):
//!   checkerboard stipple vs continuous detail;
//! - [`lab`]: Lab colour mean and spread differences `dE_mean`, `dE_std`;
//! - [`phase_density`]: pore density by ring phase (where in the ring the pores are) and the
//!   correlation of two such curves;
//! - [`report`]: all of them plus the style loss (`style`) in one [`Metrics`] struct, JSON and
//!   CSV;
//! - [`sheet`]: the side-by-side picture with the difference.

pub mod anisotropy;
pub mod lab;
pub mod orientation;
pub mod patch_swd;
pub mod phase_density;
pub mod report;
pub mod ring;
pub mod sheet;
pub mod speckle;
pub mod vessels;

pub use report::{Comparer, METRIC_NAMES, Metrics, compare};
pub use sheet::difference_sheet;
