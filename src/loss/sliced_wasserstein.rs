//! Sliced Wasserstein distance between the feature distributions of a generated image and a
//! target (Heitz et al. 2021, on fixed-filter features instead of VGG): project every pixel's
//! feature vector on random unit directions, sort each projection, and compare the sorted
//! values (the 1D optimal transport) with the target's.
//!
//! Sizes differ (a patch against a whole face), so the target's sorted values are resampled
//! at the generated image's quantile positions: with n generated pixels, value i is compared
//! with the target's quantile (i + 0.5) / n, interpolated linearly between the target's
//! order statistics. This compares distributions, not pixel counts.
//!
//! Where Gram matrices only see second moments, the sorted projections see the whole
//! marginal: sparse dark pores on a light ground and a uniform grey of the same mean and
//! variance differ here and not there (the trial of shared DESIGN section 7).

use std::collections::HashMap;
use std::sync::Mutex;

use burn::tensor::{Device, Int, Tensor, TensorData};

use crate::rng::{Rng, mix64};

/// `count` random unit directions in `features` dimensions, `[P, F]`, from `seed` and the
/// sub-stream `stream` (the layer, and the call counter when projections are redrawn).
pub(crate) fn random_projections(
    seed: u64,
    stream: u64,
    count: usize,
    features: usize,
    device: &Device,
) -> Tensor<2> {
    let mut rng = Rng::substream(seed, mix64(stream ^ 0x5357_4450));
    let mut data = Vec::with_capacity(count * features);
    for _ in 0..count {
        let row: Vec<f32> = (0..features).map(|_| rng.normal()).collect();
        let norm = row.iter().map(|v| v * v).sum::<f32>().sqrt().max(1e-12);
        data.extend(row.iter().map(|v| v / norm));
    }
    Tensor::from_data(TensorData::new(data, [count, features]), device)
}

/// Projections of `[F, N]` features on `[P, F]` directions, each row sorted: `[P, N]`.
pub(crate) fn sorted_projections(features: Tensor<2>, projections: Tensor<2>) -> Tensor<2> {
    projections.matmul(features).sort(1)
}

/// `[P, M]` sorted values resampled at `n` quantile positions `(i + 0.5) / n`: `[P, n]`.
/// Linear interpolation between order statistics (positions `(j + 0.5) / M`), clamped at the
/// ends. With `n == M` the values are returned as they are.
pub(crate) fn resample_sorted(sorted: Tensor<2>, n: usize) -> Tensor<2> {
    let [_, m] = sorted.dims();
    if m == n {
        return sorted;
    }
    let device = sorted.device();
    let mut lo = Vec::with_capacity(n);
    let mut hi = Vec::with_capacity(n);
    let mut weight = Vec::with_capacity(n);
    for i in 0..n {
        let t = ((i as f64 + 0.5) * m as f64 / n as f64 - 0.5).clamp(0.0, (m - 1) as f64);
        let j = t.floor() as usize;
        lo.push(j as i64);
        hi.push((j + 1).min(m - 1) as i64);
        weight.push((t - j as f64) as f32);
    }
    let lo = Tensor::<1, Int>::from_data(TensorData::new(lo, [n]), &device);
    let hi = Tensor::<1, Int>::from_data(TensorData::new(hi, [n]), &device);
    let w = Tensor::<2>::from_data(TensorData::new(weight, [1, n]), &device);
    let a = sorted.clone().select(1, lo);
    let b = sorted.select(1, hi);
    a.clone() + (b - a) * w
}

/// A target's sorted projections `[P, M]`, with its resamplings to the generated sizes seen so
/// far kept (a training loop asks for the same few sizes every iteration).
#[derive(Debug)]
pub(crate) struct SortedTarget {
    sorted: Tensor<2>,
    resampled: Mutex<HashMap<usize, Tensor<2>>>,
}

impl SortedTarget {
    pub(crate) fn new(sorted: Tensor<2>) -> Self {
        Self {
            sorted,
            resampled: Mutex::new(HashMap::new()),
        }
    }

    /// The target quantiles at `n` positions, `[P, n]`.
    pub(crate) fn at(&self, n: usize) -> Tensor<2> {
        let mut cache = self
            .resampled
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        cache
            .entry(n)
            .or_insert_with(|| resample_sorted(self.sorted.clone(), n))
            .clone()
    }
}
