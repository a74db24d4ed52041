//! The ring-profile term of the guided loss (`[loss.guided] profile_weight`): a patch's mean
//! colour at each ring phase against the photo window's.
//!
//! Why a term of its own: the feature distances see the ring phase only jointly with
//! band-passed filter responses, and the colour term compares colour distributions without
//! the phase, so neither asks directly for the earlywood to be as much darker than the
//! latewood as in the photo. Measured on the shipped model's CN03 sheet (BENCHMARKS "Ring
//! contrast of the NCA against the photos"), the NCA's profile over the ring phase had about
//! half to two thirds of the photos' amplitude on the side faces; on hinoki it was too
//! strong on some faces of one run and too weak on others of another. A mean per phase bin,
//! compared with the photo's own window, asks for the photo's contrast either way.
//!
//! Phase bins come from the guide channels (cos, sin of 2 pi G; `nca::train::face_guides`),
//! colours are projected on the colour term's axes (or its luminance axis alone,
//! `profile_axes = "lightness"`) and scaled by the window's spread along each, so the term
//! is dimensionless like the others. A bin counts only where both the patch and the window
//! have at least `MIN_PIXELS` pixels in it.

use burn::tensor::{Tensor, TensorData};

use super::image_tensor::tensor_values;
use super::phase_bins::{PHASE_BINS as BINS, averaging_matrix, bin_counts, bin_of_turns};

/// Fewer pixels than this in a bin (patch or window) and the bin is left out.
const MIN_PIXELS: usize = 8;

/// The phase bin of every pixel of a guide `[G, N]` whose first two channels are
/// (cos, sin) of 2 pi G.
pub(crate) fn phase_bins(guide: Tensor<2>) -> Vec<u8> {
    let [g, n] = guide.dims();
    let values = tensor_values(guide.narrow(0, 0, g.min(2))).unwrap_or_default();
    if g < 2 || values.len() < 2 * n {
        return vec![0; n];
    }
    let (cos, sin) = values.split_at(n);
    cos.iter()
        .zip(sin)
        .map(|(&c, &s)| bin_of_turns(s.atan2(c) / std::f32::consts::TAU))
        .collect()
}

/// The window's mean scaled colour per axis and bin.
pub(crate) struct ProfileTarget {
    /// `[A * BINS]`, axis-major.
    means: Vec<f32>,
    counts: [usize; BINS],
}

impl ProfileTarget {
    /// From the window's scaled colour projections `[A, M]` and its pixels' bins.
    pub(crate) fn new(scaled: Tensor<2>, bins: &[u8]) -> Self {
        let [a, m] = scaled.dims();
        let values = tensor_values(scaled).unwrap_or_default();
        let counts = bin_counts(bins);
        let mut means = vec![0.0; a * BINS];
        if values.len() == a * m {
            for axis in 0..a {
                for (&v, &b) in values[axis * m..(axis + 1) * m].iter().zip(bins) {
                    means[axis * BINS + b as usize] += v;
                }
            }
            for axis in 0..a {
                for b in 0..BINS {
                    means[axis * BINS + b] /= counts[b].max(1) as f32;
                }
            }
        }
        Self { means, counts }
    }

    /// Mean squared difference, over the axes and the bins both sides fill, of a patch's
    /// per-bin means (scaled colour projections `[A, N]`, bins of its pixels) to the window's;
    /// 0 when no bin is shared.
    pub(crate) fn distance(&self, scaled: Tensor<2>, bins: &[u8]) -> Tensor<1> {
        let [a, _] = scaled.dims();
        let device = scaled.device();
        let patch = bin_counts(bins);
        let used: Vec<bool> = (0..BINS)
            .map(|b| patch[b] >= MIN_PIXELS && self.counts[b] >= MIN_PIXELS)
            .collect();
        let shared = used.iter().filter(|&&u| u).count();
        if shared == 0 {
            return Tensor::zeros([1], &device);
        }
        let average = averaging_matrix(bins, |b| used[b], &device); // [N, BINS]
        // The mask alone leaves the unused bins out: their means are 0, their targets any.
        let mask: Vec<f32> = (0..a * BINS)
            .map(|i| if used[i % BINS] { 1.0 } else { 0.0 })
            .collect();
        let target =
            Tensor::<2>::from_data(TensorData::new(self.means.clone(), [a, BINS]), &device);
        let mask = Tensor::<2>::from_data(TensorData::new(mask, [a, BINS]), &device);
        let means = scaled.matmul(average); // [A, BINS], 0 in unused bins
        ((means - target) * mask)
            .square()
            .sum()
            .div_scalar((a * shared) as f32)
            .reshape([1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::Device;

    fn device() -> Device {
        crate::device::DeviceKind::Flex.device()
    }

    fn guide_of(phases: &[f32]) -> Tensor<2> {
        let n = phases.len();
        let mut v: Vec<f32> = phases
            .iter()
            .map(|p| (p * std::f32::consts::TAU).cos())
            .collect();
        v.extend(phases.iter().map(|p| (p * std::f32::consts::TAU).sin()));
        Tensor::from_data(TensorData::new(v, [2, n]), &device())
    }

    #[test]
    fn phases_fall_in_their_bins() {
        let bins = phase_bins(guide_of(&[0.01, 0.13, 0.26, 0.49, 0.51, 0.76, 0.99]));
        assert_eq!(bins, vec![0, 1, 2, 3, 4, 6, 7]);
    }

    #[test]
    fn the_term_sees_a_missing_earlywood_darkening_and_not_a_shuffle() {
        // 64 pixels over one ring; the window darker in bins 0-1 (earlywood) by 1 unit.
        let phases: Vec<f32> = (0..64).map(|i| (i as f32 + 0.5) / 64.0).collect();
        let bins = phase_bins(guide_of(&phases));
        let profile: Vec<f32> = bins
            .iter()
            .map(|&b| if b < 2 { -1.0 } else { 0.0 })
            .collect();
        let window = Tensor::<2>::from_data(TensorData::new(profile.clone(), [1, 64]), &device());
        let target = ProfileTarget::new(window, &bins);
        let flat = Tensor::<2>::from_data(TensorData::new(vec![-0.25; 64], [1, 64]), &device());
        let same = Tensor::<2>::from_data(TensorData::new(profile, [1, 64]), &device());
        let d_flat = tensor_values(target.distance(flat, &bins)).unwrap()[0];
        let d_same = tensor_values(target.distance(same, &bins)).unwrap()[0];
        // Flat at the mean: bins 0-1 off by 0.75, the other six by 0.25.
        let expected = (2.0 * 0.75f32.powi(2) + 6.0 * 0.25f32.powi(2)) / 8.0;
        assert!((d_flat - expected).abs() < 1e-5, "{d_flat} vs {expected}");
        assert!(d_same.abs() < 1e-10, "{d_same}");
    }

    #[test]
    fn bins_with_too_few_pixels_are_left_out() {
        // The patch has all its pixels in bin 0: only that bin counts.
        let window_phases: Vec<f32> = (0..64).map(|i| (i as f32 + 0.5) / 64.0).collect();
        let window_bins = phase_bins(guide_of(&window_phases));
        let window_values: Vec<f32> = window_bins.iter().map(|&b| b as f32).collect();
        let window = Tensor::<2>::from_data(TensorData::new(window_values, [1, 64]), &device());
        let target = ProfileTarget::new(window, &window_bins);
        let patch_bins = vec![0u8; 16];
        let patch = Tensor::<2>::from_data(TensorData::new(vec![0.5; 16], [1, 16]), &device());
        let d = tensor_values(target.distance(patch, &patch_bins)).unwrap()[0];
        assert!((d - 0.25).abs() < 1e-6, "{d}");
    }
}
