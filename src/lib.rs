//! xylem: solid (volumetric) wood textures from the six photographed faces of a wooden cube.
//!
//! # Quick start
//!
//! Every source of wood (the procedural model, a fitted growth field, a synthesised NCA
//! volume) is a [`SolidTexture`]: a colour at any point of the cube [-0.5, 0.5]^3. Slice it
//! with any [`Plane`], evaluate it on a grid into a [`Volume`], export that for other tools:
//!
//! ```
//! use xylem::export::{Format, Values, export};
//! use xylem::presets::load_species_preset;
//! use xylem::procedural::ProceduralWood;
//! use xylem::slice::slice_plane;
//! use xylem::{Plane, Volume};
//!
//! let oak = ProceduralWood::new(&load_species_preset("oak")?);
//! // The slanted validation cut cut1 (docs/DESIGN.md), 64 x 64 pixels of display sRGB.
//! let cut = slice_plane(&oak, &Plane::cut1(), 64, 64);
//! let dir = std::env::temp_dir().join(format!("xylem-quickstart-{}", std::process::id()));
//! xylem::io::save_png(&cut, &dir.join("oak-cut1.png"))?;
//! // A 32^3 colour volume, [X, Y, Z, RGB], as OpenVDB for Blender or Houdini.
//! let volume = Volume::from_texture(&oak, 32);
//! export(&volume, Values::Colour, Format::Vdb, &dir.join("oak.vdb"), "oak")?;
//! # std::fs::remove_dir_all(&dir).ok();
//! # Ok::<(), xylem::XylemError>(())
//! ```
//!
//! A trained NCA (a folder written by `xylem train` or `xylem run`, e.g. `out/demo/train`)
//! is unrolled into a volume, which is a solid texture like any other:
//!
//! ```no_run
//! use xylem::device::DeviceKind;
//! use xylem::nca::model_dir::TrainedModel;
//! use xylem::nca::synth::{SynthOptions, synthesise};
//! use xylem::slice::slice_plane;
//! use xylem::Plane;
//!
//! let device = DeviceKind::Flex.device();
//! let model = TrainedModel::load("out/demo/train".as_ref(), &device)?;
//! let options = SynthOptions {
//!     size: model.meta.grid, // the grid it was trained at: pores keep their scale
//!     steps: 90,             // the unroll length of the Mokume paper
//!     seed: model.meta.seed,
//!     slab_voxels: 1 << 18,
//!     engine: Default::default(), // the fused CPU kernels
//! };
//! let volume = synthesise(&model, &options, &device, |_step| {})?;
//! let cut = slice_plane(&volume, &Plane::cut2(), 256, 256);
//! xylem::io::save_png(&cut, "cut2.png".as_ref())?;
//! # Ok::<(), xylem::XylemError>(())
//! ```
//!
//! The whole pipeline, as `xylem demo` runs it (a synthetic sample, fit, NCA training,
//! synthesis, sheet, renders, metrics, report, in one resumable run folder):
//!
//! ```no_run
//! use xylem::pipeline::{DemoOptions, Quiet, RunLayout, demo};
//!
//! let options = DemoOptions {
//!     species: "chestnut".into(),
//!     size: 256,
//!     nca_config: None, // the built-in quick config
//!     synth_steps: 90,
//!     device: Default::default(), // burn's flex CPU backend
//!     engine: Default::default(), // the fused CPU kernels
//! };
//! let outcome = demo(&RunLayout::new("out/demo"), &options, &Quiet)?;
//! print!("{}", outcome.metrics.to_csv());
//! # Ok::<(), xylem::XylemError>(())
//! ```
//!
//! The modules follow the pipeline (see `docs/DESIGN.md` and the README's picture):
//!
//! - [`frame`]: the fixed cube conventions: faces A-F, pixel and voxel centres, the unfolded
//!   cross, the validation cuts and arbitrary planes.
//! - [`texture`]: the one solid-texture interface every source of wood implements.
//! - [`volume`]: dense voxel volumes with trilinear lookup (a solid texture too).
//! - [`field`]: the procedural growth field G(p) (pith axis, rate grid, knots) and the ring
//!   localisation image I(G), fitted ring positions and the base colour bar over G.
//! - [`fit`]: fitting the growth field and base colour to a sample's six faces (`xylem fit`).
//! - [`slice`]: sampling any solid texture on faces, cuts and planes; the unfolded cross.
//! - [`image2`]: the float image type slices are returned in (resampled by the private
//!   `resample` module: one box-filter/bilinear implementation for every caller).
//! - [`outputs`]: the standard set of faces, cuts and unfolded cross written for a texture.
//! - [`render`]: lit renders of any solid texture on the cube or on a carved mesh.
//! - [`report`]: comparison sheets, captioned render rows and the HTML report of a run.
//! - [`export`]: volumes for other tools (OpenVDB, a Mitsuba scene or `.vol`, NRRD, `.npy`).
//! - [`io`]: PNG, NPY and TOML files, written atomically; output folders.
//! - [`config`]: shared config loading and range checks.
//! - [`sample`]: sample folders in the Mokume layout (photos, ring images, knot markers).
//! - [`rng`]: seeded, hash-based randomness (same seed, same output).
//! - [`series`]: correlation and slope of two series (edge profiles, ring images, curves).
//! - [`device`]: choosing burn's CPU device (flex or ndarray) at run time.
//! - [`loss`]: the VGG-free style loss (fixed-filter features, sliced Wasserstein, Gram,
//!   moments, colour) that the NCA trains with.
//! - [`metrics`]: comparison metrics (ring alignment, grain direction, patch texture distance
//!   on Lab, lightness and chroma, colour differences) and `xylem compare`'s JSON.
//! - [`procedural`]: the procedural wood model (rings, pores, rays, fibres, knots, figure,
//!   burl) and synthetic sample cubes made from species presets.
//! - [`nca`]: the 3D neural cellular automaton: model, training on the faces, synthesis.
//! - [`run_folder`]: the names inside a run folder, shared by the pipeline and the report.
//! - [`pipeline`]: the stages of `xylem run` (fit, train, synth, sheet, renders, metrics,
//!   report) and the demo as library functions on a run folder, resumable.

#![warn(unreachable_pub)]

pub mod config;
pub mod device;
pub mod error;
pub mod export;
pub mod field;
pub mod fit;
pub mod frame;
pub mod image2;
pub(crate) mod image_filter;
pub mod io;
pub mod loss;
mod mask_patches;
pub mod memory;
pub mod metrics;
pub mod nca;
pub mod outputs;
pub mod pipeline;
pub mod presets;
pub mod procedural;
pub mod render;
pub mod report;
mod resample;
pub mod rings;
pub mod rng;
pub mod run_folder;
pub mod sample;
pub mod series;
pub mod slice;
pub(crate) mod symmetric_eigen;
pub mod texture;
pub mod volume;

pub use error::{Result, XylemError};
pub use frame::{Face, Plane};
pub use image2::Image2;
pub use texture::SolidTexture;
pub use volume::Volume;
