//! The guided local loss: a generated patch of a face against the photo's own pixels around
//! the same place, with the ring phase as a guide (Heitz et al. 2021 append such "tags" to
//! the features of a non-stationary texture).
//!
//! Why not the whole face's statistics ([`super::style::StyleLoss`]): a 32 px patch of a
//! face covers one or two rings; compared with the whole face it is asked for the face's
//! average pore density wherever it lies, and a texture that spreads pores evenly (speckle)
//! matches that best. Here each patch is compared with the photo's window around it (the
//! patch grown by `margin`), and every feature vector carries two more channels, the ring
//! phase (cos, sin of 2 pi G) of its pixel. The sliced Wasserstein distance of the joint
//! distribution (features, phase) is zero only when the features *at each phase* match:
//! pores where the photo has earlywood, none in the latewood.
//!
//! ```text
//! patch [3, h, w] ──> pyramid ─> filters ─> features [F, N_l] ─┐
//! guide [G, h, w] ──> pyramid ─> valid crop ─> guides [G, N_l] ─┴> random directions [P, F + G]
//! photo window [3, h + 2m, w + 2m] (and its guide window) ─> the same ─> sorted, resampled
//! ```
//!
//! Generated and target guides come from the same guide image (the phase on the face), so
//! the patch's guides are exactly its pixels' phases. The colour term compares the pixel
//! colours of the patch and the window along the style loss's six fixed colour axes
//! (R, G, B, luminance, two opponent axes), each relative to the window's spread along that
//! axis. A first version used random directions over (RGB, guides) there; on the demo
//! sample it let pink and green speckle through (swd_chroma 0.021 vs the base colour's
//! 0.005): random directions in RGB are mostly lightness, and the opponent axes are what
//! holds the chroma; measured against the lightness variance, chroma errors still cost
//! little, hence one scale per axis.

use std::collections::HashMap;

use burn::tensor::{Device, Tensor};

use super::colour::{LUMINANCE_AXIS, colour_axes};
use super::config::LossConfig;
use super::distance::{SCALE_EPS, relative_mse};
use super::features::FeatureExtractor;
use super::fine_energy::{fine_distance, fine_energies, log_energies};
use super::guided_config::{GuidedConfig, ProfileAxes};
use super::image_tensor::{image_to_tensor, planar_tensor, tensor_values};
use super::pyramid::pyramid;
use super::ring_profile::{ProfileTarget, phase_bins};
use super::sliced_wasserstein::{random_projections, resample_sorted};
use crate::error::{Result, XylemError};
use crate::image2::Image2;

/// The variance of cos and sin over a whole ring period: guides are scaled against it.
const GUIDE_VARIANCE: f32 = 0.5;

/// The loss with its fixed filters.
#[derive(Clone, Debug)]
pub struct GuidedLoss {
    style: LossConfig,
    guided: GuidedConfig,
    device: Device,
    features: FeatureExtractor,
    /// The colour axes `[A, 3]` of the colour term (A = 6, or 10 with `joint_colour`).
    colour_axes: Tensor<2>,
}

/// A target face: its photo `[3, H, W]` and guide channels `[G, H, W]` (plain device).
#[derive(Clone, Debug)]
pub struct GuidedTarget {
    image: Tensor<3>,
    guide: Tensor<3>,
}

/// A generated patch, the target it belongs to and its place there (top-left pixel).
#[derive(Clone, Debug)]
pub struct GuidedPatch {
    /// `[3, h, w]`, plain or autodiff device.
    pub image: Tensor<3>,
    pub target: usize,
    pub origin: [usize; 2],
    /// The patch's own guide channels `[G, h, w]`, for a patch that does not lie on its
    /// target (a plane parallel to it); `None`: the target's guides at `origin`.
    pub guide: Option<Tensor<3>>,
}

/// The loss of one call: total and its terms, each averaged over patches.
#[derive(Clone, Debug)]
pub struct GuidedTerms {
    pub swd: Tensor<1>,
    pub colour: Tensor<1>,
    /// The pixel-scale energy term (0 unless `[loss.guided] fine_weight` > 0).
    pub fine: Tensor<1>,
    /// The ring-profile term (0 unless `[loss.guided] profile_weight` > 0).
    pub profile: Tensor<1>,
    /// `swd weight x swd + colour weight x colour + fine_weight x fine + profile_weight x
    /// profile`, `[1]`.
    pub total: Tensor<1>,
}

/// The window of a `len`-pixel patch at `start` grown by `margin`, clipped to `0..side`.
fn window(start: usize, len: usize, side: usize, margin: usize) -> (usize, usize) {
    let lo = start.saturating_sub(margin);
    let hi = (start + len + margin).min(side);
    (lo, hi - lo)
}

/// Variance of each row of `[R, N]`.
fn axis_variances(x: &Tensor<2>) -> Vec<f32> {
    let centred = x.clone() - x.clone().mean_dim(1);
    let v = centred.square().mean_dim(1); // [R, 1]
    tensor_values(v).unwrap_or_default()
}

/// Mean variance of the rows of `[F, N]` (trace of the covariance / F), as a number.
fn mean_variance(x: &Tensor<2>) -> f32 {
    let centred = x.clone() - x.clone().mean_dim(1);
    centred.square().mean().into_scalar::<f32>()
}

fn crop(t: &Tensor<3>, rows: (usize, usize), cols: (usize, usize)) -> Tensor<3> {
    t.clone()
        .narrow(1, rows.0, rows.1)
        .narrow(2, cols.0, cols.1)
}

/// `[C, H, W]` -> `[C, H W]`.
fn flat(t: Tensor<3>) -> Tensor<2> {
    let [c, h, w] = t.dims();
    t.reshape([c, h * w])
}

/// A window's statistics for one call, shared by the patches over it.
struct WindowStats {
    /// Per feature layer (`None` where the patch or window has none).
    layers: Vec<Option<LayerStats>>,
    colour: ColourStats,
    /// The window's pixel-scale log energies `[3]`, when the fine term is on.
    fine: Option<Tensor<1>>,
    /// The window's mean colour per ring phase, when the profile term is on.
    profile: Option<ProfileTarget>,
}

struct LayerStats {
    /// The call's directions, split: on the features `[P, F]`, on the scaled guides `[P, G]`.
    on_values: Tensor<2>,
    on_guides: Tensor<2>,
    /// The window's sorted projections `[P, M]`.
    sorted: Tensor<2>,
    /// The window's feature variance (trace of the covariance / F).
    variance: f32,
}

impl LayerStats {
    /// Sliced Wasserstein distance of a patch's joint (features `[F, N]`, guides `[G, N]`)
    /// to the window's, relative to the window's feature variance.
    fn distance(&self, values: Tensor<2>, guides: Tensor<2>) -> Tensor<1> {
        let n = values.dims()[1];
        let generated =
            (self.on_values.clone().matmul(values) + self.on_guides.clone().matmul(guides)).sort(1); // [P, N]
        relative_mse(
            generated,
            resample_sorted(self.sorted.clone(), n),
            self.variance,
        )
    }
}

struct ColourStats {
    /// The window's sorted, scaled colour projections `[A, M]`.
    sorted: Tensor<2>,
    /// Per-axis scale `[A, 1]`.
    scale: Tensor<2>,
}

impl ColourStats {
    /// Mean squared difference of a patch's sorted, scaled colours `[3, N]` to the window's.
    fn distance(&self, pixels: Tensor<2>, axes: &Tensor<2>) -> Tensor<1> {
        let n = pixels.dims()[1];
        let generated = axes.clone().matmul(pixels).sort(1) * self.scale.clone(); // [A, N]
        relative_mse(generated, resample_sorted(self.sorted.clone(), n), 1.0)
    }
}

impl GuidedLoss {
    /// A loss instance; filters from `style` on `device`'s plain version.
    pub fn new(style: &LossConfig, guided: &GuidedConfig, device: &Device) -> Self {
        let device = device.clone().without_autodiff();
        Self {
            features: FeatureExtractor::new(style, &device),
            colour_axes: colour_axes(&device, style.joint_colour),
            style: style.clone(),
            guided: guided.clone(),
            device,
        }
    }

    /// Whether an `h` x `w` patch has at least one feature layer.
    pub(crate) fn usable(&self, h: usize, w: usize) -> bool {
        self.features.layer_shape(h, w, 0).is_some()
    }

    /// A target from a photo (RGB) and its guide image (any number of channels, same size).
    pub fn target(&self, image: &Image2, guide: &Image2) -> Result<GuidedTarget> {
        if (image.width, image.height) != (guide.width, guide.height) {
            return Err(XylemError::input(
                "guided loss target",
                format!(
                    "photo is {}x{} but its guide is {}x{}; expected the same size",
                    image.width, image.height, guide.width, guide.height
                ),
            ));
        }
        Ok(GuidedTarget {
            image: image_to_tensor(image, &self.device),
            guide: planar_tensor(guide, &self.device),
        })
    }

    /// The loss of `patches` at call `call` (the random directions are drawn from the seed
    /// and the call, so the same call gives the same value). Patches over the same place
    /// of the same target (a face and the planes parallel to it) share the window's
    /// statistics, computed once.
    pub fn terms(
        &self,
        patches: &[GuidedPatch],
        targets: &[GuidedTarget],
        call: u64,
    ) -> Result<GuidedTerms> {
        let mut swd = Vec::with_capacity(patches.len());
        let mut colour = Vec::with_capacity(patches.len());
        let mut fine = Vec::with_capacity(patches.len());
        let mut profile = Vec::with_capacity(patches.len());
        let mut windows: HashMap<(usize, [usize; 2], [usize; 2]), WindowStats> = HashMap::new();
        for (i, p) in patches.iter().enumerate() {
            let target = targets.get(p.target).ok_or_else(|| {
                XylemError::input(
                    format!("guided loss patch {i}"),
                    format!("target {} of {}", p.target, targets.len()),
                )
            })?;
            let [_, h, w] = p.image.dims();
            self.check_patch(p, target, i)?;
            let stats = windows
                .entry((p.target, p.origin, [h, w]))
                .or_insert_with(|| self.window_stats(target, p.origin, [h, w], call));
            let [s, c, e, r] = self.patch_terms(p, target, stats);
            swd.push(s);
            colour.push(c);
            fine.push(e);
            profile.push(r);
        }
        let mean = |v: Vec<Tensor<1>>| {
            let n = v.len().max(1) as f32;
            v.into_iter()
                .reduce(|a, b| a + b)
                .map(|s| s.div_scalar(n))
                .unwrap_or_else(|| Tensor::zeros([1], &self.device))
        };
        let (swd, colour) = (mean(swd), mean(colour));
        let (fine, profile) = (mean(fine), mean(profile));
        let w = &self.style.weights;
        let total = swd.clone().mul_scalar(w.swd)
            + colour.clone().mul_scalar(w.colour)
            + fine.clone().mul_scalar(self.guided.fine_weight)
            + profile.clone().mul_scalar(self.guided.profile_weight);
        Ok(GuidedTerms {
            swd,
            colour,
            fine,
            profile,
            total,
        })
    }

    fn check_patch(&self, p: &GuidedPatch, target: &GuidedTarget, index: usize) -> Result<()> {
        let [c, h, w] = p.image.dims();
        let [g, th, tw] = target.guide.dims();
        let [r0, c0] = p.origin;
        if c != 3 || !self.usable(h, w) || r0 + h > th || c0 + w > tw {
            return Err(XylemError::input(
                format!("guided loss patch {index}"),
                format!(
                    "[{c}, {h}, {w}] at ({r0}, {c0}): expected an RGB patch with a feature layer inside its {th}x{tw} target"
                ),
            ));
        }
        if let Some(own) = &p.guide
            && own.dims() != [g, h, w]
        {
            return Err(XylemError::input(
                format!("guided loss patch {index}"),
                format!("guide of shape {:?}; expected [{g}, {h}, {w}]", own.dims()),
            ));
        }
        Ok(())
    }

    /// The statistics of the photo's window around an `[h, w]` patch at `origin`.
    fn window_stats(
        &self,
        target: &GuidedTarget,
        origin: [usize; 2],
        [h, w]: [usize; 2],
        call: u64,
    ) -> WindowStats {
        let [_, th, tw] = target.image.dims();
        let m = self.guided.margin;
        let (rows, cols) = (window(origin[0], h, th, m), window(origin[1], w, tw, m));
        let image = crop(&target.image, rows, cols);
        let guide = crop(&target.guide, rows, cols);
        let guide_window = guide.clone();
        let features = self.features.layers(image.clone());
        let guides = self.guide_layers(guide, rows.1, cols.1);
        let layers = features
            .into_iter()
            .zip(guides)
            .enumerate()
            .map(|(l, (f, g))| Some(self.layer_stats(f?, g?, l, call)))
            .collect();
        let fine =
            (self.guided.fine_weight > 0.0).then(|| log_energies(fine_energies(image.clone())));
        let colour = self.colour_stats(flat(image.clone()));
        let profile = (self.guided.profile_weight > 0.0).then(|| {
            let scaled = self.profile_projection(flat(image), &colour);
            ProfileTarget::new(scaled, &phase_bins(flat(guide_window)))
        });
        WindowStats {
            layers,
            colour,
            fine,
            profile,
        }
    }

    /// Pixels `[3, N]` on the ring-profile term's axes, each scaled by the window's spread
    /// along it: `[A, N]`, or `[1, N]` on luminance alone.
    fn profile_projection(&self, pixels: Tensor<2>, window: &ColourStats) -> Tensor<2> {
        let scaled = self.colour_axes.clone().matmul(pixels) * window.scale.clone();
        match self.guided.profile_axes {
            ProfileAxes::All => scaled,
            ProfileAxes::Lightness => scaled.narrow(0, LUMINANCE_AXIS, 1),
        }
    }

    /// A patch's terms against its window's statistics: swd, colour, fine, profile.
    fn patch_terms(
        &self,
        p: &GuidedPatch,
        target: &GuidedTarget,
        stats: &WindowStats,
    ) -> [Tensor<1>; 4] {
        let [_, h, w] = p.image.dims();
        let [r0, c0] = p.origin;
        let guide = p
            .guide
            .clone()
            .unwrap_or_else(|| crop(&target.guide, (r0, h), (c0, w)));
        let features = self.features.layers(p.image.clone());
        let profile = match &stats.profile {
            Some(target) => {
                let scaled = self.profile_projection(flat(p.image.clone()), &stats.colour);
                target.distance(scaled, &phase_bins(flat(guide.clone())))
            }
            None => Tensor::zeros([1], &self.device),
        };
        let guides = self.guide_layers(guide, h, w);
        let mut layers = Vec::new();
        for ((f, g), t) in features.into_iter().zip(guides).zip(&stats.layers) {
            if let (Some(f), Some(g), Some(t)) = (f, g, t) {
                layers.push(t.distance(f, g));
            }
        }
        let n = layers.len().max(1) as f32;
        let swd = layers
            .into_iter()
            .reduce(|a, b| a + b)
            .map(|s| s.div_scalar(n))
            .unwrap_or_else(|| Tensor::zeros([1], &self.device));
        let fine = match &stats.fine {
            Some(target) => fine_distance(fine_energies(p.image.clone()), target),
            None => Tensor::zeros([1], &self.device),
        };
        let colour = stats
            .colour
            .distance(flat(p.image.clone()), &self.colour_axes);
        [swd, colour, fine, profile]
    }

    /// The guide channels of each feature layer of an `h` x `w` image: the guide image's own
    /// pyramid, cropped to the valid feature region, `[G, N_l]`.
    fn guide_layers(&self, guide: Tensor<3>, h: usize, w: usize) -> Vec<Option<Tensor<2>>> {
        let g = guide.dims()[0];
        let off = self.features.valid_offset();
        let mut levels = pyramid(guide.reshape([1, g, h, w]), self.style.octaves).into_iter();
        (0..self.style.octaves)
            .map(|l| {
                let level = levels.next()?;
                let (fh, fw) = self.features.layer_shape(h, w, l)?;
                Some(
                    level
                        .narrow(2, off, fh)
                        .narrow(3, off, fw)
                        .reshape([g, fh * fw]),
                )
            })
            .collect()
    }

    /// The window's pixel colours `[3, M]` along the fixed colour axes, sorted and scaled
    /// per axis by the window's own spread along it (floored at a tenth of the axes' mean).
    /// Chroma varies far less than lightness in wood: measured against the lightness
    /// variance, a green or pink cast cost almost nothing (see the module note).
    fn colour_stats(&self, pixels: Tensor<2>) -> ColourStats {
        let projected = self.colour_axes.clone().matmul(pixels); // [A, M], A = 6 or 10 axes
        let variances = axis_variances(&projected);
        let floor = 0.1 * variances.iter().sum::<f32>() / variances.len() as f32;
        let scale: Vec<f32> = variances
            .iter()
            .map(|v| 1.0 / (v.max(floor) + SCALE_EPS).sqrt())
            .collect();
        let scale = Tensor::<2>::from_data(
            burn::tensor::TensorData::new(scale, [variances.len(), 1]),
            &self.device,
        ); // [A, 1]
        ColourStats {
            sorted: projected.sort(1) * scale.clone(),
            scale,
        }
    }

    /// One layer of the window: random directions over (features, guides) drawn from the
    /// seed, the call and the layer, the window's sorted projections on them and its
    /// feature variance. Guides are scaled to `guide_weight` times the features' spread.
    fn layer_stats(
        &self,
        values: Tensor<2>,
        guides: Tensor<2>,
        layer: usize,
        call: u64,
    ) -> LayerStats {
        let f = values.dims()[0];
        let g = guides.dims()[0];
        let variance = mean_variance(&values);
        let scale = self.guided.guide_weight * (variance / GUIDE_VARIANCE).sqrt();
        let directions = random_projections(
            self.style.seed,
            (call << 8) | layer as u64,
            self.style.swd.projections,
            f + g,
            &self.device,
        ); // [P, F + G]
        let on_values = directions.clone().narrow(1, 0, f); // [P, F]
        let on_guides = directions.narrow(1, f, g).mul_scalar(scale); // [P, G]
        let sorted = (on_values.clone().matmul(values) + on_guides.clone().matmul(guides)).sort(1); // [P, M]
        LayerStats {
            on_values,
            on_guides,
            sorted,
            variance,
        }
    }
}
