//! Fitting a growth field and a base colour to the six faces of a sample (Mokume 5.2, DESIGN
//! section 5; issue 4).
//!
//! 1. [`contours`]: ring bands of the ring localisation images, lifted to 3D.
//! 2. Step 1, the pith of the undistorted field G = r: [`pith_search`] (a coarse grid of
//!    axes, near and far, straight and tilted) then [`pith_descent`] (Adam, analytic
//!    gradients), both on the [`iso_loss`].
//! 3. Step 2 ([`distortion`]): the rate grid R ([`grid_layout`] places its nodes over the
//!    cube's wedge of azimuths, [`stem_basis`] makes G linear in R), the grey map M
//!    ([`grey_map`]) and knots ([`knot_init`] from the markers, [`knot_fit`]); ring iso-values
//!    from M's peaks ([`ring_peaks`]), stored as the field's ring warp.
//! 4. Base colour ([`colour_fit`]) on the white-balanced photos ([`white_balance`]).
//! 5. [`run`] ties it together; [`write`](mod@write) and [`sheet`] produce the files; [`metrics`]
//!    measures accuracy; [`synthetic`] writes samples with known truth for tests.
//! 6. [`fibre_direction`]: which way the fibres run, measured on the photos;
//!    [`grain_shading_fit`]: how much darker (or lighter) the photos show end grain.
//! 7. [`procedural_fit`]: the procedural model's preset, ring phase and colours fitted to the
//!    photos on the fitted field (inverse procedural), searching [`procedural_search`]'s
//!    appearance parameters.
//!
//! [`config`] is the fit config; its `[localiser]` section ([`localiser_config`]) configures
//! `crate::rings`, which predicts ring images for faces without them before the fit runs.
//!
//! Optimisation is plain Adam ([`adam`]) on analytic gradients (central differences only for
//! the knot parameters, see [`knot_fit`]); `tests/fit.rs` checks them against finite
//! differences of the losses.

pub mod adam;
pub mod colour_fit;
pub mod config;
pub mod contours;
pub mod distortion;
pub mod fibre_direction;
pub mod grain_shading_fit;
pub mod grey_map;
pub mod grid_layout;
pub mod iso_loss;
pub mod knot_fit;
pub mod knot_init;
pub mod localiser_config;
pub mod metrics;
pub mod pith_descent;
pub mod pith_search;
pub mod procedural_fit;
pub mod procedural_search;
pub mod ring_peaks;
pub mod run;
pub mod sheet;
pub mod stem_basis;
pub mod synthetic;
pub mod white_balance;
pub mod write;

pub use config::{FitConfig, ProceduralFitConfig};
pub use run::{FitResult, fit_sample};
pub use synthetic::write_synthetic_sample;
pub use write::Display;
pub(crate) use write::write_fit;
