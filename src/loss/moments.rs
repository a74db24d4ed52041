//! First and second central moments of a feature layer: the mean of every feature and their
//! covariance. Both are per-pixel averages, so independent of the image size. Unlike the
//! Gram matrix they separate "how strong on average" from "how it varies together", which
//! keeps a mean error from hiding in the second moments.

use burn::tensor::Tensor;

/// Mean `[F]` and covariance `[F, F]` of `[F, N]` features (divided by N).
pub(crate) fn mean_and_covariance(features: Tensor<2>) -> (Tensor<1>, Tensor<2>) {
    let [f, n] = features.dims();
    let mean = features.clone().mean_dim(1); // [F, 1]
    let centred = features - mean.clone(); // [F, N]
    let cov = centred
        .clone()
        .matmul(centred.transpose())
        .div_scalar(n as f32); // [F, F]
    (mean.reshape([f]), cov)
}

/// The variance of a projection onto a random unit direction, on average: trace(C) / F.
/// Used as the scale of mean and sliced-Wasserstein differences.
pub(crate) fn mean_variance(cov: &Tensor<2>) -> f32 {
    let f = cov.dims()[0];
    let eye = Tensor::<2>::eye(f, &cov.device());
    (cov.clone() * eye).sum().into_scalar::<f32>() / f as f32
}
