//! `xylem compare`: the comparison metrics of a candidate image against a reference, as one
//! JSON object on stdout.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use xylem::device::DeviceKind;
use xylem::io::{check_new_file, load_rgb, save_png};
use xylem::loss::LossConfig;
use xylem::metrics::{Comparer, difference_sheet};

use super::json_out::{Summary, json_mode};
use xylem::config::ConfigFile;

/// Compare a candidate image with a reference: ring alignment, grain direction, patch texture
/// distance (all, lightness, chroma), Lab colour differences and the style loss.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem compare ../shared/data/mokume/CN03/A_col.png out/nca/faces/A.png --sheet cmp.png

Prints one JSON object on stdout:
  ring_ncc    ring alignment, best correlation of band-passed luminance over +-3 px (1 = same)
  orient      grain-direction agreement, weighted mean cos(2 dtheta) (1 = same)
  swd         patch texture distance, sliced Wasserstein of Lab patches at 2 scales (0 = same)
  swd_L       the same on lightness patches only
  swd_chroma  the same on (a, b) patches only
  dE_mean     distance of the mean Lab colours (Delta E)
  dE_std      distance of the Lab standard deviations (Delta E)
  style       the style loss of the candidate against the reference (0 = same statistics)
  aniso       pore-scale anisotropy of the candidate, 0 to 1 (dots 0, dashes towards 1);
              aniso_ref the reference's (same = alike)
  speckle     pixel-scale speckle of the candidate: checkerboard over neighbour-difference
              energy (smooth 0, white noise 1, checkerboard 2); speckle_ref the reference's
A candidate of another size is resized to the reference's if the aspect ratios agree.")]
pub struct CompareArgs {
    /// The reference image (PNG).
    pub reference: PathBuf,
    /// The candidate image (PNG).
    pub candidate: PathBuf,
    /// Also write reference | candidate | difference to this PNG.
    #[arg(long)]
    pub sheet: Option<PathBuf>,
    /// Replace the sheet if it exists.
    #[arg(long)]
    pub force: bool,
    /// Loss config of the `style` value (default: the built-in configs/loss/default.toml).
    #[arg(long)]
    pub loss: Option<PathBuf>,
    /// CPU backend of the style loss: flex (default) or ndarray.
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
}

pub fn run(args: CompareArgs) -> Result<()> {
    if let Some(sheet) = &args.sheet {
        check_new_file(sheet, args.force)?;
    }
    let loss = match &args.loss {
        Some(path) => LossConfig::load(path)?,
        None => LossConfig::default_config(),
    };
    let reference = load_rgb(&args.reference)?;
    let candidate = load_rgb(&args.candidate)?;
    let metrics = Comparer::new(&loss, &args.device.device())
        .compare(&reference, &candidate)
        .with_context(|| {
            format!(
                "comparing {} with {}",
                args.candidate.display(),
                args.reference.display()
            )
        })?;
    if let Some(sheet) = &args.sheet {
        save_png(&difference_sheet(&reference, &candidate), sheet)?;
    }
    // compare's output always was one JSON object; --json only wraps it with the inputs.
    let summary = Summary::new("compare")
        .text("reference", &args.reference.display().to_string())
        .text("candidate", &args.candidate.display().to_string())
        .raw("metrics", metrics.to_json());
    if json_mode() {
        summary.emit();
    } else {
        println!("{}", metrics.to_json());
    }
    Ok(())
}
