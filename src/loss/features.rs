//! Multi-scale features of one image: at every pyramid level, every filter bank is applied
//! without padding (a padded border would put statistics into the features that the wood
//! does not have, and patches are mostly border), cropped to the largest kernel's valid
//! region, passed through the nonlinearity and flattened to one layer `[F, N]`.

use burn::tensor::activation::relu;
use burn::tensor::module::conv2d;
use burn::tensor::ops::ConvOptions;
use burn::tensor::{Device, Tensor};

use super::config::{LossConfig, Nonlinearity};
use super::filters::{FilterBank, filter_banks};
use super::pyramid::{level_side, pyramid};

/// The fixed feature extractor of a loss instance.
#[derive(Clone, Debug)]
pub(crate) struct FeatureExtractor {
    banks: Vec<FilterBank>,
    nonlinearity: Nonlinearity,
    octaves: usize,
    min_layer_pixels: usize,
    max_kernel: usize,
}

impl FeatureExtractor {
    pub(crate) fn new(cfg: &LossConfig, device: &Device) -> Self {
        Self {
            banks: filter_banks(&cfg.filters, cfg.seed, device),
            nonlinearity: cfg.filters.nonlinearity,
            octaves: cfg.octaves,
            min_layer_pixels: cfg.min_layer_pixels,
            max_kernel: cfg.filters.kernel_sizes.iter().copied().max().unwrap_or(1),
        }
    }

    /// Number of layers (pyramid levels) an image can have.
    pub(crate) fn layer_count(&self) -> usize {
        self.octaves
    }

    /// Features per layer.
    pub(crate) fn channels(&self) -> usize {
        self.banks.iter().map(|b| b.weights.dims()[0]).sum()
    }

    /// Side lengths of the valid feature map of level `level` for an `h` x `w` image, if the
    /// level is used (big enough).
    pub(crate) fn layer_shape(&self, h: usize, w: usize, level: usize) -> Option<(usize, usize)> {
        let (lh, lw) = (level_side(h, level), level_side(w, level));
        if lh < self.max_kernel || lw < self.max_kernel {
            return None;
        }
        let (fh, fw) = (lh - self.max_kernel + 1, lw - self.max_kernel + 1);
        (fh * fw >= self.min_layer_pixels).then_some((fh, fw))
    }

    /// Offset of feature pixel (0, 0) in its level: the centre of the largest kernel.
    pub(crate) fn valid_offset(&self) -> usize {
        (self.max_kernel - 1) / 2
    }

    /// Pyramid levels of `image` (`[3, H, W]`), finest first: each `[1, 3, H_l, W_l]`.
    pub(crate) fn levels(&self, image: Tensor<3>) -> Vec<Tensor<4>> {
        let [c, h, w] = image.dims();
        pyramid(image.reshape([1, c, h, w]), self.octaves)
    }

    /// The feature layers of `image` (`[3, H, W]`): entry l is level l's features
    /// `[F, N_l]` (N_l valid pixels), or `None` where the level is too small.
    pub(crate) fn layers(&self, image: Tensor<3>) -> Vec<Option<Tensor<2>>> {
        let [_, h, w] = image.dims();
        let mut levels = self.levels(image).into_iter();
        (0..self.octaves)
            .map(|l| {
                let level = levels.next()?;
                let (fh, fw) = self.layer_shape(h, w, l)?;
                Some(self.layer(level, fh, fw))
            })
            .collect()
    }

    /// One level's features: `[1, 3, H_l, W_l]` -> `[F, fh * fw]`.
    fn layer(&self, level: Tensor<4>, fh: usize, fw: usize) -> Tensor<2> {
        let responses: Vec<Tensor<4>> = self
            .banks
            .iter()
            .map(|bank| {
                let r = conv2d(
                    level.clone(),
                    bank.weights.clone(),
                    None,
                    ConvOptions::new([1, 1], [0, 0], [1, 1], 1),
                ); // [1, F_b, H_l - k + 1, W_l - k + 1]
                let off = (self.max_kernel - bank.size) / 2;
                r.narrow(2, off, fh).narrow(3, off, fw)
            })
            .collect();
        let f = Tensor::cat(responses, 1); // [1, F, fh, fw]
        let f = match self.nonlinearity {
            Nonlinearity::Relu => relu(f),
            Nonlinearity::Abs => f.abs(),
            Nonlinearity::None => f,
        };
        let channels = f.dims()[1];
        f.reshape([channels, fh * fw])
    }
}
