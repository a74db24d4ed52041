//! Accuracy and time of `xylem fit` (issue 4), printed as Markdown table rows.
//!
//!     cargo run --release --example bench_fit -- synthetic [CONFIG]
//!     cargo run --release --example bench_fit -- real [CONFIG]
//!     cargo run --release --example bench_fit -- lofo [CONFIG]
//!
//! - `synthetic`: samples written from field configs with known truth (near, far, tilted,
//!   mildly and strongly distorted, knotted) at 256 px; pith distance (cm) and direction (degrees) errors after
//!   step 1, iso-contour error (mm) of the sample's contours under the step-1 field and under
//!   the final field, and correlation of the fitted ring image with the true one on the
//!   faces and on the hidden cuts cut1/cut2.
//! - `samples`: the same figures on `xylem sample` output (procedural colour photos, exact ring
//!   images, truth in `truth/field.toml`) of the species presets chestnut, softwood (knot)
//!   and oak (ring widths vary by year, so its ring images are not exactly I(G) of the truth).
//! - `real`: CN03 and H11 (from XYLEM_MOKUME_DIR or ../shared/data/mokume): iso-contour loss
//!   (cube units) and error (mm) after step 1 and step 2, seconds per stage.
//! - `lofo`: leave-one-face-out on CN03 and H11: fit on five faces, then on the held-out
//!   face the correlation of the predicted ring image with its ARL image (Pearson, best over
//!   shifts of up to 3 px) and the iso-contour error (mm) of its contours, under the step-1
//!   field (G = r around the step-1 pith, with the final ring positions) and the final field.

#[path = "common/fit_bench.rs"]
mod fit_bench;

use std::path::Path;
use std::time::Instant;

use fit_bench::{mean, mokume_dir, table_header};
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField, PithAxis, RingImage};
use xylem::fit::metrics::{
    axis_errors, iso_error_mm, shifted_correlation, truth_ring_correlations,
};
use xylem::fit::run::contour_set;
use xylem::fit::{FitConfig, FitResult, fit_sample, write_synthetic_sample};
use xylem::frame::Face;
use xylem::sample::{Needs, Sample};
use xylem::slice::slice_face;
use xylem::texture::SolidTexture;

const SIZE: usize = 256;
/// Pixels of shift forgiven by the leave-one-face-out ring-image correlation.
const SHIFT: usize = 3;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map(String::as_str).unwrap_or("synthetic");
    let cfg = match args.get(1) {
        Some(path) => FitConfig::load(Path::new(path)).expect("fit config"),
        None => FitConfig::default(),
    };
    match mode {
        "synthetic" => synthetic(&cfg),
        "samples" => samples(&cfg),
        "real" => real(&cfg),
        "lofo" => lofo(&cfg),
        other => panic!("unknown mode {other:?}; expected synthetic, real or lofo"),
    }
}

fn no_progress() -> impl FnMut(&str, usize, usize) {
    |_, _, _| {}
}

fn fit(sample: &Sample, cfg: &FitConfig) -> (FitResult, f64) {
    let t = Instant::now();
    let result = fit_sample(sample, cfg, &mut no_progress()).expect("fit");
    (result, t.elapsed().as_secs_f64())
}

fn load(dir: &Path, faces: &[Face]) -> Sample {
    let needs = Needs {
        photos: true,
        arl: true,
    };
    Sample::load(dir, faces, needs).expect("sample")
}

/// Synthetic truths: name and field TOML.
const CASES: &[(&str, &str)] = &[
    (
        "near (pith 1.2 cm outside face F)",
        "[pith]\norigin = [0.1, 0.0, -0.8]\ndirection = [0.03, 1.0, -0.05]\n[growth]\nyears_per_unit = 12.0\n",
    ),
    (
        "far (24 cm, near-parallel rings)",
        include_str!("../configs/fields/far.toml"),
    ),
    (
        "tilted (35 degrees, 8 cm)",
        "[pith]\norigin = [-1.6, 0.0, -1.2]\ndirection = [0.55, 1.0, 0.3]\n[growth]\nyears_per_unit = 10.0\n",
    ),
    (
        "mildly distorted (8 cm, rate grid amplitude 0.1)",
        "[pith]\norigin = [0.35, 0.0, -2.0]\ndirection = [0.12, 1.0, 0.2]\n[growth]\n\
         years_per_unit = 11.0\n[growth.distortion]\nseed = 7\namplitude = 0.1\n\
         azimuthal_waves = 4\nradial_waves = 3\n",
    ),
    (
        "distorted preset (8 cm, amplitude 0.25)",
        include_str!("../configs/fields/distorted.toml"),
    ),
    (
        "knotted (alive knot)",
        include_str!("../configs/fields/knot_alive.toml"),
    ),
];

fn cases_header() {
    table_header(
        "case | pith distance error (cm) | direction error (deg) | iso error step 1 (mm) | iso error step 2 (mm) | iso error of truth (mm) | faces corr. | cut1 corr. | cut2 corr. | time (s)",
    );
}

fn synthetic(cfg: &FitConfig) {
    let root = std::env::temp_dir().join(format!("xylem-bench-fit-{}", std::process::id()));
    cases_header();
    for (k, (name, text)) in CASES.iter().enumerate() {
        let truth_cfg = FieldConfig::parse(text, Path::new(name)).expect("case config");
        let dir = root.join(format!("case{k}"));
        write_synthetic_sample(&dir, &truth_cfg, SIZE).expect("synthetic sample");
        report_case(name, &truth_cfg, &dir, cfg);
    }
    let _ = std::fs::remove_dir_all(&root);
}

fn samples(cfg: &FitConfig) {
    let root = std::env::temp_dir().join(format!("xylem-bench-fit-samples-{}", std::process::id()));
    cases_header();
    for species in ["chestnut", "softwood", "oak"] {
        let dir = root.join(species);
        let wood = xylem::presets::load_species_preset(species).expect("species preset");
        let out = xylem::io::OutputDir::prepare(&dir).expect("sample folder");
        xylem::procedural::write_sample(&wood, species, SIZE, &out).expect("xylem sample");
        let truth_cfg = FieldConfig::load(&dir.join("truth/field.toml")).expect("truth field");
        report_case(
            &format!("xylem sample --preset {species}"),
            &truth_cfg,
            &dir,
            cfg,
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// Fits the sample in `dir` and prints one table row against its true field.
fn report_case(name: &str, truth_cfg: &FieldConfig, dir: &Path, cfg: &FitConfig) {
    {
        let sample = load(dir, &Face::ALL);
        let (result, secs) = fit(&sample, cfg);
        let truth = GrowthField::from_config(truth_cfg);
        let fitted = GrowthField::from_config(&result.field);
        let (dist, angle) = axis_errors(&result.step1_pith, &truth.pith);
        let set = contour_set(&sample, &Face::ALL, cfg);
        let truth_iso = iso_error_mm(&truth, &set);
        let [faces, cut1, cut2] = truth_ring_correlations(&fitted, &truth, SIZE);
        println!(
            "| {name} | {dist:.2} | {angle:.2} | {:.3} | {:.3} | {truth_iso:.3} | {faces:.2} | {:.2} | {:.2} | {secs:.1} |",
            result.iso_mm_step1, result.iso_mm_step2, cut1, cut2,
        );
    }
}

fn real(cfg: &FitConfig) {
    table_header(
        "sample | contours (points) | iso loss step 1 (cube units) | iso loss step 2 | iso error step 1 (mm) | iso error step 2 (mm) | contours / pith / distortion / colour (s) | total (s)",
    );
    for name in ["CN03", "H11"] {
        let sample = load(&mokume_dir().join(name), &Face::ALL);
        let (r, secs) = fit(&sample, cfg);
        let s = r.seconds;
        println!(
            "| {name} | {} ({}) | {:.4} | {:.4} | {:.3} | {:.3} | {:.1} / {:.1} / {:.1} / {:.1} | {secs:.1} |",
            r.contours,
            r.contour_points,
            r.iso_step1,
            r.iso_step2,
            r.iso_mm_step1,
            r.iso_mm_step2,
            s[0],
            s[1],
            s[2],
            s[3]
        );
    }
}

fn lofo(cfg: &FitConfig) {
    table_header(
        "sample | held-out face | ARL corr. step 1 | ARL corr. final | held-out iso error step 1 (mm) | held-out iso error final (mm) | time (s)",
    );
    for name in ["CN03", "H11"] {
        let dir = mokume_dir().join(name);
        let full = load(&dir, &Face::ALL);
        let (mut c1, mut c2, mut e1, mut e2) = (vec![], vec![], vec![], vec![]);
        for held in Face::ALL {
            let faces: Vec<Face> = Face::ALL.into_iter().filter(|&f| f != held).collect();
            let sample = load(&dir, &faces);
            let (r, secs) = fit(&sample, cfg);
            let fitted = GrowthField::from_config(&r.field);
            let step1 = step1_rings(&r);
            let target = full.ring_image(held).expect("held-out ARL");
            let corr = |t: &dyn SolidTexture| {
                let predicted = slice_face(t, held, target.width);
                shifted_correlation(&predicted, target, cfg.contours.border, SHIFT)
            };
            let held_set = contour_set(&full, &[held], cfg);
            let step1_field = Step1Field(r.step1_pith);
            let row = (
                corr(&step1),
                corr(&RingImage(&fitted)),
                iso_error_mm(&step1_field, &held_set),
                iso_error_mm(&fitted, &held_set),
            );
            println!(
                "| {name} | {held} | {:.2} | {:.2} | {:.3} | {:.3} | {secs:.1} |",
                row.0, row.1, row.2, row.3
            );
            c1.push(row.0);
            c2.push(row.1);
            e1.push(row.2);
            e2.push(row.3);
        }
        println!(
            "| {name} | mean | {:.2} | {:.2} | {:.3} | {:.3} | |",
            mean(c1),
            mean(c2),
            mean(e1),
            mean(e2)
        );
    }
}

/// The rings of the step-1 field: G = r around the step-1 pith, with the final field's
/// years per unit and ring positions (so that only the distortions differ).
fn step1_rings(r: &FitResult) -> RingImage<GrowthField> {
    let mut cfg = r.field.clone();
    cfg.pith.origin = r.step1_pith.origin.into();
    cfg.pith.direction = r.step1_pith.dir.into();
    cfg.growth.rates = None;
    cfg.knots.clear();
    RingImage(GrowthField::from_config(&cfg))
}

/// G = r around the step-1 pith.
struct Step1Field(PithAxis);

impl SolidTexture for Step1Field {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: glam::Vec3, out: &mut [f32]) {
        out[0] = self.0.radius(p);
    }
}
