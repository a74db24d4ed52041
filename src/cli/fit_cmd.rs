//! `xylem fit`: fit a growth field and base colour to a sample folder.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use xylem::Face;
use xylem::fit::run::total_steps;
use xylem::fit::{Display, FitConfig, fit_sample, write_fit};
use xylem::io::OutputDir;
use xylem::rings::{RingSource, load_with_rings};
use xylem::sample::{Needs, Sample, faces_or_all};

use super::json_out::{Summary, say};
use super::progress::Progress;

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
OUT/loss.csv and OUT/config.toml (the fit config used)."
)]
pub struct FitArgs {
    /// Sample folder (Mokume layout).
    #[arg(long, value_name = "DIR")]
    pub sample: PathBuf,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// Fit on these faces only, e.g. A,B,C,D,E (leave-one-face-out); default all six.
    #[arg(long, value_name = "LIST")]
    pub faces: Option<String>,
    /// Fit config (TOML, see configs/fit/default.toml); default: the built-in defaults.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Ring images: auto (the folder's X_arl-unet.png / X_arl.png where present, predicted
    /// from the photos elsewhere), given (the folder's only), predict (from the photos for
    /// every face; see `xylem rings`).
    #[arg(long, default_value = "auto", value_name = "SOURCE", value_parser = super::output_args::ring_source)]
    pub rings: RingSource,
}

pub fn run(args: FitArgs) -> Result<()> {
    let cfg = FitConfig::load_or_default(args.config.as_deref())?;
    let faces = faces_or_all(args.faces.as_deref())?;
    let loaded = load_with_rings(&args.sample, &faces, args.rings, &cfg.localiser)?;
    say_predicted(&loaded.predicted);
    let sample = loaded.sample;
    let out = OutputDir::prepare(&args.out)?;

    let bar = Progress::new("fit", total_steps(&cfg) as u64);
    let mut done_before = 0usize;
    let mut current = String::new();
    let mut report = |stage: &str, step: usize, _of: usize| {
        if stage != current {
            done_before = bar.position() as usize;
            current = stage.to_string();
            bar.set_message(current.clone());
        }
        bar.set_position((done_before + step) as u64);
    };
    let result = fit_sample(&sample, &cfg, &mut report)
        .with_context(|| format!("fitting {}", args.sample.display()))?;
    bar.finish();

    let display = display_images(&sample);
    write_fit(
        &out,
        &result,
        &cfg,
        &sample.faces,
        &display,
        sample.size,
        &args.sample.display().to_string(),
    )?;
    let seconds = result.seconds.iter().sum::<f64>();
    say(&format!(
        "iso-contour error: {:.3} mm after step 1 (pith), {:.3} mm after step 2; {} contours; \
         {seconds:.1} s",
        result.iso_mm_step1, result.iso_mm_step2, result.contours,
    ));
    say(&format!(
        "wrote {}/fit.toml and sheet.png",
        args.out.display()
    ));
    Summary::new("fit")
        .text("sample", &args.sample.display().to_string())
        .text("out", &args.out.display().to_string())
        .number("iso_mm_step1", f64::from(result.iso_mm_step1))
        .number("iso_mm_step2", f64::from(result.iso_mm_step2))
        .integer("contours", result.contours as u64)
        .number("seconds", seconds)
        .emit();
    Ok(())
}

/// Says which faces' ring images the localiser made (none when the folder had them all).
fn say_predicted(faces: &[Face]) {
    if !faces.is_empty() {
        let letters: Vec<String> = faces.iter().map(|f| f.letter().to_string()).collect();
        say(&format!(
            "ring images predicted from the photos for faces {} (the folder has none for them, \
             or --rings predict); OUT/sheet.png shows them",
            letters.join(",")
        ));
    }
}

/// Photos and ring images of all six faces for the sheet: the fitted faces' as the fit used
/// them (predicted ring images included), the others as far as the folder has them (shown,
/// never fitted; a photo without a ring image is still shown).
fn display_images(sample: &Sample) -> Display {
    let mut display = Display {
        photos: sample.photos.clone(),
        targets: sample.arl.clone(),
    };
    let photo_only = Needs {
        photos: true,
        arl: false,
    };
    for face in Face::ALL.into_iter().filter(|f| !sample.faces.contains(f)) {
        if let Ok(mut s) = Sample::load(&sample.dir, &[face], photo_only) {
            // A ring image of another size than its photo is left out.
            let _ = s.load_ring_image(face);
            display.photos[face.index()] = s.photos[face.index()].take();
            display.targets[face.index()] = s.arl[face.index()].take();
        }
    }
    display
}
