//! `xylem slice`: one image of a solid texture on a plane.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::field::{FieldConfig, GrowthField, RingImage};
use xylem::frame::PlaneSpec;
use xylem::io::{check_new_file, save_png};
use xylem::procedural::{ProceduralWood, SpeciesConfig};
use xylem::slice::slice_plane;
use xylem::texture::SolidTexture;

/// What to slice: a growth field's ring image or a species' procedural wood.
#[derive(clap::Args, Debug)]
#[group(required = true, multiple = false)]
pub struct SliceSource {
    /// Growth-field config (TOML); the image is its ring localisation I(G) in grey.
    #[arg(long, value_name = "FILE")]
    pub field: Option<PathBuf>,
    /// Species config (TOML); the image is the procedural wood's colour.
    #[arg(long, value_name = "FILE")]
    pub procedural: Option<PathBuf>,
}

/// Slice a solid texture with a plane and write one PNG.
#[derive(Args, Debug)]
#[command(after_help = "Planes:
  cut1, cut2      the validation cuts of docs/DESIGN.md section 3
  A .. F          a cube face
  \"ox,oy,oz;ux,uy,uz;vx,vy,vz\"
                  origin = the image's top-left corner, u = its width edge, v = its height
                  edge, in cube units (the cube is [-0.5, 0.5]^3)

Examples:
  xylem slice --field configs/fields/knot_alive.toml --plane cut1 --size 256 --out cut1.png
  xylem slice --field configs/fields/far.toml --plane \"-0.5,0,0.5;1,0,0;0,0,-1\" --out mid.png
  xylem slice --procedural configs/species/oak.toml --plane cut2 --size 512 --out oak.png")]
pub struct SliceArgs {
    #[command(flatten)]
    pub source: SliceSource,
    /// The plane: cut1, cut2, A..F, or "ox,oy,oz;ux,uy,uz;vx,vy,vz".
    #[arg(long, allow_hyphen_values = true)]
    pub plane: PlaneSpec,
    /// Image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(2..=8192))]
    pub size: u32,
    /// Output PNG.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: SliceArgs) -> Result<()> {
    check_new_file(&args.out, args.force)?;
    let texture: Box<dyn SolidTexture> = match (&args.source.field, &args.source.procedural) {
        (Some(path), _) => Box::new(RingImage(GrowthField::from_config(&FieldConfig::load(
            path,
        )?))),
        (None, Some(path)) => Box::new(ProceduralWood::new(&SpeciesConfig::load(path)?)),
        (None, None) => unreachable!("clap requires --field or --procedural"),
    };
    let n = args.size as usize;
    let image = slice_plane(texture.as_ref(), &args.plane.plane(), n, n);
    save_png(&image, &args.out)?;
    Ok(())
}
