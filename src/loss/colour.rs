//! The colour term: the distribution of pixel colours, compared along six fixed axes of RGB
//! (R, G, B, luminance and two opponent axes) by sorting, as in the sliced Wasserstein term.
//! Sorting matches mean, spread and the shape of each histogram at once (a wood face is a
//! light ground with a tail of dark pores and latewood, which mean and variance alone miss).
//! Fixed axes rather than random ones because colour has only three dimensions and these six
//! cover the directions a viewer notices.

use burn::tensor::{Device, Tensor, TensorData};

use super::distance::relative_mse;
use super::filters::LUMA;
use super::moments::{mean_and_covariance, mean_variance};
use super::sliced_wasserstein::{SortedTarget, sorted_projections};

/// The colour axes, `[6, 3]` (`[10, 3]` with `joint`: see `LossConfig::joint_colour`), each
/// of unit length.
pub fn colour_axes(device: &Device, joint: bool) -> Tensor<2> {
    let mut data = six_axes();
    if joint {
        let [luma, rg, yb] = [&data[9..12], &data[12..15], &data[15..18]].map(|a| {
            let v: [f32; 3] = a.try_into().expect("3 components");
            v
        });
        for chroma in [rg, yb] {
            for sign in [1.0f32, -1.0] {
                let v: [f32; 3] = std::array::from_fn(|i| luma[i] + sign * chroma[i]);
                let n = v.iter().map(|x| x * x).sum::<f32>().sqrt();
                data.extend(v.map(|x| x / n));
            }
        }
    }
    let axes = data.len() / 3;
    Tensor::from_data(TensorData::new(data, [axes, 3]), device)
}

/// The row of the luminance axis in [`colour_axes`] (with or without `joint`).
pub(crate) const LUMINANCE_AXIS: usize = 3;

/// R, G, B, luminance and the two opponent axes, row by row.
fn six_axes() -> Vec<f32> {
    let s2 = std::f32::consts::FRAC_1_SQRT_2;
    let s6 = 1.0 / 6f32.sqrt();
    let luma = LUMA;
    let ln = luma.iter().map(|v| v * v).sum::<f32>().sqrt();
    #[rustfmt::skip]
    let data = vec![
        1.0, 0.0, 0.0,
        0.0, 1.0, 0.0,
        0.0, 0.0, 1.0,
        luma[0] / ln, luma[1] / ln, luma[2] / ln,
        s2, -s2, 0.0,
        s6, s6, -2.0 * s6,
    ];
    data
}

/// A target image's colour statistics.
#[derive(Debug)]
pub(crate) struct ColourTarget {
    sorted: SortedTarget,
    scale: f32,
}

/// `[3, H, W]` -> `[3, H * W]`.
fn pixels(image: Tensor<3>) -> Tensor<2> {
    let [c, h, w] = image.dims();
    image.reshape([c, h * w])
}

impl ColourTarget {
    pub(crate) fn new(image: Tensor<3>, axes: &Tensor<2>) -> Self {
        let px = pixels(image);
        let (_, cov) = mean_and_covariance(px.clone());
        Self {
            sorted: SortedTarget::new(sorted_projections(px, axes.clone())),
            scale: mean_variance(&cov),
        }
    }

    /// The colour term of `generated` (`[3, H, W]`) against this target, `[1]`.
    pub(crate) fn term(&self, generated: Tensor<3>, axes: &Tensor<2>) -> Tensor<1> {
        let px = pixels(generated);
        let n = px.dims()[1];
        relative_mse(
            sorted_projections(px, axes.clone()),
            self.sorted.at(n),
            self.scale,
        )
    }
}
