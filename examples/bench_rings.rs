//! Accuracy and time of the ring localiser (issue 13), printed as Markdown tables.
//!
//!     XYLEM_MOKUME_DIR=../shared/data/mokume cargo run --release --example bench_rings -- real [FIT_CONFIG]
//!     cargo run --release --example bench_rings -- synthetic [FIT_CONFIG]
//!     XYLEM_MOKUME_DIR=../shared/data/mokume cargo run --release --example bench_rings -- lofo [FIT_CONFIG]
//!     XYLEM_MOKUME_DIR=../shared/data/mokume cargo run --release --example bench_rings -- per-face [FIT_CONFIG]
//!
//! - `real`: CN03 and H11. Per face, the predicted ring image against the authors' U-Net
//!   image (`rings::agreement`: correlation best within 2 px, precision and recall of ring
//!   pixels within 2 px) and the localiser's time; then the fit from the given and from the
//!   predicted ring images: the iso-contour error (mm) of the *given* images' contours under
//!   each fitted field, and the mean correlation (best within 3 px) of each fitted field's
//!   ring image with the given images on the six faces.
//! - `synthetic`: a 256 px `xylem sample` of every species preset: agreement with the exact
//!   ring images, and the fits from exact and from predicted rings compared with the truth
//!   (correlation of the fitted ring image with the true one on the faces and the hidden
//!   cuts; iso error of the exact images' contours under each fitted field).
//! - `lofo`: leave-one-face-out on CN03 and H11 for both ring sources: fit on five faces,
//!   on the held-out face the correlation (best within 3 px) of the predicted I(G) with the
//!   given U-Net image and the iso error (mm) of that face's given contours.
//! - `per-face`: CN03 and H11, per face and for all six, the iso error (mm) of the given and
//!   of the predicted contours under the fits from given and from predicted rings.
//!
//! Every mode judges with the default `[contours]` settings, whatever FIT_CONFIG sets there:
//! a config under test changes the fits, never the contours they are judged by.

#[path = "common/fit_bench.rs"]
mod fit_bench;

use std::path::Path;
use std::time::Instant;

use fit_bench::{mean, mokume_dir, table_header};
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField, RingImage};
use xylem::fit::metrics::{iso_error_mm, shifted_correlation, truth_ring_correlations};
use xylem::fit::run::contour_set;
use xylem::fit::{FitConfig, FitResult, fit_sample};
use xylem::frame::Face;
use xylem::rings::{RingSource, agreement, load_with_rings};
use xylem::sample::Sample;
use xylem::slice::slice_face;

const SIZE: usize = 256;
/// Pixels of shift forgiven by the fitted-ring correlations (as bench_fit's lofo).
const SHIFT: usize = 3;
const SOURCES: [RingSource; 2] = [RingSource::Given, RingSource::Predict];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cfg = match args.get(1) {
        Some(path) => FitConfig::load(Path::new(path)).expect("fit config"),
        None => FitConfig::default(),
    };
    match args.first().map(String::as_str).unwrap_or("real") {
        "real" => real(&cfg),
        "synthetic" => synthetic(&cfg),
        "lofo" => lofo(&cfg),
        "per-face" => per_face(&cfg),
        other => panic!("unknown mode {other:?}; expected real, synthetic, lofo or per-face"),
    }
}

fn load(dir: &Path, faces: &[Face], source: RingSource, cfg: &FitConfig) -> Sample {
    load_with_rings(dir, faces, source, &cfg.localiser)
        .expect("sample")
        .sample
}

fn fit(sample: &Sample, cfg: &FitConfig) -> FitResult {
    fit_sample(sample, cfg, &mut |_, _, _| {}).expect("fit")
}

/// Agreement rows of the six faces against `reference`; returns the mean and the seconds
/// per face.
fn agreement_rows(name: &str, dir: &Path, cfg: &FitConfig) -> ([f32; 3], f64) {
    let given = load(dir, &Face::ALL, RingSource::Given, cfg);
    let started = Instant::now();
    let predicted = load(dir, &Face::ALL, RingSource::Predict, cfg);
    let per_face = started.elapsed().as_secs_f64() / 6.0;
    let mut sum = [0f32; 3];
    for face in Face::ALL {
        let a = agreement(
            predicted.ring_image(face).expect("predicted"),
            given.ring_image(face).expect("given"),
        );
        println!(
            "| {name} | {face} | {:.2} | {:.2} | {:.2} |",
            a.correlation, a.precision, a.recall
        );
        sum[0] += a.correlation / 6.0;
        sum[1] += a.precision / 6.0;
        sum[2] += a.recall / 6.0;
    }
    println!(
        "| {name} | mean | {:.2} | {:.2} | {:.2} |",
        sum[0], sum[1], sum[2]
    );
    (sum, per_face)
}

fn agreement_header() {
    table_header(
        "sample | face | correlation (best within 2 px) | precision (2 px) | recall (2 px)",
    );
}

fn real(cfg: &FitConfig) {
    agreement_header();
    let mut times = Vec::new();
    for name in ["CN03", "H11"] {
        let (_, per_face) = agreement_rows(name, &mokume_dir().join(name), cfg);
        times.push((name, per_face));
    }
    for (name, t) in times {
        println!(
            "\n{name}: localiser {:.3} s per 256 px face (includes loading the photo)",
            t
        );
    }
    println!();
    table_header(
        "sample | rings | iso error of the given contours (mm) | faces corr. with the given rings (best within 3 px) | fit time (s)",
    );
    for name in ["CN03", "H11"] {
        let dir = mokume_dir().join(name);
        let given = load(&dir, &Face::ALL, RingSource::Given, cfg);
        let set = contour_set(&given, &Face::ALL, &judging(cfg));
        for source in SOURCES {
            let sample = load(&dir, &Face::ALL, source, cfg);
            let started = Instant::now();
            let r = fit(&sample, cfg);
            let secs = started.elapsed().as_secs_f64();
            let field = GrowthField::from_config(&r.field);
            let faces = mean(Face::ALL.iter().map(|&f| {
                let target = given.ring_image(f).expect("given");
                let fitted = slice_face(&RingImage(&field), f, target.width);
                shifted_correlation(&fitted, target, cfg.contours.border, SHIFT)
            }));
            println!(
                "| {name} | {source} | {:.3} | {faces:.2} | {secs:.1} |",
                iso_error_mm(&field, &set)
            );
        }
    }
}

fn synthetic(cfg: &FitConfig) {
    let root = std::env::temp_dir().join(format!("xylem-bench-rings-{}", std::process::id()));
    let names: Vec<&str> = xylem::presets::SPECIES_PRESETS
        .iter()
        .map(|(n, _)| *n)
        .collect();
    agreement_header();
    for &species in &names {
        let dir = root.join(species);
        let wood = xylem::presets::load_species_preset(species).expect("species preset");
        let out = xylem::io::OutputDir::prepare(&dir).expect("sample folder");
        xylem::procedural::write_sample(&wood, species, SIZE, &out).expect("xylem sample");
        agreement_rows(species, &dir, cfg);
    }
    println!();
    table_header(
        "sample | rings | faces corr. with truth | cut1 corr. | cut2 corr. | iso error of the exact contours (mm)",
    );
    for &species in &names {
        let dir = root.join(species);
        let truth_cfg = FieldConfig::load(&dir.join("truth/field.toml")).expect("truth field");
        let truth = GrowthField::from_config(&truth_cfg);
        let exact = contour_set(
            &load(&dir, &Face::ALL, RingSource::Given, cfg),
            &Face::ALL,
            &judging(cfg),
        );
        for source in SOURCES {
            let sample = load(&dir, &Face::ALL, source, cfg);
            let r = fit(&sample, cfg);
            let fitted = GrowthField::from_config(&r.field);
            let [faces, cut1, cut2] = truth_ring_correlations(&fitted, &truth, SIZE);
            let label = if source == RingSource::Given {
                "exact"
            } else {
                "predicted"
            };
            println!(
                "| {species} | {label} | {faces:.2} | {:.2} | {:.2} | {:.3} |",
                cut1,
                cut2,
                iso_error_mm(&fitted, &exact)
            );
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}

fn lofo(cfg: &FitConfig) {
    table_header(
        "sample | rings | held-out face | ARL corr. (best within 3 px) | held-out iso error (mm)",
    );
    for name in ["CN03", "H11"] {
        let dir = mokume_dir().join(name);
        let given = load(&dir, &Face::ALL, RingSource::Given, cfg);
        for source in SOURCES {
            let (mut corrs, mut errors) = (Vec::new(), Vec::new());
            for held in Face::ALL {
                let faces: Vec<Face> = Face::ALL.into_iter().filter(|&f| f != held).collect();
                let r = fit(&load(&dir, &faces, source, cfg), cfg);
                let field = GrowthField::from_config(&r.field);
                let target = given.ring_image(held).expect("given");
                let predicted = slice_face(&RingImage(&field), held, target.width);
                let corr = shifted_correlation(&predicted, target, cfg.contours.border, SHIFT);
                let error = iso_error_mm(&field, &contour_set(&given, &[held], &judging(cfg)));
                println!("| {name} | {source} | {held} | {corr:.2} | {error:.3} |");
                corrs.push(corr);
                errors.push(error);
            }
            println!(
                "| {name} | {source} | mean | {:.2} | {:.3} |",
                mean(corrs),
                mean(errors)
            );
        }
    }
}

/// Per face of CN03 and H11, the iso error (mm) of the given and of the predicted contours
/// under the fits from given and from predicted rings: which faces the gap between the two
/// fits comes from, and whether the predicted lines are as good iso-lines of the given fit
/// as the given ones.
fn per_face(cfg: &FitConfig) {
    table_header(
        "sample | face | given contours, given fit | given contours, predicted fit | predicted contours, given fit | predicted contours, predicted fit | contours given / predicted",
    );
    let judge = judging(cfg);
    for name in ["CN03", "H11"] {
        let dir = mokume_dir().join(name);
        let given = load(&dir, &Face::ALL, RingSource::Given, cfg);
        let predicted = load(&dir, &Face::ALL, RingSource::Predict, cfg);
        let from_given = GrowthField::from_config(&fit(&given, cfg).field);
        let from_predicted = GrowthField::from_config(&fit(&predicted, cfg).field);
        let rows = Face::ALL.iter().map(|&f| (f.to_string(), vec![f]));
        for (label, faces) in rows.chain(std::iter::once(("all".to_string(), Face::ALL.to_vec()))) {
            let g = contour_set(&given, &faces, &judge);
            let p = contour_set(&predicted, &faces, &judge);
            println!(
                "| {name} | {label} | {:.3} | {:.3} | {:.3} | {:.3} | {} / {} |",
                iso_error_mm(&from_given, &g),
                iso_error_mm(&from_predicted, &g),
                iso_error_mm(&from_given, &p),
                iso_error_mm(&from_predicted, &p),
                g.len(),
                p.len()
            );
        }
    }
}

/// The contour settings every mode judges with: the default ones whatever `cfg` under test
/// says, so that a fit config that changes `[contours]` changes the fits, not the yardstick.
fn judging(cfg: &FitConfig) -> FitConfig {
    FitConfig {
        contours: FitConfig::default().contours,
        ..cfg.clone()
    }
}
