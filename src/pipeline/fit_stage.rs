//! The fit stage: a growth field and base colour fitted to a sample folder's faces, written
//! with its sheet into one folder (`xylem fit`, and `fit/` of a run).

use std::path::Path;

use glam::Vec3;

use super::procedural_step::fit_and_write_procedural;
use super::reporter::Reporter;
use crate::Result;
use crate::fit::fibre_direction::{
    AGREEMENT_DEG, FibreChoice, FibreMeasure, MAX_EIGEN_RATIO, MIN_EVIDENCE,
};
use crate::fit::grain_shading_fit::{MIN_T, ShadingEstimate};
use crate::fit::run::total_steps;
use crate::fit::{Display, FitConfig, FitResult, fit_sample, write_fit};
use crate::frame::Face;
use crate::io::OutputDir;
use crate::rings::{RingSource, load_with_rings};
use crate::sample::{Needs, Sample};

/// What to fit.
#[derive(Clone, Debug)]
pub struct FitOptions<'a> {
    /// The sample folder (Mokume layout).
    pub sample: &'a Path,
    /// The faces fitted (the others are only shown).
    pub faces: &'a [Face],
    pub config: &'a FitConfig,
    /// Where the ring images come from.
    pub rings: RingSource,
}

/// Fits the sample and writes `fit.toml`, the faces, cuts, sheet, loss and config into
/// `out`, saying which ring images were predicted and what the fit reached.
pub fn fit_into(options: &FitOptions, out: &Path, reporter: &dyn Reporter) -> Result<FitResult> {
    let cfg = options.config;
    let loaded = load_with_rings(options.sample, options.faces, options.rings, &cfg.localiser)?;
    say_predicted(&loaded.predicted, reporter);
    let sample = loaded.sample;
    let dir = OutputDir::prepare(out)?;

    let bar = reporter.counter("fit", total_steps(cfg) as u64);
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
    let result = fit_sample(&sample, cfg, &mut report)
        .map_err(|e| e.during(format!("fitting {}", options.sample.display())))?;
    bar.finish();

    let source = options.sample.display().to_string();
    fit_and_write_procedural(
        &sample,
        &result.field,
        &cfg.procedural,
        &dir,
        &source,
        reporter,
    )?;
    write_fit(
        &dir,
        &result,
        cfg,
        &sample.faces,
        &display_images(&sample),
        sample.size,
        &source,
    )?;
    let seconds = result.seconds.iter().sum::<f64>();
    reporter.say(&format!(
        "iso-contour error: {:.3} mm after step 1 (pith), {:.3} mm after step 2; {} contours; \
         {seconds:.1} s",
        result.iso_mm_step1, result.iso_mm_step2, result.contours,
    ));
    say_fibre(result.fibre.as_ref(), result.field.pith.direction, reporter);
    say_grain(result.grain.as_ref(), reporter);
    reporter.say(&format!("wrote {}/fit.toml and sheet.png", out.display()));
    Ok(result)
}

/// Says which way the fibres run and whether the photos or the pith axis decided it.
fn say_fibre(fibre: Option<&FibreMeasure>, axis: [f32; 3], reporter: &dyn Reporter) {
    let Some(m) = fibre else { return };
    let [x, y, z] = m.direction.to_array();
    let ratio = m.eigen_ratio;
    reporter.say(&match m.choice(Vec3::from(axis)) {
        FibreChoice::Measured(_) => format!(
            "fibre direction measured on the photos: ({x:.3}, {y:.3}, {z:.3}) (eigenvalue \
             ratio {ratio:.3}); the NCA's grain follows it, not the pith axis"
        ),
        FibreChoice::AlongAxis(deg) => format!(
            "the photos' fibres run within {deg:.1} degrees of the pith axis (within \
             {AGREEMENT_DEG}): fibres along the axis"
        ),
        FibreChoice::Undetermined => format!(
            "the photos do not determine the fibre direction (eigenvalue ratio {ratio:.3}, \
             needs < {MAX_EIGEN_RATIO}; evidence {:.2}, needs >= {MIN_EVIDENCE}): fibres along \
             the pith axis",
            m.evidence
        ),
    });
}

/// Says whether the photos show end grain darker or lighter than side grain.
fn say_grain(grain: Option<&ShadingEstimate>, reporter: &dyn Reporter) {
    let Some(est) = grain else {
        reporter.say(
            "grain shading: not estimated (it needs at least two end-grain and two side-grain faces)",
        );
        return;
    };
    let m = &est.model;
    let rgb = |c: [f32; 3]| c.map(|v| (v * 255.0).round() as i32);
    let t = m.t_statistic;
    reporter.say(&if est.is_shown() {
        format!(
            "grain shading: end grain RGB {:?}, side grain {:?} (|t| {:.1} >= {MIN_T}); held-out \
             faces, cuts and renders are seen with it",
            rgb(m.end),
            rgb(m.side),
            t.abs()
        )
    } else {
        format!(
            "grain shading not shown by the photos (|t| {:.1} < {MIN_T}: the faces' mean colours \
             do not separate end from side grain); every surface gets the plain mean colour",
            t.abs()
        )
    });
}

/// Says which faces' ring images the localiser made (none when the folder had them all).
fn say_predicted(faces: &[Face], reporter: &dyn Reporter) {
    if !faces.is_empty() {
        let letters: Vec<String> = faces.iter().map(|f| f.letter().to_string()).collect();
        reporter.say(&format!(
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
