//! The Gaussian pyramid the features are computed on: level 0 is the image, each next level
//! the previous one blurred with the separable binomial kernel [1, 3, 3, 1] / 8 and taken at
//! every second pixel (no padding, so a level of an h px image has h/2 - 1 px).
//!
//! A first version used 2x2 box averages: the gradient of a box average is the same for the
//! four pixels of a block, and images optimised through it showed 8 px blocks (level 3). The
//! overlapping binomial kernel spreads gradients smoothly and does not alias the pores.

use burn::tensor::module::conv2d;
use burn::tensor::ops::ConvOptions;
use burn::tensor::{Tensor, TensorData};

/// The 1D binomial kernel.
const BINOMIAL: [f32; 4] = [0.125, 0.375, 0.375, 0.125];

/// The 2D kernel for `channels` depthwise groups, `[C, 1, 4, 4]`.
fn kernel(channels: usize, like: &Tensor<4>) -> Tensor<4> {
    let taps: Vec<f32> = (0..channels)
        .flat_map(|_| {
            BINOMIAL
                .iter()
                .flat_map(|a| BINOMIAL.iter().map(move |b| a * b))
        })
        .collect();
    Tensor::from_data(TensorData::new(taps, [channels, 1, 4, 4]), &like.device())
}

/// One level down: `[1, C, H, W]` -> `[1, C, H/2 - 1, W/2 - 1]`.
pub(crate) fn downsample(level: Tensor<4>) -> Tensor<4> {
    let c = level.dims()[1];
    let k = kernel(c, &level).without_autodiff();
    conv2d(level, k, None, ConvOptions::new([2, 2], [0, 0], [1, 1], c))
}

/// Side of level `level` of an image side `side` (0 when the level does not exist).
pub(crate) fn level_side(side: usize, level: usize) -> usize {
    (0..level).fold(side, |s, _| if s < 4 { 0 } else { (s - 4) / 2 + 1 })
}

/// Pyramid levels of `image` (`[1, C, H, W]`), finest first, at most `levels`, stopping
/// before a side would drop below 4.
pub fn pyramid(image: Tensor<4>, levels: usize) -> Vec<Tensor<4>> {
    let mut out = Vec::with_capacity(levels);
    let mut current = image;
    for l in 0..levels {
        if l > 0 {
            let [_, _, h, w] = current.dims();
            if h < 4 || w < 4 {
                break;
            }
            current = downsample(current);
        }
        out.push(current.clone());
    }
    out
}
