//! `xylem procedural`: render the procedural wood model of a species config.

use anyhow::{Context, Result};
use clap::Args;
use xylem::config::write_config_copy;
use xylem::io::OutputDir;
use xylem::io::npy::write_volume;
use xylem::outputs::SliceSet;
use xylem::procedural::{FibreDirection, ProceduralWood};
use xylem::texture::SolidTexture;
use xylem::volume::Volume;

use super::output_args::SizeAndOut;
use super::presets::SpeciesSource;
use super::progress::Progress;

/// Render a species with the procedural wood model: the six faces, the two validation cuts,
/// the unfolded cross and optionally an RGB volume.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem procedural --config configs/species/oak.toml --size 256 --out out/oak
  xylem procedural --preset softwood --size 256 --out out/softwood --volume-size 128
  xylem procedural --preset maple --size 128 --out out/maple --volume-size 64 --fibre-direction

Writes DIR/faces/A.png..F.png, DIR/cuts/cut1.png, DIR/cuts/cut2.png, DIR/unfolded.png (the
cross: B above A, row C A E F, D below A) and DIR/config.toml. With --volume-size R also
DIR/volume.npy: float32 RGB in [0, 1], shape [R, R, R, 3] = [X, Y, Z, C]; vol[i, j, k] is
the voxel centred at ((i + 0.5)/R - 0.5, (j + 0.5)/R - 0.5, (k + 0.5)/R - 0.5).
--fibre-direction adds DIR/fibre_direction.npy: the unit fibre direction per voxel, same
shape and order.")]
pub struct ProceduralArgs {
    #[command(flatten)]
    pub source: SpeciesSource,
    #[command(flatten)]
    pub target: SizeAndOut,
    /// Also write an R^3 RGB volume as DIR/volume.npy (R voxels per side).
    #[arg(long, value_name = "R", value_parser = super::output_args::side_2_1024)]
    pub volume_size: Option<u32>,
    /// With --volume-size, also write the unit fibre direction (x, y, z in the cube frame) as
    /// DIR/fibre_direction.npy, shape [R, R, R, 3], for anisotropic rendering.
    #[arg(long, requires = "volume_size")]
    pub fibre_direction: bool,
}

pub fn run(args: ProceduralArgs) -> Result<()> {
    let (cfg, origin) = args.source.load()?;
    let out = OutputDir::prepare(&args.target.out)?;
    let model = ProceduralWood::new(&cfg);
    SliceSet::render(&model, args.target.size as usize)
        .write(&out, "")
        .with_context(|| format!("writing the images of {origin}"))?;
    write_config_copy(&out.path("config.toml"), &cfg, &origin)?;
    if let Some(r) = args.volume_size {
        let volume = render_volume(&model, r as usize, "volume")?;
        write_volume(&out.path("volume.npy"), &volume)?;
    }
    if let Some(r) = args.volume_size.filter(|_| args.fibre_direction) {
        let directions = FibreDirection(&model);
        let volume = render_volume(&directions, r as usize, "fibres")?;
        write_volume(&out.path("fibre_direction.npy"), &volume)?;
    }
    // Volumes an earlier call wrote into this (xylem's own) folder belong to another
    // config: keeping them beside the new images and config.toml would mislabel them.
    let written = [
        ("volume.npy", args.volume_size.is_some()),
        (
            "fibre_direction.npy",
            args.volume_size.is_some() && args.fibre_direction,
        ),
    ];
    for (name, now) in written {
        let path = out.path(name);
        if !now && path.is_file() {
            std::fs::remove_file(&path)
                .with_context(|| format!("removing the earlier {}", path.display()))?;
            eprintln!("removed {name} of an earlier call (not asked for this time)");
        }
    }
    println!("wrote {}", out.root().display());
    Ok(())
}

/// Evaluates a texture on an r^3 grid with a progress bar (one step per x-slab).
fn render_volume(texture: &dyn SolidTexture, r: usize, label: &str) -> Result<Volume> {
    let bar = Progress::new(&format!("{label} slabs"), r as u64);
    let volume = Volume::from_texture_with_progress(texture, r, &|| bar.inc(1));
    bar.finish();
    Ok(volume)
}
