//! The procedural wood model (Liu et al. 2016, simplified as in Mokume section 5.3.1 and
//! appendix A.2.3, with Moyer 2003's burl): a point-wise colour model on top of the growth
//! field, and synthetic sample cubes made from it.
//!
//! - [`config`]: the species config (one TOML per species under `configs/species/`).
//! - [`colour_map`]: 64-entry colour maps given by a few control points.
//! - [`rings`]: the earlywood/latewood profile and colours along G.
//! - [`years`]: year-to-year ring width and colour variation (the ring time T).
//! - [`pigment`]: Beer's-law pigment exponent and its small 3D noise.
//! - [`tree`]: tree-space coordinates around the pith.
//! - [`cells`]: cylindrical cells for stratified, hashed placement.
//! - [`fibres`], [`pores`], [`rays`]: the fine anatomy.
//! - [`knot_colour`]: colour, darkening and dead-knot outline inside knots.
//! - [`figure`]: radial/tangential displacement of the lookup point.
//! - [`burl`]: buds pushing the lookup point, several blended levels of curl.
//! - [`noise`]: hashed lattice noise.
//! - [`model`]: the model itself ([`ProceduralWood`], a `SolidTexture`).
//! - [`direction`]: the fibre direction implied by the distortions (extra channels).
//! - [`photograph`]: how a synthetic sample is photographed (the end-grain factor).
//! - [`synthetic`]: sample folders in the Mokume layout with their hidden truth.
//! - [`recolour`]: a config with every colour scaled (the inverse procedural fit's palette).
//!
//! Every random choice is a hash of the species seed (and of the field's own seed for its
//! distortion): the same point always gets the same colour, on any thread.

pub mod burl;
pub mod cells;
mod checks;
pub mod colour_map;
pub mod config;
pub mod direction;
pub mod fibres;
pub mod figure;
pub mod knot_colour;
pub mod model;
pub mod noise;
pub mod photograph;
pub mod pigment;
pub mod pores;
pub mod rays;
pub mod recolour;
pub mod rings;
pub mod synthetic;
pub mod tree;
pub mod years;

pub use config::SpeciesConfig;
pub use direction::{FibreDirection, WithFibreDirection};
pub use model::{ProceduralWood, RingTime, WoodSample};
pub use photograph::Photograph;
pub use synthetic::{write_photographed_sample, write_sample};
