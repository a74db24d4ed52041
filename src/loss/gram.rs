//! Gram matrices: the uncentred second moments of a feature layer, `G = F F^T / N`. Dividing
//! by the pixel count N makes G independent of the image size, so a 32 px patch and a 256 px
//! face are compared directly (the classic Gatys et al. statistic, here on fixed filters).

use burn::tensor::Tensor;

/// `[F, N]` features -> `[F, F]` Gram matrix.
pub fn gram(features: Tensor<2>) -> Tensor<2> {
    let n = features.dims()[1] as f32;
    features.clone().matmul(features.transpose()).div_scalar(n)
}
