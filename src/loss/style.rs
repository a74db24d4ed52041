//! The style loss the NCA trains with: a generated image (or a patch of one) against the
//! statistics of a whole target face.
//!
//! ```text
//! image [3, h, w] ─> pyramid levels l = 0..octaves ─> filter bank (valid conv) ─> nonlinearity
//!                 ─> layer l: features [F, N_l] ─> Gram / mean / covariance / sorted projections
//! image [3, h, w] ─> pixels [3, h w] ─> sorted along six colour axes (colour term)
//! ```
//!
//! Every statistic is a per-pixel average or a distribution (quantiles), so a 32 px patch is
//! compared with a 256 px face directly. Levels too small in the generated image are
//! skipped, and each term is averaged over the levels both images have. Target statistics are
//! computed once ([`StyleLoss::targets`]) on the plain (no autodiff) device and reused on
//! every call; generated images may live on the autodiff device, where the targets, filters
//! and projections act as constants.

use std::collections::HashMap;

use burn::tensor::{Device, Int, Tensor, TensorData};

use super::colour::{ColourTarget, colour_axes};
use super::config::LossConfig;
use super::distance::{mean_square, relative_mse};
use super::features::FeatureExtractor;
use super::gram::gram;
use super::image_tensor::image_to_tensor;
use super::moments::{mean_and_covariance, mean_variance};
use super::sliced_wasserstein::{
    SortedTarget, random_projections, resample_sorted, sorted_projections,
};
use crate::error::{Result, XylemError};
use crate::image2::Image2;
use crate::rng::Rng;

/// The style loss with its fixed filters and projections.
#[derive(Clone, Debug)]
pub struct StyleLoss {
    cfg: LossConfig,
    /// The device without autodiff: filters, projections and targets live here.
    device: Device,
    features: FeatureExtractor,
    /// The fixed projection directions per layer, `[P, F]` (call 0 when redrawing).
    projections: Vec<Tensor<2>>,
    colour_axes: Tensor<2>,
}

/// Precomputed statistics of target images, in the order given to [`StyleLoss::targets`].
#[derive(Debug)]
pub struct StyleTargets {
    faces: Vec<FaceTarget>,
}

#[derive(Debug)]
struct FaceTarget {
    width: usize,
    height: usize,
    layers: Vec<Option<LayerTarget>>,
    colour: Option<ColourTarget>,
}

#[derive(Debug)]
struct LayerTarget {
    /// The average variance of a random projection of the features, trace(C) / F: the
    /// scale of mean and sliced-Wasserstein differences.
    variance: f32,
    gram: Option<(Tensor<2>, f32)>,
    mean: Option<Tensor<1>>,
    covariance: Option<(Tensor<2>, f32)>,
    swd: Option<SwdTarget>,
}

#[derive(Debug)]
enum SwdTarget {
    /// Sorted projections on the fixed directions.
    Fixed(SortedTarget),
    /// All features `[F, N]`; every call projects a seeded subset of them anew.
    Redraw(Tensor<2>),
}

/// The loss split by term (each averaged over images and, for feature terms, layers; `None`
/// for terms with weight 0) and the weighted total.
#[derive(Clone, Debug)]
pub struct LossTerms {
    pub gram: Option<Tensor<1>>,
    pub mean: Option<Tensor<1>>,
    pub covariance: Option<Tensor<1>>,
    pub swd: Option<Tensor<1>>,
    pub colour: Option<Tensor<1>>,
    /// `sum of weight x term`, `[1]`.
    pub total: Tensor<1>,
}

impl LossTerms {
    /// The unweighted terms as numbers, with their config names (for logs).
    pub fn values(&self) -> Vec<(&'static str, f32)> {
        [
            ("gram", &self.gram),
            ("mean", &self.mean),
            ("covariance", &self.covariance),
            ("swd", &self.swd),
            ("colour", &self.colour),
        ]
        .into_iter()
        .filter_map(|(name, t)| Some((name, t.clone()?.into_scalar::<f32>())))
        .collect()
    }
}

/// Running sums of one image's terms over its layers.
#[derive(Default)]
struct TermSums {
    gram: Vec<Tensor<1>>,
    mean: Vec<Tensor<1>>,
    covariance: Vec<Tensor<1>>,
    swd: Vec<Tensor<1>>,
}

fn average(terms: Vec<Tensor<1>>) -> Option<Tensor<1>> {
    let n = terms.len() as f32;
    terms
        .into_iter()
        .reduce(|a, b| a + b)
        .map(|s| s.div_scalar(n))
}

/// Sub-stream of the projections of `layer` at call `call` (call 0 is the fixed set).
fn projection_stream(layer: usize, call: u64) -> u64 {
    (call << 8) | layer as u64
}

impl StyleLoss {
    /// A loss instance: builds the filter bank and the fixed projections from `cfg.seed` on
    /// `device` (its plain, no-autodiff version; generated images may be on the autodiff one).
    pub fn new(cfg: &LossConfig, device: &Device) -> Self {
        let device = device.clone().without_autodiff();
        let features = FeatureExtractor::new(cfg, &device);
        let projections = (0..features.layer_count())
            .map(|l| {
                random_projections(
                    cfg.seed,
                    projection_stream(l, 0),
                    cfg.swd.projections,
                    features.channels(),
                    &device,
                )
            })
            .collect();
        Self {
            cfg: cfg.clone(),
            colour_axes: colour_axes(&device, cfg.joint_colour),
            device,
            features,
            projections,
        }
    }

    pub fn config(&self) -> &LossConfig {
        &self.cfg
    }

    /// The smallest side a generated image or target may have (the largest kernel).
    pub(crate) fn min_side(&self) -> usize {
        self.cfg
            .filters
            .kernel_sizes
            .iter()
            .copied()
            .max()
            .unwrap_or(1)
    }

    /// Whether an `h` x `w` image can be used (as target or generated).
    pub(crate) fn usable(&self, h: usize, w: usize) -> bool {
        h >= self.min_side() && w >= self.min_side() && self.features.layer_shape(h, w, 0).is_some()
    }

    /// Precomputes the statistics of each target image (RGB, any size the loss can use; e.g.
    /// the white-balanced face photos). Done once; the result is reused by every call.
    pub fn targets(&self, images: &[Image2]) -> Result<StyleTargets> {
        let faces = images
            .iter()
            .enumerate()
            .map(|(i, img)| self.face_target(i, img))
            .collect::<Result<Vec<_>>>()?;
        Ok(StyleTargets { faces })
    }

    fn face_target(&self, index: usize, img: &Image2) -> Result<FaceTarget> {
        if !self.usable(img.height, img.width) {
            return Err(XylemError::input(
                format!("style target {index}"),
                format!(
                    "is {}x{}; the loss needs at least {}x{} pixels and {} valid feature pixels (min_layer_pixels)",
                    img.width,
                    img.height,
                    self.min_side(),
                    self.min_side(),
                    self.cfg.min_layer_pixels
                ),
            ));
        }
        let image = image_to_tensor(img, &self.device);
        let w = &self.cfg.weights;
        let colour = (w.colour > 0.0).then(|| ColourTarget::new(image.clone(), &self.colour_axes));
        let layers = self
            .features
            .layers(image)
            .into_iter()
            .enumerate()
            .map(|(l, f)| f.map(|f| self.layer_target(l, f)))
            .collect();
        Ok(FaceTarget {
            width: img.width,
            height: img.height,
            layers,
            colour,
        })
    }

    fn layer_target(&self, layer: usize, features: Tensor<2>) -> LayerTarget {
        let w = &self.cfg.weights;
        let (mean, cov) = mean_and_covariance(features.clone());
        let variance = mean_variance(&cov);
        let gram = (w.gram > 0.0).then(|| {
            let g = gram(features.clone());
            let scale = mean_square(&g);
            (g, scale)
        });
        let covariance = (w.covariance > 0.0).then(|| {
            let scale = mean_square(&cov);
            (cov, scale)
        });
        let swd = (w.swd > 0.0).then(|| {
            if self.cfg.swd.redraw {
                SwdTarget::Redraw(features)
            } else {
                SwdTarget::Fixed(SortedTarget::new(sorted_projections(
                    features,
                    self.projections[layer].clone(),
                )))
            }
        });
        LayerTarget {
            variance,
            gram,
            mean: (w.mean > 0.0).then_some(mean),
            covariance,
            swd,
        }
    }

    /// At most `swd.max_target_pixels` columns of `[F, N]`, a random subset seeded by the
    /// seed, the call and the layer (a new subset every call, so over calls every target
    /// pixel counts).
    fn pixel_subset(&self, layer: usize, call: u64, features: Tensor<2>) -> Tensor<2> {
        let n = features.dims()[1];
        let keep = self.cfg.swd.max_target_pixels;
        if n <= keep {
            return features;
        }
        let mut rng = Rng::substream(self.cfg.seed, 0x5355_4253 ^ projection_stream(layer, call));
        let mut index: Vec<i64> = (0..n as i64).collect();
        for i in 0..keep {
            let j = i + rng.below(n - i);
            index.swap(i, j);
        }
        index.truncate(keep);
        index.sort_unstable();
        let index = Tensor::<1, Int>::from_data(TensorData::new(index, [keep]), &self.device);
        features.select(1, index)
    }

    /// The loss of `generated` images (each `[3, h, w]`, on the plain or autodiff device)
    /// against `targets`: `generated[i]` is compared with target `pairs[i]`. Returns a `[1]`
    /// tensor, the mean over images. Uses the fixed projections.
    pub fn loss(
        &self,
        generated: &[Tensor<3>],
        targets: &StyleTargets,
        pairs: &[usize],
    ) -> Result<Tensor<1>> {
        Ok(self.terms(generated, targets, pairs, 0)?.total)
    }

    /// As [`StyleLoss::loss`] at call number `call`: with `swd.redraw` the projections are
    /// drawn from the seed and `call` (same call, same projections); without, `call` is
    /// ignored.
    pub fn loss_at(
        &self,
        generated: &[Tensor<3>],
        targets: &StyleTargets,
        pairs: &[usize],
        call: u64,
    ) -> Result<Tensor<1>> {
        Ok(self.terms(generated, targets, pairs, call)?.total)
    }

    /// The loss split by term (see [`LossTerms`]).
    pub fn terms(
        &self,
        generated: &[Tensor<3>],
        targets: &StyleTargets,
        pairs: &[usize],
        call: u64,
    ) -> Result<LossTerms> {
        self.check_inputs(generated, targets, pairs)?;
        let call = if self.cfg.swd.redraw { call } else { 0 };
        let draw = self.draw(targets, pairs, call);
        let mut per_image = Vec::with_capacity(generated.len());
        for (image, &pair) in generated.iter().zip(pairs) {
            per_image.push(self.image_terms(image.clone(), &targets.faces[pair], &draw, pair));
        }
        let take = |f: fn(&ImageTerms) -> Option<Tensor<1>>| {
            let parts: Vec<Tensor<1>> = per_image.iter().filter_map(f).collect();
            (!parts.is_empty()).then(|| {
                let n = per_image.len() as f32;
                parts
                    .into_iter()
                    .reduce(|a, b| a + b)
                    .map(|s| s.div_scalar(n))
            })?
        };
        let w = &self.cfg.weights;
        let gram = take(|t| t.gram.clone()).filter(|_| w.gram > 0.0);
        let mean = take(|t| t.mean.clone()).filter(|_| w.mean > 0.0);
        let covariance = take(|t| t.covariance.clone()).filter(|_| w.covariance > 0.0);
        let swd = take(|t| t.swd.clone()).filter(|_| w.swd > 0.0);
        let colour = take(|t| t.colour.clone()).filter(|_| w.colour > 0.0);
        let total = [
            (&gram, w.gram),
            (&mean, w.mean),
            (&covariance, w.covariance),
            (&swd, w.swd),
            (&colour, w.colour),
        ]
        .into_iter()
        .filter_map(|(t, weight)| Some(t.clone()?.mul_scalar(weight)))
        .reduce(|a, b| a + b)
        .unwrap_or_else(|| Tensor::zeros([1], &generated[0].device()));
        Ok(LossTerms {
            gram,
            mean,
            covariance,
            swd,
            colour,
            total,
        })
    }

    fn check_inputs(
        &self,
        generated: &[Tensor<3>],
        targets: &StyleTargets,
        pairs: &[usize],
    ) -> Result<()> {
        if generated.is_empty() {
            return Err(XylemError::input("style loss", "no generated images"));
        }
        if pairs.len() != generated.len() {
            return Err(XylemError::input(
                "style loss pairs",
                format!(
                    "{} pairs for {} generated images; expected one target index per image",
                    pairs.len(),
                    generated.len()
                ),
            ));
        }
        for (i, (image, &pair)) in generated.iter().zip(pairs).enumerate() {
            let [c, h, w] = image.dims();
            if c != 3 || !self.usable(h, w) {
                return Err(XylemError::input(
                    format!("generated image {i}"),
                    format!(
                        "has shape [{c}, {h}, {w}]; expected [3, h, w] with h, w >= {} and at least {} valid feature pixels",
                        self.min_side(),
                        self.cfg.min_layer_pixels
                    ),
                ));
            }
            if pair >= targets.faces.len() {
                return Err(XylemError::input(
                    format!("style loss pair {i}"),
                    format!(
                        "= {pair}; expected a target index below {}",
                        targets.faces.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// This call's projections and, when they are redrawn, the targets' sorted projections
    /// on them: once per target used, however many generated images share it.
    fn draw(&self, targets: &StyleTargets, pairs: &[usize], call: u64) -> Draw {
        let projections: Vec<Tensor<2>> = (0..self.features.layer_count())
            .map(|l| {
                if call == 0 {
                    return self.projections[l].clone();
                }
                random_projections(
                    self.cfg.seed,
                    projection_stream(l, call),
                    self.cfg.swd.projections,
                    self.features.channels(),
                    &self.device,
                )
            })
            .collect();
        let mut redrawn = HashMap::new();
        for &pair in pairs {
            redrawn.entry(pair).or_insert_with(|| {
                targets.faces[pair]
                    .layers
                    .iter()
                    .zip(&projections)
                    .enumerate()
                    .map(|(l, (layer, p))| match layer.as_ref()?.swd.as_ref()? {
                        SwdTarget::Redraw(features) => Some(SortedTarget::new(sorted_projections(
                            self.pixel_subset(l, call, features.clone()),
                            p.clone(),
                        ))),
                        SwdTarget::Fixed(_) => None,
                    })
                    .collect()
            });
        }
        Draw {
            projections,
            redrawn,
        }
    }

    fn image_terms(
        &self,
        image: Tensor<3>,
        target: &FaceTarget,
        draw: &Draw,
        pair: usize,
    ) -> ImageTerms {
        let colour = target
            .colour
            .as_ref()
            .map(|c| c.term(image.clone(), &self.colour_axes));
        let mut sums = TermSums::default();
        for (l, generated) in self.features.layers(image).into_iter().enumerate() {
            let (Some(f), Some(Some(t))) = (generated, target.layers.get(l)) else {
                continue;
            };
            let redrawn = draw
                .redrawn
                .get(&pair)
                .and_then(|layers| layers[l].as_ref());
            self.layer_terms(f, t, &draw.projections[l], redrawn, &mut sums);
        }
        ImageTerms {
            gram: average(sums.gram),
            mean: average(sums.mean),
            covariance: average(sums.covariance),
            swd: average(sums.swd),
            colour,
        }
    }

    fn layer_terms(
        &self,
        f: Tensor<2>,
        t: &LayerTarget,
        projections: &Tensor<2>,
        redrawn: Option<&SortedTarget>,
        sums: &mut TermSums,
    ) {
        if let Some((g, scale)) = &t.gram {
            sums.gram
                .push(relative_mse(gram(f.clone()), g.clone(), *scale));
        }
        if t.mean.is_some() || t.covariance.is_some() {
            let (mean, cov) = mean_and_covariance(f.clone());
            if let Some(m) = &t.mean {
                sums.mean.push(relative_mse(mean, m.clone(), t.variance));
            }
            if let Some((c, scale)) = &t.covariance {
                sums.covariance.push(relative_mse(cov, c.clone(), *scale));
            }
        }
        if let Some(swd) = &t.swd {
            let n = f.dims()[1];
            let target = match (swd, redrawn) {
                (SwdTarget::Fixed(sorted), _) | (SwdTarget::Redraw(_), Some(sorted)) => {
                    sorted.at(n)
                }
                // not reached: `draw` sorts every redrawing target that is paired
                (SwdTarget::Redraw(features), None) => {
                    resample_sorted(sorted_projections(features.clone(), projections.clone()), n)
                }
            };
            sums.swd.push(relative_mse(
                sorted_projections(f, projections.clone()),
                target,
                t.variance,
            ));
        }
    }
}

/// The projections of one call (see [`StyleLoss::draw`]).
struct Draw {
    /// Per layer, `[P, F]`.
    projections: Vec<Tensor<2>>,
    /// Per target index, per layer: the target's sorted projections on this call's
    /// directions (redrawing losses only).
    redrawn: HashMap<usize, Vec<Option<SortedTarget>>>,
}

/// One image's terms, each averaged over its layers.
struct ImageTerms {
    gram: Option<Tensor<1>>,
    mean: Option<Tensor<1>>,
    covariance: Option<Tensor<1>>,
    swd: Option<Tensor<1>>,
    colour: Option<Tensor<1>>,
}

impl StyleTargets {
    /// Number of targets.
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// Width and height of target `i`.
    pub fn size(&self, i: usize) -> Option<(usize, usize)> {
        self.faces.get(i).map(|f| (f.width, f.height))
    }
}
