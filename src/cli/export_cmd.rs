//! `xylem export`: convert a volume for other tools.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::export::{Format, export};
use xylem::io::check_new_file;

/// Export a volume as .npy, Mitsuba 3 .vol or NRRD.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem export --volume out/synth/volume.npy --format vol --out wood.vol
  xylem export --volume out/synth/volume.npy --format nrrd --out wood.nrrd

Axis orders: .npy [X, Y, Z, C] (z fastest); .vol x fastest, bounding box [-0.5, 0.5]^3
(Mitsuba gridvolume); .nrrd sizes 'C Z Y X' fastest first with space directions and origin
placing voxel centres in cube coordinates.")]
pub struct ExportArgs {
    /// Input volume (.npy, float32 [X, Y, Z, C]).
    #[arg(long, value_name = "V.npy")]
    pub volume: PathBuf,
    /// npy, vol or nrrd.
    #[arg(long)]
    pub format: Format,
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: ExportArgs) -> Result<()> {
    check_new_file(&args.out, args.force)?;
    let volume = xylem::io::npy::read_volume(&args.volume)?;
    export(&volume, args.format, &args.out)?;
    Ok(())
}
