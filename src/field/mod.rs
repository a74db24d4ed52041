//! The procedural growth field (DESIGN section 4; Mokume 5.2.1; Larsson et al. 2022).
//!
//! - [`config`]: the TOML config and its checks.
//! - [`pith`]: the pith axis and cylindrical coordinates.
//! - [`rate_grid`]: the radial growth-rate grid R and its integral.
//! - [`distortion`]: seeded random rate grids.
//! - [`smin`]: the power smooth minimum and its adaptive exponent.
//! - [`knot`]: one knot strand, alive or dead.
//! - [`growth`]: the combined field G and the dominant strand.
//! - [`arl`]: the ring localisation image I(G).

pub mod arl;
pub mod config;
pub mod distortion;
pub mod growth;
pub mod knot;
pub mod pith;
pub mod rate_grid;
pub mod smin;

pub use arl::{RingImage, ring_intensity};
pub use config::{DistortionConfig, FieldConfig, GrowthConfig, KnotConfig, PithConfig};
pub use growth::{FieldSample, GrowthField, Strand};
pub use knot::{Knot, KnotSample};
pub use pith::{Cylindrical, PithAxis};
pub use rate_grid::RateGrid;
pub use smin::power_smin;
