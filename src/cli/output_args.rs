//! The image size and output folder shared by commands that render a species.

use std::path::PathBuf;

use clap::Args;

#[derive(Args, Debug)]
pub struct SizeAndOut {
    /// Image (face) side in pixels.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(2..=8192))]
    pub size: u32,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long)]
    pub out: PathBuf,
}
