//! Inverse procedural (issue 14; Mokume section 5.3.1, a step the authors did not release):
//! the procedural wood model fitted to a sample's photos on its fitted growth field.
//!
//! For every species preset of the config's `[procedural] presets` (by default all but `burl`,
//! a figure rather than a species and 30x slower), on the fitted faces at `search_size`
//! pixels (128 keeps a whole fit of five presets, on parallel tasks, near 22 s on 2 cores):
//! 1. the preset on the fitted field: its pith, rate grid, rings and knots replace the
//!    preset's, so its rings lie where the photos' do;
//! 2. the ring phase offset (`rings.phase_offset`) that best aligns the preset's pore density
//!    over the ring phase with the photos' (circular shift of `PHASE_BINS` bins maximising
//!    the correlation of the two curves; kept at 0 when the best correlation is below
//!    `MIN_PHASE_CORRELATION`, e.g. for photos without visible pores). The Mokume U-Net
//!    draws its ring lines on the earlywood pore band, so on CN03 the photos' pores sit at
//!    phases 0.6-1.0 of the fitted field where the presets put them at 0-0.3;
//! 3. every colour scaled per channel so the mean colour of its faces matches the photos'
//!    (`COLOUR_ROUNDS` fixed-point rounds: scaling clamps and the pores' opacity mixes);
//! 4. pore contrast and occurrence, fibre contrast and pigment noise by a pattern search on
//!    the style loss (`procedural_search`), then the colours matched again, and the knots'
//!    colours alone matched to the photos' inside the knots;
//! 5. the score: the style loss (`xylem compare`'s) averaged over the fitted faces at the
//!    photos' own size.
//!
//! Every render is seen with the fit's grain shading (`field::GrainShaded`), as the sheets
//! show the fitted model: end-grain photos are darker, and an unshaded model would be scored
//! against that difference.
//!
//! The preset with the lowest score wins. Derivative-free and closed-form where possible: each
//! step has one target (phase curve, mean colour, texture statistics) and is deterministic.
//! Not fitted: pore and ray sizes, ray density, ring profile and the colour maps' shape stay
//! the chosen preset's. Without step 4 the style loss picked maple (no visible pores) for
//! chestnut CN03: the presets' pores are darker than any photo's.

use rayon::prelude::*;

use super::config::ProceduralFitConfig;
use super::procedural_search::search;
use crate::error::Result;
use crate::field::{FieldConfig, GrainShaded, GrowthField, WhiteBalance};
use crate::frame::Face;
use crate::image2::Image2;
use crate::metrics::Comparer;
use crate::metrics::phase_density::{PhaseDensity, curve_correlation};
use crate::metrics::report::StyleReference;
use crate::presets::load_species_preset;
use crate::procedural::{ProceduralWood, SpeciesConfig};
use crate::slice::slice_face;
use crate::texture::FirstChannels;

/// Phase bins of the pore-density curves (the offset's resolution is 1 / bins years).
pub const PHASE_BINS: usize = 20;

/// Below this correlation of the shifted curves the phase offset stays 0.
pub const MIN_PHASE_CORRELATION: f32 = 0.3;

/// Rounds of the mean-colour match.
const COLOUR_ROUNDS: usize = 3;

/// Fewest knot pixels on the faces (at the search size) for the knot colours to be matched.
const MIN_KNOT_PIXELS: usize = 64;

/// One preset as fitted, with its score.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub preset: String,
    pub species: SpeciesConfig,
    /// Correlation of its pore-density curve with the photos' after the shift.
    pub phase_correlation: f32,
    /// Mean style loss over the fitted faces (lower is better).
    pub style: f32,
}

/// The fit: the best candidate and every candidate's score.
#[derive(Clone, Debug)]
pub struct ProceduralFit {
    pub best: Candidate,
    pub candidates: Vec<Candidate>,
}

/// The photos of the fitted faces, and the growth field's G on each face at their size.
struct Targets {
    /// The photos at the search size.
    photos: Vec<(Face, Image2)>,
    /// The style statistics of the photos at the search size and as given (the final
    /// score), computed once for the whole search.
    style: Vec<StyleReference>,
    full_style: Vec<StyleReference>,
    /// The photos' own side.
    full_size: usize,
    /// The fit's white balance: renders are seen with its grain shading, as the sheets show
    /// the procedural model.
    white_balance: Option<WhiteBalance>,
    growth: Vec<Image2>,
    curve: Vec<f32>,
    mean: [f32; 3],
    size: usize,
}

/// Fits the procedural model to `photos` (the fitted faces, all of one size) on the fitted
/// field `fit`, trying `cfg.presets`; `progress(done, total)` is called after each preset.
/// `None` when there are no photos or no presets to try.
pub fn fit_procedural(
    photos: &[(Face, &Image2)],
    fit: &FieldConfig,
    cfg: &ProceduralFitConfig,
    comparer: &Comparer,
    mut progress: impl FnMut(usize, usize),
) -> Result<Option<ProceduralFit>> {
    if cfg.presets.is_empty() {
        return Ok(None);
    }
    let Some(targets) = Targets::new(photos, fit, cfg.search_size, comparer)? else {
        return Ok(None);
    };
    let candidates = fit_presets_in_parallel(cfg, fit, &targets, comparer, &mut progress)?;
    let best = candidates
        .iter()
        .min_by(|a, b| a.style.total_cmp(&b.style))
        .cloned()
        .expect("at least one preset");
    Ok(Some(ProceduralFit { best, candidates }))
}

/// Every preset of `cfg` fitted on its own rayon task (each fit is deterministic and
/// independent, and the results come back in the presets' order, so the outcome does not
/// depend on the threads): much of one preset's fit is single-threaded (the style loss),
/// and the five presets of the default overlap on 2 cores. `progress` runs on the calling
/// thread, told by the tasks as each preset finishes; the tasks run on rayon's global pool
/// (from a helper thread, so a caller inside `ThreadPool::install` does not choose theirs).
fn fit_presets_in_parallel(
    cfg: &ProceduralFitConfig,
    fit: &FieldConfig,
    targets: &Targets,
    comparer: &Comparer,
    progress: &mut impl FnMut(usize, usize),
) -> Result<Vec<Candidate>> {
    let total = cfg.presets.len();
    let (done, finished) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        let tasks = scope.spawn(move || {
            cfg.presets
                .par_iter()
                .map_with(done, |done, name| {
                    let candidate = fit_preset(name, fit, targets, cfg.rounds, comparer);
                    // The receiver outlives every task; a failed send only means no progress.
                    let _ = done.send(());
                    candidate
                })
                .collect::<Result<Vec<_>>>()
        });
        // Ends when every task's sender is dropped, i.e. when the tasks are done.
        for (i, ()) in finished.iter().enumerate() {
            progress(i + 1, total);
        }
        tasks
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

impl Targets {
    fn new(
        photos: &[(Face, &Image2)],
        fit: &FieldConfig,
        search_size: usize,
        comparer: &Comparer,
    ) -> Result<Option<Self>> {
        let Some(&(_, first)) = photos.first() else {
            return Ok(None);
        };
        let size = first.width.min(search_size);
        let full_style = photos
            .iter()
            .map(|(_, p)| comparer.style_reference(p))
            .collect::<Result<Vec<_>>>()?;
        let white_balance = fit.base_colour.as_ref().map(|c| c.white_balance.clone());
        let photos: Vec<(Face, Image2)> = photos
            .iter()
            .map(|(f, p)| (*f, p.with_channels(3).resized(size, size)))
            .collect();
        let field = GrowthField::from_config(fit);
        let growth: Vec<Image2> = photos
            .iter()
            .map(|(f, _)| slice_face(&field, *f, size))
            .collect();
        let style = photos
            .iter()
            .map(|(_, p)| comparer.style_reference(p))
            .collect::<Result<Vec<_>>>()?;
        let refs: Vec<&Image2> = photos.iter().map(|(_, p)| p).collect();
        let curve = pore_curve(&refs, &growth)?;
        let mean = mean_colour(&refs);
        Ok(Some(Self {
            photos,
            style,
            full_style,
            full_size: first.width,
            white_balance,
            growth,
            curve,
            mean,
            size,
        }))
    }

    /// The faces of a species config at the search size, seen with the grain shading.
    fn render(&self, species: &SpeciesConfig) -> Vec<Image2> {
        self.render_at(species, self.size)
    }

    fn render_at(&self, species: &SpeciesConfig, size: usize) -> Vec<Image2> {
        let wood = ProceduralWood::new(species);
        let seen = seen_procedural(&wood, self.white_balance.as_ref());
        self.photos
            .iter()
            .map(|(f, _)| slice_face(&seen, *f, size))
            .collect()
    }

    /// Per face, row-major: the pixels inside a knot of the model (membership > 0.5).
    fn knot_masks(&self, species: &SpeciesConfig) -> Vec<Vec<bool>> {
        let wood = ProceduralWood::new(species);
        let n = self.size;
        self.photos
            .iter()
            .map(|(f, _)| {
                (0..n * n)
                    .map(|i| wood.sample(f.pixel_point(i / n, i % n, n)).knot > 0.5)
                    .collect()
            })
            .collect()
    }

    /// Mean style loss of faces rendered at the search size.
    fn search_style(&self, faces: &[Image2], comparer: &Comparer) -> Result<f32> {
        mean_style(&self.style, faces, comparer)
    }

    /// Mean style loss over the faces at the photos' own size (the candidates' score).
    fn full_size_style(&self, species: &SpeciesConfig, comparer: &Comparer) -> Result<f32> {
        let faces = self.render_at(species, self.full_size);
        mean_style(&self.full_style, &faces, comparer)
    }
}

/// A procedural model's colour as the sheets show it: RGB, seen with the fit's grain shading
/// (`None`: plain).
pub(crate) fn seen_procedural<'a>(
    wood: &'a ProceduralWood,
    white_balance: Option<&WhiteBalance>,
) -> GrainShaded<FirstChannels<&'a ProceduralWood>> {
    GrainShaded::new(FirstChannels { inner: wood, n: 3 }, white_balance)
}

/// Mean style loss of `faces` against the prepared photos, face by face.
fn mean_style(references: &[StyleReference], faces: &[Image2], comparer: &Comparer) -> Result<f32> {
    let mut sum = 0.0;
    for (reference, face) in references.iter().zip(faces) {
        sum += comparer.style(reference, face)?;
    }
    Ok(sum / faces.len().max(1) as f32)
}

fn fit_preset(
    name: &str,
    fit: &FieldConfig,
    targets: &Targets,
    rounds: usize,
    comparer: &Comparer,
) -> Result<Candidate> {
    let mut species = load_species_preset(name)?;
    species.pith = fit.pith.clone();
    species.growth = fit.growth.clone();
    species.knots = fit.knots.clone();
    let (offset, phase_correlation) = phase_offset(&targets.render(&species), targets)?;
    species.rings.phase_offset = offset;
    let species = match_colour(species, targets);
    let loss = |s: &SpeciesConfig| targets.search_style(&targets.render(s), comparer);
    let (species, _) = search(species, rounds, loss)?;
    let species = match_colour(species, targets);
    let species = match_knot_colour(species, targets);
    let style = targets.full_size_style(&species, comparer)?;
    Ok(Candidate {
        preset: name.to_string(),
        species,
        phase_correlation,
        style,
    })
}

/// The config with its colours scaled until its faces' mean colour is the photos'.
fn match_colour(mut species: SpeciesConfig, targets: &Targets) -> SpeciesConfig {
    for _ in 0..COLOUR_ROUNDS {
        let faces = targets.render(&species);
        let mean = mean_colour(&faces.iter().collect::<Vec<_>>());
        let factor: [f32; 3] = std::array::from_fn(|c| targets.mean[c] / mean[c].max(1e-3));
        species = species.recoloured(factor);
    }
    species
}

/// The config with its knot colours scaled until the knots' mean colour on the faces is the
/// photos' there (the stem's match leaves a preset's knot palette: on H11 an orange disc where
/// the photo's knot is dark brown). Knot pixels: the model's knot membership above 0.5; with
/// fewer than `MIN_KNOT_PIXELS` of them on the faces the config is returned unchanged.
fn match_knot_colour(mut species: SpeciesConfig, targets: &Targets) -> SpeciesConfig {
    let masks = targets.knot_masks(&species);
    if masks.iter().flatten().filter(|&&m| m).count() < MIN_KNOT_PIXELS {
        return species;
    }
    let refs: Vec<&Image2> = targets.photos.iter().map(|(_, p)| p).collect();
    let want = masked_mean(&refs, &masks);
    for _ in 0..COLOUR_ROUNDS {
        let faces = targets.render(&species);
        let have = masked_mean(&faces.iter().collect::<Vec<_>>(), &masks);
        let factor: [f32; 3] = std::array::from_fn(|c| want[c] / have[c].max(1e-3));
        species = species.recoloured_knots(factor);
    }
    species
}

/// Mean RGB of the pixels where `masks` (one per image, row-major) is set.
fn masked_mean(images: &[&Image2], masks: &[Vec<bool>]) -> [f32; 3] {
    mean_where(images, |image, pixel| masks[image][pixel])
}

/// The phase offset (years, in (-0.5, 0.5]) whose shifted pore curve of `faces` best matches
/// the photos', and that correlation; 0 when it is below `MIN_PHASE_CORRELATION`.
fn phase_offset(faces: &[Image2], targets: &Targets) -> Result<(f32, f32)> {
    let refs: Vec<&Image2> = faces.iter().collect();
    let curve = pore_curve(&refs, &targets.growth)?;
    let n = curve.len();
    // With offset k / n the model's phase at field phase b is b + k: its curve over the
    // field's phase is the offset-0 curve read k bins later.
    let (k, corr) = (0..n)
        .map(|k| {
            let shifted: Vec<f32> = (0..n).map(|b| curve[(b + k) % n]).collect();
            (k, curve_correlation(&shifted, &targets.curve))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("bins");
    // A NaN correlation (a flat curve) keeps the offset at 0 too.
    if corr.is_nan() || corr < MIN_PHASE_CORRELATION {
        return Ok((0.0, corr));
    }
    let k = if k > n / 2 {
        k as f32 - n as f32
    } else {
        k as f32
    };
    Ok((k / n as f32, corr))
}

fn pore_curve(images: &[&Image2], growth: &[Image2]) -> Result<Vec<f32>> {
    let mut density = PhaseDensity::new(PHASE_BINS);
    for (image, g) in images.iter().zip(growth) {
        density.add(image, g)?;
    }
    Ok(density.curve())
}

/// Mean RGB over all pixels of the images (each image weighted by its pixel count).
fn mean_colour(images: &[&Image2]) -> [f32; 3] {
    mean_where(images, |_, _| true)
}

/// Mean RGB of the pixels `keep(image index, pixel index)` selects, summed in f64.
fn mean_where(images: &[&Image2], keep: impl Fn(usize, usize) -> bool) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    let mut count = 0.0f64;
    for (i, img) in images.iter().enumerate() {
        let rgb = img.with_channels(3);
        for (_, px) in rgb
            .data
            .chunks_exact(3)
            .enumerate()
            .filter(|(k, _)| keep(i, *k))
        {
            for c in 0..3 {
                sum[c] += px[c] as f64;
            }
            count += 1.0;
        }
    }
    sum.map(|s| (s / count.max(1.0)) as f32)
}
