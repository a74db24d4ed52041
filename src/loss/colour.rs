//! The colour term: the distribution of pixel colours and of colour differences between
//! neighbouring pixels, compared along fixed axes of RGB by sorting (as in the sliced
//! Wasserstein term).
//!
//! - Pixel colours along six axes (R, G, B, luminance and two opponent axes): sorting matches
//!   mean, spread and the shape of each histogram at once (a wood face is a light ground with
//!   a tail of dark pores and latewood, which mean and variance alone miss).
//! - Horizontal and vertical neighbour differences along luminance and the two opponent
//!   axes: wood has almost no pixel-to-pixel chroma change, and without this part 2D results
//!   kept green/purple speckle from the initial noise. The filter features are dominated by
//!   lightness structure (a random filter over RGB sees mostly luminance on wood), so they
//!   barely penalise fine chroma noise; this term does, relative to the target's own tiny
//!   chroma differences. It is also what keeps an NCA from adding colour speckle.
//!
//! Fixed axes rather than random ones because colour has only three dimensions and these
//! cover the directions a viewer notices.

use burn::tensor::{Device, Tensor, TensorData};

use super::distance::relative_mse;
use super::moments::{mean_and_covariance, mean_variance};
use super::sliced_wasserstein::{SortedTarget, sorted_projections};

/// Unit luminance and opponent axes of RGB, `[3, 3]` rows: luminance, red-green,
/// yellow-blue.
fn luminance_opponent_rows() -> [f32; 9] {
    let s2 = std::f32::consts::FRAC_1_SQRT_2;
    let s6 = 1.0 / 6f32.sqrt();
    let luma = [0.2126f32, 0.7152, 0.0722];
    let ln = luma.iter().map(|v| v * v).sum::<f32>().sqrt();
    [
        luma[0] / ln,
        luma[1] / ln,
        luma[2] / ln,
        s2,
        -s2,
        0.0,
        s6,
        s6,
        -2.0 * s6,
    ]
}

/// The fixed axes of the colour term.
#[derive(Clone, Debug)]
pub struct ColourAxes {
    /// Pixel colour axes `[6, 3]`: R, G, B, luminance, red-green, yellow-blue.
    pixels: Tensor<2>,
    /// Difference axes `[3, 3]`: luminance, red-green, yellow-blue.
    differences: Tensor<2>,
}

impl ColourAxes {
    pub fn new(device: &Device) -> Self {
        let lo = luminance_opponent_rows();
        let mut pixels = vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        pixels.extend(lo);
        Self {
            pixels: Tensor::from_data(TensorData::new(pixels, [6, 3]), device),
            differences: Tensor::from_data(TensorData::new(lo.to_vec(), [3, 3]), device),
        }
    }
}

/// The interior of `[3, H, W]`, at least `margin` from the border: `[3, H - 2m, W - 2m]`.
/// The margin is the finest features' (half the largest kernel): a pixel there is seen by
/// few filter windows, and when the colour term alone ruled it, optimisation used the border
/// to fit the colour histogram (a frame of odd colours around 2D results).
fn interior(image: Tensor<3>, margin: usize) -> Tensor<3> {
    let [_, h, w] = image.dims();
    image
        .narrow(1, margin, h - 2 * margin)
        .narrow(2, margin, w - 2 * margin)
}

/// `[3, H, W]` -> `[3, H W]`.
fn flat(image: Tensor<3>) -> Tensor<2> {
    let [c, h, w] = image.dims();
    image.reshape([c, h * w])
}

/// Horizontal and vertical neighbour differences of `[3, H, W]`, `[3, 2 (H - 1)(W - 1)]`.
fn differences(image: Tensor<3>) -> Tensor<2> {
    let [_, h, w] = image.dims();
    let dx = image.clone().narrow(2, 1, w - 1) - image.clone().narrow(2, 0, w - 1); // [3, H, W-1]
    let dy = image.clone().narrow(1, 1, h - 1) - image.narrow(1, 0, h - 1); // [3, H-1, W]
    Tensor::cat(
        vec![flat(dx.narrow(1, 0, h - 1)), flat(dy.narrow(2, 0, w - 1))],
        1,
    )
}

/// One sorted distribution with its scale.
#[derive(Debug)]
struct Sorted {
    sorted: SortedTarget,
    scale: f32,
}

impl Sorted {
    fn new(values: Tensor<2>, axes: &Tensor<2>) -> Self {
        let (_, cov) = mean_and_covariance(values.clone());
        Self {
            sorted: SortedTarget::new(sorted_projections(values, axes.clone())),
            scale: mean_variance(&cov),
        }
    }

    fn term(&self, values: Tensor<2>, axes: &Tensor<2>) -> Tensor<1> {
        let n = values.dims()[1];
        relative_mse(
            sorted_projections(values, axes.clone()),
            self.sorted.at(n),
            self.scale,
        )
    }
}

/// A target image's colour statistics.
#[derive(Debug)]
pub struct ColourTarget {
    pixels: Sorted,
    differences: Sorted,
    margin: usize,
}

impl ColourTarget {
    /// Statistics of `image` (`[3, H, W]`, both sides > 2 `margin` + 1) without its `margin`.
    pub fn new(image: Tensor<3>, axes: &ColourAxes, margin: usize) -> Self {
        let inner = interior(image, margin);
        Self {
            pixels: Sorted::new(flat(inner.clone()), &axes.pixels),
            differences: Sorted::new(differences(inner), &axes.differences),
            margin,
        }
    }

    /// The colour term of `generated` (`[3, H, W]`) against this target, `[1]`: the pixel
    /// part plus the difference part.
    pub fn term(&self, generated: Tensor<3>, axes: &ColourAxes) -> Tensor<1> {
        let inner = interior(generated, self.margin);
        self.pixels.term(flat(inner.clone()), &axes.pixels)
            + self.differences.term(differences(inner), &axes.differences)
    }
}
