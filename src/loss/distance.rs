//! How a generated statistic is compared with its target: the mean squared difference divided
//! by a scale taken from the target (its own magnitude or variance). Dividing by the target's
//! scale makes every term dimensionless, so one weight means the same for a faint and a
//! contrasted face, for white-balanced and raw images, and across feature layers.

use burn::tensor::Tensor;

/// Added to every scale so a flat target does not divide by zero.
pub(crate) const SCALE_EPS: f32 = 1e-8;

/// `mean((generated - target)^2) / scale` as a `[1]` tensor.
pub(crate) fn relative_mse<const D: usize>(
    generated: Tensor<D>,
    target: Tensor<D>,
    scale: f32,
) -> Tensor<1> {
    (generated - target)
        .square()
        .mean()
        .div_scalar(scale + SCALE_EPS)
}

/// Mean of the squares of a tensor's values, as a number (for target scales).
pub(crate) fn mean_square<const D: usize>(t: &Tensor<D>) -> f32 {
    t.clone().square().mean().into_scalar::<f32>()
}
