//! `xylem slice`: one image of a solid texture on a plane.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::frame::PlaneSpec;
use xylem::io::{check_new_file, save_png};
use xylem::slice::slice_plane;

use super::texture_source::{ShadingSource, TextureSource};

/// Slice a solid texture with a plane and write one PNG.
#[derive(Args, Debug)]
#[command(
    after_help = "The PNG holds the first three channels as display sRGB, clamped to [0, 1] (an
NCA volume may step slightly outside; `xylem synth` prints by how much).

Planes:
  cut1, cut2      the validation cuts of docs/DESIGN.md section 3
  A .. F          a cube face
  \"ox,oy,oz;ux,uy,uz;vx,vy,vz\"
                  origin = the image's top-left corner, u = its width edge, v = its height
                  edge, in cube units (the cube is [-0.5, 0.5]^3)

Examples:
  xylem slice --field configs/fields/knot_alive.toml --plane cut1 --size 256 --out cut1.png
  xylem slice --field configs/fields/far.toml --plane \"-0.5,0,0.5;1,0,0;0,0,-1\" --out mid.png
  xylem slice --procedural configs/species/oak.toml --plane cut2 --size 512 --out oak.png
  xylem slice --volume out/synth/volume.npy --plane cut1 --out cut1.png
  xylem slice --volume out/run/synth/volume.npy --grain-shading out/run/fit --plane B --out B.png"
)]
pub struct SliceArgs {
    #[command(flatten)]
    pub source: TextureSource,
    #[command(flatten)]
    pub shading: ShadingSource,
    /// The plane: cut1, cut2, A..F, or "ox,oy,oz;ux,uy,uz;vx,vy,vz".
    #[arg(long, allow_hyphen_values = true, value_parser = super::output_args::flagged::<PlaneSpec>)]
    pub plane: PlaneSpec,
    /// Image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::output_args::side_2_8192)]
    pub size: u32,
    /// Output PNG.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: SliceArgs) -> Result<()> {
    check_new_file(&args.out, args.force)?;
    let (texture, _) = args.source.load_colour()?;
    let texture = args.shading.apply(texture)?;
    let n = args.size as usize;
    let image = slice_plane(texture.as_ref(), &args.plane.plane(), n, n);
    save_png(&image, &args.out)?;
    Ok(())
}
