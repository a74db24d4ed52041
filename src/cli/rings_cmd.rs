//! `xylem rings`: ring-localisation images predicted from a sample's photos.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use xylem::Face;
use xylem::config::write_config_copy;
use xylem::io::{OutputDir, read_bytes, save_png, write_bytes_atomic};
use xylem::rings::sheet::{RingsRow, rings_sheet};
use xylem::rings::{Agreement, RingSource, agreement, load_with_rings};
use xylem::sample::Sample;

use super::json_out::say;
use super::output_args::{SampleWithFitConfig, help_texts};

/// Predict ring-localisation images (bright bands on the annual rings) from the face photos
/// of a sample folder, for cubes that come without them.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem rings --sample my_cube --out out/my_cube_rings
  xylem rings --sample ../shared/data/mokume/CN03 --out out/CN03_rings

Writes OUT/A_arl.png..F_arl.png (the predicted ring images), a copy of the photos and knot
markers (so OUT is a complete sample folder: `xylem fit --sample OUT`), OUT/sheet.png (per
face: photo | predicted | given | both overlaid, given green and predicted magenta),
OUT/agreement.csv where the folder has its own ring images (correlation best within 2 px,
precision and recall of ring pixels within 2 px) and OUT/config.toml (the fit config whose
[localiser] table was used). `xylem fit` and `xylem run` run the same localiser themselves
on faces without ring images.",
    mut_args(help_texts(&[
        ("sample", "Sample folder with the face photos A_col.png..F_col.png"),
        ("faces", "These faces only, e.g. A,B,C; default all six"),
        ("config", "Fit config whose [localiser] table sets the localiser \
            (configs/fit/default.toml); default: the built-in defaults"),
    ]))
)]
pub struct RingsArgs {
    #[command(flatten)]
    pub input: SampleWithFitConfig,
}

pub fn run(args: RingsArgs) -> Result<()> {
    let args = args.input;
    let (cfg, faces) = args.config_and_faces()?;
    let started = Instant::now();
    let loaded = load_with_rings(&args.sample, &faces, RingSource::Predict, &cfg.localiser)?;
    let seconds = started.elapsed().as_secs_f64();
    let sample = loaded.sample;
    let out = OutputDir::prepare(&args.out)?;
    let mut rows = Vec::new();
    let mut scores = Vec::new();
    for &face in &faces {
        let predicted = sample.ring_image(face).expect("predicted for every face");
        save_png(predicted, &out.path(format!("{face}_arl.png")))?;
        copy_sample_files(&sample, face, &out)?;
        let given = Sample::given_ring_image(&args.sample, face)?
            .filter(|g| g.width == predicted.width && g.height == predicted.height);
        if let Some(g) = &given {
            scores.push((face, agreement(predicted, g)));
        }
        rows.push(RingsRow {
            photo: sample.photo(face).expect("photos loaded").clone(),
            predicted: predicted.clone(),
            given,
        });
    }
    save_png(&rings_sheet(&rows), &out.path("sheet.png"))?;
    write_config_copy(
        &out.path("config.toml"),
        &cfg,
        &config_origin(args.config.as_deref()),
    )?;
    if !scores.is_empty() {
        write_bytes_atomic(
            &out.path("agreement.csv"),
            agreement_csv(&scores).as_bytes(),
        )?;
        for (face, a) in &scores {
            say(&format!(
                "{face}: correlation {:.2}, precision {:.2}, recall {:.2} (vs the given ring image)",
                a.correlation, a.precision, a.recall
            ));
        }
    }
    say(&format!(
        "predicted {} ring images in {seconds:.2} s; wrote {}",
        faces.len(),
        args.out.display()
    ));
    Ok(())
}

/// The photo and knot marker of `face`, copied so the output folder is a sample of its own.
fn copy_sample_files(sample: &Sample, face: Face, out: &OutputDir) -> Result<()> {
    for name in [format!("{face}_col.png"), format!("{face}_knot.png")] {
        let from = sample.dir.join(&name);
        if from.is_file() {
            let bytes = read_bytes(&from, "a PNG image")?;
            write_bytes_atomic(&out.path(&name), &bytes)
                .with_context(|| format!("copying {}", from.display()))?;
        }
    }
    Ok(())
}

fn agreement_csv(scores: &[(Face, Agreement)]) -> String {
    let mut csv = String::from("face,correlation,precision,recall\n");
    for (face, a) in scores {
        csv.push_str(&format!(
            "{face},{:.4},{:.4},{:.4}\n",
            a.correlation, a.precision, a.recall
        ));
    }
    csv
}

fn config_origin(path: Option<&Path>) -> String {
    path.map_or_else(
        || "built-in defaults".to_string(),
        |p| p.display().to_string(),
    )
}
