//! The ring localiser (issue 13): it finds the rings of synthetic faces, a folder of photos
//! alone runs through `xylem fit`, and bad folders get errors that name the file.

mod common;
use common::{photos_only, run_err, run_ok, run_ok_said, xylem};

use std::path::Path;

use xylem::Face;
use xylem::config::Checker;
use xylem::config::ConfigFile;
use xylem::fit::FitConfig;
use xylem::io::{OutputDir, load_rgb, save_png};
use xylem::presets::load_species_preset;
use xylem::procedural::write_sample;
use xylem::rings::{LocaliserConfig, RingSource, agreement, load_with_rings, localise};
use xylem::sample::Sample;

/// A `xylem sample` of `species` at `size` px in a fresh scratch folder.
fn synthetic_sample(name: &str, species: &str, size: usize) -> common::Scratch {
    let dir = common::scratch(name);
    let wood = load_species_preset(species).unwrap();
    write_sample(&wood, species, size, &OutputDir::prepare(&dir).unwrap()).unwrap();
    dir
}

/// Floors for the side-grain and end-grain faces of the softwood preset at 256 px, where
/// the measured agreement with the exact ring images is about 0.9 precision and recall
/// (BENCHMARKS "Ring localisation"); a detector that drew noise or missed the latewood
/// lines falls far below.
#[test]
fn localiser_finds_the_rings_of_synthetic_faces() {
    let dir = synthetic_sample("rings-softwood", "softwood", 256);
    let cfg = LocaliserConfig::default();
    for face in [Face::B, Face::D, Face::E] {
        let photo = load_rgb(&dir.join(format!("{face}_col.png"))).unwrap();
        let exact = xylem::io::load_gray(&dir.join(format!("{face}_arl.png"))).unwrap();
        let predicted = localise(&photo, &cfg);
        assert_eq!((predicted.width, predicted.height), (256, 256));
        assert!(predicted.data.iter().all(|v| (0.0..=1.0).contains(v)));
        let a = agreement(&predicted, &exact);
        assert!(a.precision > 0.7, "face {face}: precision {}", a.precision);
        assert!(a.recall > 0.7, "face {face}: recall {}", a.recall);
        assert!(
            a.correlation > 0.5,
            "face {face}: correlation {}",
            a.correlation
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 256 px face of a ring-porous wood seen flat-sawn: the rings are oblique bands made of
/// many short dark dashes along the fibres (vertical), with a few dashes between the bands
/// (as CN03 F). Returns the photo and the band centres as a ring image.
fn dashed_bands() -> (xylem::Image2, xylem::Image2) {
    const N: usize = 256;
    const PERIOD: f32 = 40.0;
    const BAND: f32 = 10.0;
    const SLOPE: f32 = 0.6;
    let phase = |row: usize, col: usize| (col as f32 + SLOPE * row as f32).rem_euclid(PERIOD);
    let mut light = vec![0.72f32; N * N];
    let mut rng = xylem::rng::Rng::new(3);
    for _ in 0..6000 {
        let (row, col) = (rng.below(N), rng.below(N));
        let chance = if phase(row, col) < BAND { 0.9 } else { 0.08 };
        if rng.uniform() < chance {
            for r in row.saturating_sub(3)..(row + 3).min(N) {
                for c in col..(col + 2).min(N) {
                    light[r * N + c] = 0.45;
                }
            }
        }
    }
    let tint = [1.0, 0.82, 0.62];
    let photo: Vec<f32> = light
        .iter()
        .flat_map(|&v| tint.map(|t| (v * t).min(1.0)))
        .collect();
    let mut rings = xylem::Image2::filled(N, N, 1, 0.0);
    for row in 0..N {
        for col in 0..N {
            let off =
                (phase(row, col) - BAND / 2.0 + PERIOD / 2.0).rem_euclid(PERIOD) - PERIOD / 2.0;
            let across = off / (1.0 + SLOPE * SLOPE).sqrt();
            rings.pixel_mut(row, col)[0] = (-0.5 * (across / 2.5).powi(2)).exp();
        }
    }
    (xylem::Image2::from_data(N, N, 3, photo).unwrap(), rings)
}

/// The pore density term (`pore_weight`) is what lets the localiser see a band of pores as
/// one ring instead of many dashes along the fibres: correlation with the band centres 0.65
/// without it, 0.86 with the defaults (weight 2, 5 px high-pass and density).
#[test]
fn pore_density_turns_a_band_of_dashes_into_one_ring() {
    let (photo, bands) = dashed_bands();
    let with = LocaliserConfig::default();
    assert!(with.pore_weight > 0.0);
    let without = LocaliserConfig {
        pore_weight: 0.0,
        ..with.clone()
    };
    let a_with = agreement(&localise(&photo, &with), &bands).correlation;
    let a_without = agreement(&localise(&photo, &without), &bands).correlation;
    assert!(a_with > 0.75, "with the pore density: correlation {a_with}");
    assert!(
        a_with > a_without + 0.1,
        "with {a_with} against without {a_without}"
    );
}

#[test]
fn localiser_is_deterministic_and_blank_on_a_flat_photo() {
    let dir = synthetic_sample("rings-chestnut", "chestnut", 64);
    let photo = load_rgb(&dir.join("B_col.png")).unwrap();
    let cfg = LocaliserConfig::default();
    assert_eq!(localise(&photo, &cfg), localise(&photo, &cfg));
    let flat = xylem::Image2::filled(64, 64, 3, 0.6);
    let rings = localise(&flat, &cfg);
    assert!(rings.data.iter().all(|v| v.is_finite() && *v <= 1.0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ring_sources_choose_given_or_predicted_images() {
    let dir = synthetic_sample("rings-sources", "maple", 64);
    let cfg = LocaliserConfig::default();
    let auto = load_with_rings(&dir, &Face::ALL, RingSource::Auto, &cfg).unwrap();
    assert!(
        auto.predicted.is_empty(),
        "the folder has all six ring images"
    );
    let predict = load_with_rings(&dir, &Face::ALL, RingSource::Predict, &cfg).unwrap();
    assert_eq!(predict.predicted, Face::ALL.to_vec());
    assert_ne!(
        auto.sample.ring_image(Face::A),
        predict.sample.ring_image(Face::A)
    );
    std::fs::remove_file(dir.join("C_arl.png")).unwrap();
    let mixed = load_with_rings(&dir, &Face::ALL, RingSource::Auto, &cfg).unwrap();
    assert_eq!(mixed.predicted, vec![Face::C]);
    let err = load_with_rings(&dir, &Face::ALL, RingSource::Given, &cfg)
        .err()
        .expect("given rings are required")
        .to_string();
    assert!(
        err.contains("C_arl") && err.contains("xylem rings"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn localiser_config_values_are_checked_with_the_key() {
    let mut cfg = LocaliserConfig::default();
    cfg.high_percentile = cfg.low_percentile;
    let err = cfg
        .validate(&Checker::new(Path::new("fit.toml")))
        .unwrap_err()
        .to_string();
    assert!(err.contains("high_percentile"), "{err}");
    let err = FitConfig::parse("[localiser]\nvalley_offsets = []\n", Path::new("fit.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("localiser.valley_offsets"), "{err}");
}

/// A fit config small enough for a test (as tests/fit.rs's).
const QUICK_FIT: &str = "[contours]\nborder = 2\nmin_pixels = 10\n\
[pith]\ndirection_step_deg = 10.0\ndistances = [0.0, 0.5, 1.0, 2.0, 4.0]\noffset_azimuths = 12\n\
search_points = 600\nrefine = 2\niterations = 60\n\
[distortion]\niterations = 30\ntrial_iterations = 10\nimage_stride = 3\n\
[colour]\niterations = 10\n";

#[test]
fn a_folder_of_photos_alone_runs_through_fit_and_rings() {
    let full = synthetic_sample("rings-fit-full", "chestnut", 96);
    let photos = photos_only(&full, "rings-fit-photos");
    let config = photos.with_extension("toml");
    std::fs::write(&config, QUICK_FIT).unwrap();
    let out = common::scratch("rings-fit-out");
    let said = run_ok_said(
        xylem()
            .args(["fit", "--quiet", "--sample"])
            .arg(&photos)
            .arg("--out")
            .arg(&out)
            .arg("--config")
            .arg(&config),
    );
    assert!(
        said.contains("predicted from the photos for faces A,B,C,D,E,F"),
        "{said}"
    );
    assert!(out.join("fit.toml").is_file() && out.join("sheet.png").is_file());
    // The sheet's first tile is the photo of face A (it was blank for folders without ring
    // images): not one flat colour.
    let sheet = load_rgb(&out.join("sheet.png")).unwrap();
    let tile = sheet.crop(0, 0, 96, 96).unwrap();
    let first = tile.pixel(0, 0).to_vec();
    assert!(
        (0..96).any(|r| (0..96).any(|c| tile.pixel(r, c) != first.as_slice())),
        "the photo tile of the fit's sheet is blank"
    );

    let stderr = run_err(
        xylem()
            .args(["fit", "--quiet", "--rings", "given", "--sample"])
            .arg(&photos)
            .arg("--out")
            .arg(common::scratch("rings-fit-given")),
    );
    assert!(
        stderr.contains("A_arl") && stderr.contains("missing ring localisation image"),
        "{stderr}"
    );

    let rings_out = common::scratch("rings-cmd-out");
    run_ok(
        xylem()
            .args(["rings", "--sample"])
            .arg(&full)
            .arg("--out")
            .arg(&rings_out),
    );
    for face in Face::ALL {
        assert!(rings_out.join(format!("{face}_arl.png")).is_file());
        assert!(rings_out.join(format!("{face}_col.png")).is_file());
    }
    let csv = std::fs::read_to_string(rings_out.join("agreement.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    assert!(rings_out.join("sheet.png").is_file() && rings_out.join("config.toml").is_file());
    // The output is a sample folder of its own.
    let sample = Sample::load(
        &rings_out,
        &Face::ALL,
        xylem::sample::Needs {
            photos: true,
            arl: true,
        },
    )
    .unwrap();
    assert_eq!(sample.size, 96);
    let _ = std::fs::remove_file(&config);
}

/// Spoils one photo of a photos-only folder.
type Spoil = Box<dyn Fn(&Path)>;

#[test]
fn photos_that_are_not_square_differ_in_size_or_are_missing_are_named() {
    let full = synthetic_sample("rings-bad-full", "oak", 64);
    let cases: [(&str, Spoil, &str); 3] = [
        (
            "not-square",
            Box::new(|d: &Path| {
                save_png(&xylem::Image2::filled(64, 48, 3, 0.5), &d.join("B_col.png")).unwrap()
            }),
            "B_col.png: is 64x48; face images must be square",
        ),
        (
            "sizes",
            Box::new(|d: &Path| {
                save_png(&xylem::Image2::filled(80, 80, 3, 0.5), &d.join("C_col.png")).unwrap()
            }),
            "C_col.png: is 80x80, but the sample's other images are 64x64",
        ),
        (
            "missing",
            Box::new(|d: &Path| std::fs::remove_file(d.join("D_col.png")).unwrap()),
            "D_col.png",
        ),
    ];
    for (name, spoil, expected) in cases {
        let dir = photos_only(&full, &format!("rings-bad-{name}"));
        spoil(&dir);
        let stderr = run_err(
            xylem()
                .args(["rings", "--sample"])
                .arg(&dir)
                .arg("--out")
                .arg(common::scratch(&format!("rings-bad-out-{name}"))),
        );
        assert!(stderr.contains(expected), "{name}: {stderr}");
        let _ = std::fs::remove_dir_all(&dir);
    }
    let _ = std::fs::remove_dir_all(&full);
}

/// Horizontal lines every `period` rows from row `offset`: white, with grey shoulders.
fn stripes(n: usize, period: usize, offset: usize) -> xylem::Image2 {
    let mut img = xylem::Image2::filled(n, n, 1, 0.0);
    for r in 0..n {
        let v = match (r + period - offset % period) % period {
            0 => 1.0,
            d if d == 1 || d == period - 1 => 0.6,
            _ => 0.0,
        };
        for c in 0..n {
            img.pixel_mut(r, c)[0] = v;
        }
    }
    img
}

#[test]
fn agreement_forgives_two_pixels_and_no_more() {
    let reference = stripes(64, 12, 0);
    let same = agreement(&reference, &reference);
    assert!((same.correlation - 1.0).abs() < 1e-4);
    assert_eq!((same.precision, same.recall), (1.0, 1.0));
    let near = agreement(&stripes(64, 12, 2), &reference);
    assert_eq!((near.precision, near.recall), (1.0, 1.0));
    assert!(near.correlation > 0.99, "{}", near.correlation);
    let between = agreement(&stripes(64, 12, 6), &reference);
    assert_eq!((between.precision, between.recall), (0.0, 0.0));
    assert!(between.correlation < 0.5, "{}", between.correlation);
}
