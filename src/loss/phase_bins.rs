//! Ring-phase bins shared by the terms that compare colours per place in the ring: the
//! ring-profile term (`super::ring_profile`, faces) and the low-band term's `ring_phase`
//! reference (`nca::train::low_band`, the residual volume). One binning for both so that
//! "earlywood" means the same pixels to each.

use burn::tensor::{Device, Tensor, TensorData};

/// Bins over one ring: a ring spans 10 to 40 pixels at 256 px, so 8 bins tell earlywood
/// from latewood and the transition between them.
pub(crate) const PHASE_BINS: usize = 8;

/// The bin, in [0, PHASE_BINS), of a place in the ring given in turns (G in years, or an
/// angle over 2 pi; whole turns are ring boundaries).
pub(crate) fn bin_of_turns(turns: f32) -> u8 {
    ((turns.rem_euclid(1.0) * PHASE_BINS as f32) as usize).min(PHASE_BINS - 1) as u8
}

/// Pixels (or voxels) per bin.
pub(crate) fn bin_counts(bins: &[u8]) -> [usize; PHASE_BINS] {
    let mut n = [0; PHASE_BINS];
    for &b in bins {
        n[b as usize] += 1;
    }
    n
}

/// The averaging matrix `[N, PHASE_BINS]` of `bins`: in each pixel's row, 1 / its bin's count
/// in its bin's column where `keep(bin)`, 0 elsewhere. Values `[C, N]` times it give each
/// kept bin's mean, `[C, PHASE_BINS]` (0 in the others).
pub(crate) fn averaging_matrix(
    bins: &[u8],
    keep: impl Fn(usize) -> bool,
    device: &Device,
) -> Tensor<2> {
    let n = bins.len();
    let counts = bin_counts(bins);
    let mut averaging = vec![0.0f32; n * PHASE_BINS];
    for (i, &b) in bins.iter().enumerate() {
        let b = b as usize;
        if keep(b) {
            averaging[i * PHASE_BINS + b] = 1.0 / counts[b] as f32;
        }
    }
    Tensor::from_data(TensorData::new(averaging, [n, PHASE_BINS]), device)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_averaging_matrix_gives_each_kept_bin_its_mean() {
        let device = crate::device::DeviceKind::Flex.device();
        let bins = [0u8, 0, 3, 3, 3, 5];
        let values = Tensor::<2>::from_data(
            TensorData::new(vec![1.0f32, 3.0, 2.0, 4.0, 6.0, 9.0], [1, 6]),
            &device,
        );
        let means = values.matmul(averaging_matrix(&bins, |b| b != 5, &device));
        let means = crate::loss::image_tensor::tensor_values(means).unwrap();
        assert_eq!(means, vec![2.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0]);
    }
}
