//! `xylem fit`: fit a growth field and base colour to a sample folder.

use anyhow::Result;
use clap::Args;
use xylem::pipeline::{FitOptions, fit_into};
use xylem::rings::RingSource;

use super::json_out::Summary;
use super::output_args::{SampleWithFitConfig, help_texts};
use super::progress::CliReporter;

/// Fit the growth field (pith, rate grid, knots, ring positions) and the base colour to the
/// ring images and photos of a sample folder.
#[derive(Args, Debug)]
#[command(
    after_help = "The sample folder holds A_col.png..F_col.png, optionally A_arl-unet.png (or \
A_arl.png)..F_arl*.png ring images (predicted from the photos where absent, as `xylem rings` \
does) and X_knot.png knot markers (Mokume layout).

Examples:
  xylem fit --sample ../shared/data/mokume/CN03 --out out/fit/CN03
  xylem fit --sample ../shared/data/mokume/H11 --out out/fit/H11-noE --faces A,B,C,D,F

Writes OUT/fit.toml (the fitted field: `xylem field --config OUT/fit.toml` renders it),
OUT/faces/X_arl.png and X_base.png for all six faces, OUT/cuts/cut1_arl.png, cut2_arl.png,
cut1_base.png, cut2_base.png, OUT/sheet.png (per face: photo | target rings | fitted rings |
both overlaid, target green and fit magenta | base colour; held-out faces framed red),
OUT/loss.csv and OUT/config.toml (the fit config used).",
    mut_args(help_texts(&[
        ("sample", "Sample folder (Mokume layout)"),
        ("faces", "Fit on these faces only, e.g. A,B,C,D,E (leave-one-face-out); \
            default all six"),
        ("config", "Fit config (TOML, see configs/fit/default.toml); \
            default: the built-in defaults"),
    ]))
)]
pub struct FitArgs {
    #[command(flatten)]
    pub input: SampleWithFitConfig,
    /// Ring images: auto (the folder's X_arl-unet.png / X_arl.png where present, predicted
    /// from the photos elsewhere), given (the folder's only), predict (from the photos for
    /// every face; see `xylem rings`).
    #[arg(long, default_value = "auto", value_name = "SOURCE", value_parser = super::output_args::ring_source)]
    pub rings: RingSource,
}

pub fn run(args: FitArgs) -> Result<()> {
    let (config, faces) = args.input.config_and_faces()?;
    let options = FitOptions {
        sample: &args.input.sample,
        faces: &faces,
        config: &config,
        rings: args.rings,
    };
    let result = fit_into(&options, &args.input.out, &CliReporter)?;
    Summary::new("fit")
        .text("sample", &args.input.sample.display().to_string())
        .text("out", &args.input.out.display().to_string())
        .number("iso_mm_step1", f64::from(result.iso_mm_step1))
        .number("iso_mm_step2", f64::from(result.iso_mm_step2))
        .integer("contours", result.contours as u64)
        .number("seconds", result.seconds.iter().sum::<f64>())
        .emit();
    Ok(())
}
