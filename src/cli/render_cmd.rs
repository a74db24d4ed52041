//! `xylem render`: a lit image of a solid texture on the cube or on a carved mesh.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use xylem::io::{check_new_file, save_png};
use xylem::render::{RenderConfig, Shape, TriMesh, render, turntable};

use super::output_args::parse_size;
use super::texture_source::{ShadingSource, TextureSource};
use xylem::config::ConfigFile;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum View {
    /// One view from the configured camera.
    Cube,
    /// Several views orbiting around the vertical (pith) axis, side by side.
    Turntable,
}

/// Render a solid texture: the cube seen from a corner, or an object carved from the wood.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem render --volume out/synth/volume.npy --size 800x800 --out cube.png
  xylem render --volume out/synth/volume.npy --mesh assets/bowl.obj --out bowl.png
  xylem render --field configs/fields/knots.toml --view turntable --size 300x300 --out strip.png

The mesh is fitted into the cube and rotated inside the wood by [carve] in the render config
(configs/render/default.toml is built in; pass --config to change camera, light, finish).")]
pub struct RenderArgs {
    #[command(flatten)]
    pub source: TextureSource,
    #[command(flatten)]
    pub shading: ShadingSource,
    /// Carve this OBJ mesh from the wood instead of showing the cube.
    #[arg(long, value_name = "M.obj")]
    pub mesh: Option<PathBuf>,
    /// One lit view of the cube (or mesh), or a turntable of several views side by side.
    #[arg(long, value_enum, default_value = "cube")]
    pub view: View,
    /// Image size WIDTHxHEIGHT, or N for N x N (per view for the turntable).
    #[arg(long, default_value = "800x800")]
    pub size: String,
    /// Render config (TOML); default: the built-in configs/render/default.toml.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Output PNG.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: RenderArgs) -> Result<()> {
    check_new_file(&args.out, args.force)?;
    let (width, height) = parse_size("--size", &args.size)?;
    let cfg = match &args.config {
        Some(path) => RenderConfig::load(path)?,
        None => RenderConfig::default_config(),
    };
    let (texture, what) = args.source.load()?;
    let texture = args.shading.apply(texture)?;
    let shape = match &args.mesh {
        Some(path) => Shape::carved(&TriMesh::load_obj(path)?, &cfg.carve),
        None => Shape::Cube,
    };
    let image = match args.view {
        View::Cube => render(
            texture.as_ref(),
            &shape,
            shape.camera(&cfg),
            &cfg,
            width,
            height,
        ),
        View::Turntable => turntable(texture.as_ref(), &shape, &cfg, width, height),
    };
    save_png(&image, &args.out).with_context(|| format!("rendering {what}"))?;
    Ok(())
}
