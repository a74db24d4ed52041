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
//! - [`ring_warp`]: fitted ring positions mapped onto integer years.
//! - [`field_sample`]: what the field knows about one point.
//! - [`base_colour`]: a fitted colour bar over G; [`base_colour_texture`]: its solid texture.
//! - [`grain_shading`]: how the seen colour depends on the angle of surface and fibres;
//!   [`grain_shaded_texture`]: a solid texture seen with it.

pub mod arl;
pub mod base_colour;
pub mod base_colour_texture;
pub mod config;
pub mod distortion;
pub mod field_sample;
pub mod grain_shaded_texture;
pub mod grain_shading;
pub mod growth;
pub mod knot;
pub mod pith;
pub mod rate_grid;
pub mod ring_warp;
pub mod smin;

pub use arl::{RingImage, ring_intensity};
pub use base_colour::{BaseColour, WhiteBalance};
pub(crate) use base_colour_texture::base_colour_as_seen;
pub use base_colour_texture::{BaseColourTexture, ColourSpace};
pub use config::{FieldConfig, GrowthConfig, KnotConfig, PithConfig, RingsConfig};
pub use field_sample::{FieldSample, Strand};
pub use grain_shaded_texture::GrainShaded;
pub use grain_shading::GrainShading;
pub use growth::{GrowthField, knot_union};
pub use knot::Knot;
pub use pith::{Cylindrical, PithAxis};
pub use rate_grid::RateGrid;
pub use smin::power_smin;
