//! The whole fit of one sample: contours, step 1 (pith), step 2 (rates, grey map, knots),
//! ring iso-values, base colour. Returns the fitted field config (what `fit.toml` holds) and
//! the measurements the CLI writes (`loss.csv`) and the benchmarks report.
//!
//! Units: step 1 works in cube units (G = r). Before step 2, `years_per_unit` is set from the
//! ring spacing seen along r (peaks of the ring images binned over r), so that the raw field
//! is close to years and the knot parameters (which are in years) keep their meaning. The
//! final field lists its rings (`growth.rings`), which makes them integer years exactly.

use std::time::Instant;

use glam::Vec3;

use super::colour_fit::fit_base_colour;
use super::config::{FitConfig, RingPeakConfig};
use super::contours::{Contour, ContourSet, face_contours};
use super::distortion::{LossParts, Step2, Step2Data, Step2Params};
use super::fibre_direction::{FibreChoice, FibreMeasure, measure_fibre_direction};
use super::grain_shading_fit::{ShadingEstimate, add_grain_shading, face_content};
use super::grey_map::{self, GRange};
use super::grid_layout::fitted_grid;
use super::iso_loss::iso_loss;
use super::knot_init::MarkedKnot;
use super::metrics::iso_error_mm;
use super::pith_descent::descend;
use super::pith_search::{axes_differ, axis_loss, search};
use super::ring_peaks::{median_spacing, profile_peaks};
use super::white_balance::white_balance;
use crate::config::Checker;
use crate::config::ConfigFile;
use crate::error::{Result, XylemError};
use crate::field::{
    BaseColour, FieldConfig, GrowthConfig, GrowthField, KnotConfig, PithAxis, PithConfig,
    RingsConfig,
};
use crate::frame::Face;
use crate::image2::Image2;
use crate::sample::Sample;

/// Years per cube unit assumed when no ring spacing can be measured (2.5 mm rings).
const FALLBACK_YEARS_PER_UNIT: f32 = 16.0;
/// Samples per side (faces) and per axis (interior) used to find the range of G in the cube.
const RANGE_SAMPLES: usize = 48;

/// One row of `loss.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct LossRow {
    pub stage: &'static str,
    pub iteration: usize,
    pub parts: LossParts,
}

/// Which part of the fit is running, for progress bars: (stage, steps done, steps in stage).
pub type Progress<'a> = &'a mut dyn FnMut(&str, usize, usize);

/// Everything a fit produced.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The fitted field, knots, rings and base colour (`fit.toml`).
    pub field: FieldConfig,
    /// The pith after step 1.
    pub step1_pith: PithAxis,
    /// Iso-contour loss (cube units) of all contours under the step-1 field G = r.
    pub iso_step1: f32,
    /// The same under the final field (years / years_per_unit).
    pub iso_step2: f32,
    /// Iso-contour error as a distance (mm) after step 1 and after step 2.
    pub iso_mm_step1: f32,
    pub iso_mm_step2: f32,
    /// Contour count and points used.
    pub contours: usize,
    pub contour_points: usize,
    /// The fibre direction measured on the photos (stored in the field's `[pith]` when
    /// determined).
    pub fibre: Option<FibreMeasure>,
    /// The grain shading estimated from the faces' mean colours (stored in the base colour's
    /// white balance when the photos show it); `None` when the faces cannot determine it.
    pub grain: Option<ShadingEstimate>,
    pub loss_log: Vec<LossRow>,
    /// Seconds per stage: contours, pith, distortion, colour.
    pub seconds: [f64; 4],
}

/// Steps a fit with `cfg` reports to the progress callback, for sizing a progress bar.
pub(crate) fn total_steps(cfg: &FitConfig) -> usize {
    1 + cfg.pith.refine * (cfg.pith.iterations + 1)
        + cfg.pith.refine * (cfg.distortion.trial_iterations + 1)
        + cfg.distortion.iterations
        + 1
        + cfg.colour.iterations
        + 1
}

/// Fits a growth field and base colour to the used faces of `sample` (which must have its
/// ring images and photos loaded).
pub fn fit_sample(sample: &Sample, cfg: &FitConfig, progress: Progress) -> Result<FitResult> {
    let mut log = Vec::new();
    let mut seconds = [0.0; 4];
    let clock = Instant::now();
    let contours = sample_contours(sample, cfg)?;
    let all = ContourSet::new(&contours, cfg.contours.max_points);
    let marks: Vec<MarkedKnot> = sample
        .knots()
        .iter()
        .filter_map(|m| MarkedKnot::new(m, &sample.photos, &cfg.knots))
        .collect();
    seconds[0] = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    progress("pith search", 0, 1);
    let step1_set = without_knots(&all, &marks, cfg.knots.exclusion);
    let piths = refine_piths(&step1_set, cfg, &mut log, progress);
    seconds[1] = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let (step2, mut field) = fit_distortions(sample, cfg, &all, &marks, &piths, &mut log, progress);
    seconds[2] = clock.elapsed().as_secs_f64();

    let fibre = measure_fibre_direction(&sample.photos, &sample.arl, &sample.faces, step2.pith.dir);
    if let Some(FibreChoice::Measured(d)) = fibre.as_ref().map(|m| m.choice(step2.pith.dir)) {
        field.pith.fibre_direction = Some(d.into());
    }

    let clock = Instant::now();
    let growth = GrowthField::from_config(&field);
    let (colour, grain) = fit_colour(
        sample,
        cfg,
        &growth,
        field.pith.fibre_axis(),
        &mut log,
        progress,
    );
    field.base_colour = Some(colour);
    field.validate(&Checker::new(&sample.dir.join("fit.toml")))?;
    seconds[3] = clock.elapsed().as_secs_f64();
    let pith = step2.pith;
    Ok(FitResult {
        step1_pith: pith,
        iso_step1: axis_loss(&all, &pith),
        iso_step2: final_iso(&growth, &all, step2.years_per_unit),
        iso_mm_step1: iso_error_mm(&PithRadius(pith), &all),
        iso_mm_step2: iso_error_mm(&growth, &all),
        contours: all.len(),
        contour_points: all.points.len(),
        field,
        fibre,
        grain,
        loss_log: log,
        seconds,
    })
}

/// Step 2: the best trial pith, its rates, grey map and knots fitted, and the ring positions.
/// Returns the step-2 problem (its pith and years per unit) and the fitted field config
/// without base colour.
fn fit_distortions(
    sample: &Sample,
    cfg: &FitConfig,
    all: &ContourSet,
    marks: &[MarkedKnot],
    piths: &[PithAxis],
    log: &mut Vec<LossRow>,
    progress: Progress,
) -> (Step2, FieldConfig) {
    let pixels = face_pixels(sample, cfg.contours.border, cfg.distortion.image_stride);
    let trial = best_trial(piths, all, &pixels, marks, cfg, log, progress);
    let iterations = cfg.distortion.iterations;
    let (fitted, _) = trial
        .step2
        .fit(trial.params, iterations, &cfg.knots, |it, parts| {
            log.push(LossRow {
                stage: "distortion",
                iteration: it,
                parts: *parts,
            });
            progress("distortion", it, iterations);
        });
    let mut field = field_config(&trial.step2, &fitted, None);
    field.growth.rings = rings_of(&GrowthField::from_config(&field), sample, cfg);
    (trial.step2, field)
}

/// The base colour of the fitted field on the white-balanced photos, and the grain shading
/// estimated from the photos' means (kept in the white balance when they show it).
fn fit_colour(
    sample: &Sample,
    cfg: &FitConfig,
    growth: &GrowthField,
    fibre_axis: Vec3,
    log: &mut Vec<LossRow>,
    progress: Progress,
) -> (BaseColour, Option<ShadingEstimate>) {
    let wb = white_balance(&sample.photos, &sample.faces);
    let balanced: [Option<Image2>; 6] = std::array::from_fn(|f| {
        sample.photos[f]
            .as_ref()
            .map(|p| p.with_channels(3).balanced(&wb.face_means[f]))
    });
    let iterations = cfg.colour.iterations;
    let mut colour = fit_base_colour(
        growth,
        &balanced,
        &sample.faces,
        g_range(growth),
        wb,
        &cfg.colour,
        |it, loss| {
            log.push(LossRow {
                stage: "colour",
                iteration: it,
                parts: LossParts {
                    total: loss,
                    image: loss,
                    ..Default::default()
                },
            });
            progress("colour", it, iterations);
        },
    );
    // After the bars: they tell how much of each face's mean is the wood it shows.
    let content = face_content(&colour, growth, &sample.faces);
    let grain = add_grain_shading(
        &mut colour.white_balance,
        &sample.faces,
        fibre_axis,
        &content,
    );
    (colour, grain)
}

/// Contours of every used face; an error if there are too few to fit anything.
pub fn sample_contours(sample: &Sample, cfg: &FitConfig) -> Result<Vec<Contour>> {
    let mut contours = Vec::new();
    for &face in &sample.faces {
        let arl = sample.ring_image(face).ok_or_else(|| {
            XylemError::sample(&sample.dir, format!("face {face}: ring image not loaded"))
        })?;
        contours.extend(face_contours(arl, face, &cfg.contours));
    }
    if contours.len() < 2 {
        let faces: Vec<String> = sample.faces.iter().map(|f| f.to_string()).collect();
        return Err(XylemError::sample(
            &sample.dir,
            format!(
                "found {} ring contour(s) on faces {} (pixels >= {:.3} in bands of at least {} \
                 pixels, {} px from the border); the fit needs at least 2. Are the ring \
                 localisation images white rings on black?",
                contours.len(),
                faces.join(","),
                cfg.contours.threshold,
                cfg.contours.min_pixels,
                cfg.contours.border
            ),
        ));
    }
    Ok(contours)
}

/// The contour set of `faces` (those with a ring image loaded), as the iso errors of the
/// benchmarks measure a field against a sample's rings.
pub fn contour_set(sample: &Sample, faces: &[Face], cfg: &FitConfig) -> ContourSet {
    let contours: Vec<Contour> = faces
        .iter()
        .filter_map(|&f| {
            sample
                .ring_image(f)
                .map(|arl| face_contours(arl, f, &cfg.contours))
        })
        .flatten()
        .collect();
    ContourSet::new(&contours, cfg.contours.max_points)
}

/// Contour points away from the marked knots (all points if that leaves fewer than 2
/// contours).
fn without_knots(all: &ContourSet, marks: &[MarkedKnot], exclusion: f32) -> ContourSet {
    if marks.is_empty() || exclusion <= 0.0 {
        return all.clone();
    }
    let kept = all.filter(|p| marks.iter().all(|m| m.distance(p) > exclusion));
    if kept.len() < 2 { all.clone() } else { kept }
}

/// Step 1: coarse search, then descent from the best few candidates. Returns the distinct
/// refined axes, lowest loss first.
fn refine_piths(
    set: &ContourSet,
    cfg: &FitConfig,
    log: &mut Vec<LossRow>,
    progress: Progress,
) -> Vec<PithAxis> {
    let candidates = search(
        &set.thinned(cfg.pith.search_points),
        &cfg.pith,
        cfg.pith.refine,
    );
    let per = cfg.pith.iterations + 1;
    let mut refined: Vec<(PithAxis, f32)> = Vec::new();
    for (k, c) in candidates.iter().enumerate() {
        let (axis, loss) = descend(set, &c.axis, &cfg.pith, |it, loss| {
            log.push(LossRow {
                stage: "pith",
                iteration: k * per + it,
                parts: LossParts {
                    total: loss,
                    iso: loss,
                    ..Default::default()
                },
            });
            progress("pith descent", k * per + it + 1, cfg.pith.refine * per);
        });
        refined.push((axis, loss));
    }
    refined.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut distinct: Vec<PithAxis> = Vec::new();
    for (axis, _) in refined {
        if distinct.iter().all(|d| axes_differ(d, &axis)) {
            distinct.push(axis);
        }
    }
    if distinct.is_empty() {
        distinct.push(PithAxis::new(Vec3::new(0.0, 0.0, -2.0), Vec3::Y));
    }
    distinct
}

/// A step-2 problem around one pith candidate and its parameters so far.
struct Trial {
    step2: Step2,
    params: Step2Params,
}

/// Sets up step 2 around each candidate pith, runs `trial_iterations` of it, and keeps the
/// candidate with the lowest step-2 loss: a wrong pith needs strong, unsmooth distortions to
/// explain the rings, which the undistorted step-1 loss cannot see.
fn best_trial(
    piths: &[PithAxis],
    all: &ContourSet,
    pixels: &FacePixels,
    marks: &[MarkedKnot],
    cfg: &FitConfig,
    log: &mut Vec<LossRow>,
    progress: Progress,
) -> Trial {
    let trials = cfg.distortion.trial_iterations;
    let count = if trials == 0 { 1 } else { piths.len() };
    let mut best: Option<(Trial, f32)> = None;
    for (k, pith) in piths.iter().take(count).enumerate() {
        let trial = start_trial(pith, all, pixels, marks, cfg);
        if count == 1 {
            return trial;
        }
        let (params, parts) = trial
            .step2
            .fit(trial.params, trials, &cfg.knots, |it, parts| {
                log.push(LossRow {
                    stage: "trial",
                    iteration: k * (trials + 1) + it,
                    parts: *parts,
                });
                progress(
                    "pith trials",
                    k * (trials + 1) + it + 1,
                    count * (trials + 1),
                );
            });
        if best.as_ref().is_none_or(|(_, l)| parts.total < *l) {
            let step2 = trial.step2;
            best = Some((Trial { step2, params }, parts.total));
        }
    }
    best.map(|(t, _)| t).expect("at least one pith candidate")
}

/// Step 2 around `pith`: years per unit from the ring spacing, knots from the marks, the grey
/// map from the ring images binned over the starting G.
fn start_trial(
    pith: &PithAxis,
    all: &ContourSet,
    pixels: &FacePixels,
    marks: &[MarkedKnot],
    cfg: &FitConfig,
) -> Trial {
    let ypu = years_per_unit(pith, pixels, cfg);
    let knots: Vec<KnotConfig> = marks.iter().map(|m| m.initial_knot(pith)).collect();
    let anchors = marks.iter().map(MarkedKnot::points).collect();
    let samples = (pixels.points.clone(), pixels.targets.clone());
    let step2 = prepare_step2(pith, ypu, &knots, all.clone(), samples, cfg)
        .with_knot_anchors(anchors, cfg.knots.lambda_anchor);
    let params = Step2Params {
        theta: vec![0.0; step2.layout.rates.len()],
        map: initial_map(&step2, &knots, map_nodes(&step2.range, cfg)),
        knots,
    };
    Trial { step2, params }
}

/// G = r around a fixed axis, as a solid texture (for the step-1 iso error in mm).
struct PithRadius(PithAxis);

impl crate::texture::SolidTexture for PithRadius {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[0] = self.0.radius(p);
    }
}

/// Ring-image samples of the used faces: every `stride`-th pixel away from the border, as
/// 3D points and grey values, face after face.
struct FacePixels {
    points: Vec<Vec3>,
    targets: Vec<f32>,
    /// Samples per face (every face contributes the same number).
    per_face: usize,
}

fn face_pixels(sample: &Sample, border: usize, stride: usize) -> FacePixels {
    let (mut points, mut targets) = (Vec::new(), Vec::new());
    let mut per_face = 0;
    for &face in &sample.faces {
        let Some(arl) = sample.ring_image(face) else {
            continue;
        };
        let n = arl.width;
        let before = points.len();
        for r in (border..n.saturating_sub(border)).step_by(stride) {
            for c in (border..n.saturating_sub(border)).step_by(stride) {
                points.push(face.pixel_point(r, c, n));
                targets.push(arl.get(r, c, 0));
            }
        }
        per_face = points.len() - before;
    }
    FacePixels {
        points,
        targets,
        per_face,
    }
}

/// Years per cube unit from the ring spacing along r: on each face the ring image binned
/// over r around the pith gives a grey profile whose peaks are the rings; the spacing is the
/// median of all faces' gaps between neighbouring peaks. Per face, because the undistorted
/// G = r puts a ring at a slightly different r on each face: pooled into one profile, the
/// faces' peaks interleave and halve the apparent spacing wherever more than one face shows
/// rings at the same r (predicted ring images, which mark rings the U-Net leaves dark, made
/// H11 fit twice its rings that way).
fn years_per_unit(pith: &PithAxis, pixels: &FacePixels, cfg: &FitConfig) -> f32 {
    let radii: Vec<f32> = pixels.points.iter().map(|&p| pith.radius(p)).collect();
    let whole = GRange::of(&radii, 0.0);
    // Only the peaks seen: gaps filled with evenly spaced rings would repeat one face's guess.
    let seen_only = RingPeakConfig {
        gap_factor: f32::INFINITY,
        ..cfg.rings.clone()
    };
    let mut gaps = Vec::new();
    for (r, t) in radii
        .chunks(pixels.per_face.max(1))
        .zip(pixels.targets.chunks(pixels.per_face.max(1)))
    {
        let face = GRange::of(r, 0.0);
        let share = (face.hi - face.lo) / (whole.hi - whole.lo).max(1e-9);
        let bins = (SPACING_BINS as f32 * share).round() as usize;
        let peaks = profile_peaks(r, t, bins.max(8), &seen_only);
        gaps.extend(peaks.windows(2).map(|w| w[1] - w[0]));
    }
    if gaps.is_empty() {
        return FALLBACK_YEARS_PER_UNIT;
    }
    match super::iso_loss::median(&gaps) {
        s if s > 0.0 => 1.0 / s,
        _ => FALLBACK_YEARS_PER_UNIT,
    }
}

fn prepare_step2(
    pith: &PithAxis,
    ypu: f32,
    knots: &[KnotConfig],
    iso: ContourSet,
    (pixels, targets): (Vec<Vec3>, Vec<f32>),
    cfg: &FitConfig,
) -> Step2 {
    let layout = fitted_grid(pith, cfg.distortion.grid, cfg.distortion.min_rate);
    let start = start_field(pith, ypu, knots);
    let g: Vec<f32> = pixels.iter().map(|&p| start.value(p)).collect();
    let range = GRange::of(&g, 0.02);
    Step2::new(
        *pith,
        ypu,
        layout,
        range,
        cfg.distortion.clone(),
        Step2Data {
            iso,
            pixels,
            targets,
        },
    )
}

/// The undistorted field around the step-1 pith with the initial knots.
fn start_field(pith: &PithAxis, ypu: f32, knots: &[KnotConfig]) -> GrowthField {
    GrowthField::from_config(&FieldConfig {
        pith: PithConfig {
            origin: pith.origin.into(),
            direction: pith.dir.into(),
            fibre_direction: None,
        },
        growth: GrowthConfig::uniform(ypu),
        knots: knots.to_vec(),
        base_colour: None,
    })
}

/// Nodes of M over `range` (at least 16, at most 8192).
fn map_nodes(range: &GRange, cfg: &FitConfig) -> usize {
    let nodes = ((range.hi - range.lo) * cfg.distortion.map_nodes_per_year).round();
    (nodes as usize).clamp(16, 8192)
}

/// M's start: the mean ring-image grey over the pixels nearest each node.
fn initial_map(step2: &Step2, knots: &[KnotConfig], nodes: usize) -> Vec<f32> {
    let start = start_field(&step2.pith, step2.years_per_unit, knots);
    let data = step2.data();
    let ts: Vec<f32> = data
        .pixels
        .iter()
        .map(|&p| step2.range.t(start.value(p)))
        .collect();
    grey_map::binned_means(&ts, &data.targets, nodes)
}

/// Bins per year of the fine grey profile whose peaks are the rings (`ring_peaks`).
const RING_BINS_PER_YEAR: f32 = 16.0;
/// Bins (over the whole range of r of all faces) of the grey profiles over r that give the
/// ring spacing before step 2: about 16 per ring of the real cubes, so that the noise of one
/// face's few pixels per bin does not split a ring into several peaks.
const SPACING_BINS: usize = 256;

/// The ring positions (raw stem time) of the fitted field: peaks of the ring images of all
/// face pixels binned by G.
fn rings_of(field: &GrowthField, sample: &Sample, cfg: &FitConfig) -> Option<RingsConfig> {
    let FacePixels {
        points, targets, ..
    } = face_pixels(sample, cfg.contours.border, 1);
    let g: Vec<f32> = points.iter().map(|&p| field.raw_sample(p).g).collect();
    let range = GRange::of(&g, 0.0);
    let bins = ((range.hi - range.lo) * RING_BINS_PER_YEAR).round() as usize;
    let at: Vec<f32> = profile_peaks(&g, &targets, bins.clamp(64, 16_384), &cfg.rings)
        .into_iter()
        .filter(|&g| g > 0.0)
        .collect();
    let spacing = median_spacing(&at).unwrap_or(1.0);
    let first = at.first()?;
    Some(RingsConfig {
        first_year: (first / spacing).round().max(1.0) as u32,
        at,
    })
}

/// The fitted field config (no base colour yet), with the grid layout pinned.
fn field_config(step2: &Step2, fitted: &Step2Params, rings: Option<RingsConfig>) -> FieldConfig {
    let layout = &step2.layout;
    FieldConfig {
        pith: PithConfig {
            origin: step2.pith.origin.into(),
            direction: step2.pith.dir.into(),
            fibre_direction: None,
        },
        growth: GrowthConfig {
            years_per_unit: step2.years_per_unit,
            grid: [layout.n_h, layout.n_a, layout.n_r],
            min_rate: layout.min_rate,
            rates: Some(Step2::rates(&fitted.theta)),
            distortion: None,
            height_range: Some(layout.height_range),
            radius_range: Some(layout.radius_range),
            azimuth_range: layout.azimuth_range,
            rings,
        },
        knots: fitted.knots.clone(),
        base_colour: None,
    }
}

/// The iso-contour loss (cube units) of the final field, measured in raw years.
fn final_iso(field: &GrowthField, set: &ContourSet, ypu: f32) -> f32 {
    let raw: Vec<f32> = set.points.iter().map(|&p| field.raw_sample(p).g).collect();
    iso_loss(set, &raw, None) / ypu
}

/// The range of (warped) G over the cube: faces and an interior grid.
pub fn g_range(field: &GrowthField) -> [f32; 2] {
    let n = RANGE_SAMPLES;
    let mut values = Vec::new();
    for face in Face::ALL {
        for r in 0..n {
            for c in 0..n {
                values.push(field.value(face.pixel_point(r, c, n)));
            }
        }
    }
    let m = n / 3;
    for i in 0..m {
        for j in 0..m {
            for k in 0..m {
                let at = |x: usize| crate::frame::voxel_centre(x, m);
                values.push(field.value(Vec3::new(at(i), at(j), at(k))));
            }
        }
    }
    let range = GRange::of(&values, 0.0);
    if range.hi > range.lo {
        [range.lo, range.hi]
    } else {
        [range.lo, range.lo + 1.0]
    }
}
