//! `xylem field`: render a growth field's ring localisation image on the faces and cuts.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use xylem::config::write_config_copy;
use xylem::field::{FieldConfig, GrowthField, RingImage};
use xylem::io::OutputDir;
use xylem::outputs::SliceSet;

use super::presets::FieldSource;

/// Render a growth field: the ring localisation image I(G) on the six faces, the two
/// validation cuts and the unfolded cross.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem field --config configs/fields/distorted.toml --size 256 --out out/distorted
  xylem field --preset knot_dead --size 128 --out out/knot_dead

Writes DIR/faces/A.png..F.png (I(G) in grey), DIR/cuts/cut1.png, DIR/cuts/cut2.png,
DIR/unfolded.png (the cross: B above A, row C A E F, D below A) and DIR/config.toml.")]
pub struct FieldArgs {
    #[command(flatten)]
    pub source: FieldSource,
    /// Image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::output_args::side_2_8192)]
    pub size: u32,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

pub fn run(args: FieldArgs) -> Result<()> {
    let (cfg, origin) = args.source.load()?;
    render_field(&cfg, &origin, args.size as usize, &args.out)
}

/// Renders one field config into `out` (shared with `xylem demo`).
pub fn render_field(
    cfg: &FieldConfig,
    origin: &str,
    size: usize,
    out: &std::path::Path,
) -> Result<()> {
    let out = OutputDir::prepare(out)?;
    let field = GrowthField::from_config(cfg);
    let rings = RingImage(&field);
    SliceSet::render(&rings, size)
        .write(&out, "")
        .with_context(|| format!("writing the images of {origin}"))?;
    write_config_copy(&out.path("config.toml"), cfg, origin)?;
    Ok(())
}
