//! The low-band term of the training loss (`[loss] low_band`): the root mean square of the
//! colour residual's means over blocks of `low_band_block`^3 voxels, each block mean taken
//! from a reference (`[loss] low_band_reference`; DESIGN "Low band reference and shown
//! targets"):
//! - `zero`: B already carries the rings and the colour at the block's scale, the NCA adds
//!   texture that averages out within a block;
//! - `crop_mean`: the residual may shift the whole crop's colour (dark pores on the ground
//!   colour darken it on average) but not paint bands or blotches;
//! - `ring_phase`: the residual may also depend on where in its ring a voxel is (pores
//!   packed in the earlywood darken the earlywood more than the latewood), but nothing
//!   else at the block's scale: the part of the residual explained by the ring phase (its
//!   mean over the crop's voxels of the same phase bin) is removed before the block means.

use burn::tensor::{Device, Tensor};

use crate::loss::phase_bins::{PHASE_BINS, averaging_matrix, bin_of_turns};
use crate::nca::config::LowBandReference;
use crate::nca::tensors::tensor_from;

/// The low-band term's settings (`[loss]`).
#[derive(Clone, Copy, Debug)]
pub struct LowBand {
    pub block: usize,
    pub reference: LowBandReference,
}

/// The ring-phase bin, in [0, PHASE_BINS), of each G value (years; rings at whole years).
pub fn phase_bins(g: &[f32]) -> Vec<u8> {
    g.iter().copied().map(bin_of_turns).collect()
}

impl LowBand {
    /// The term of `residual` `[3, X, Y, Z]` (the sides are multiples of the block, checked
    /// with the config), as `[1]`; `bins` is [`phase_bins`] of the region's voxels in the
    /// residual's order (used by the `ring_phase` reference only).
    pub fn term(&self, residual: Tensor<4>, bins: &[u8]) -> Tensor<1> {
        let deviations = match self.reference {
            LowBandReference::RingPhase => minus_phase_means(residual, bins),
            LowBandReference::Zero | LowBandReference::CropMean => residual,
        };
        let means = block_means(deviations, self.block); // [3, blocks]
        let centred = match self.reference {
            LowBandReference::Zero | LowBandReference::RingPhase => means,
            LowBandReference::CropMean => means.clone() - means.mean_dim(1),
        };
        centred.square().mean().add_scalar(1e-12).sqrt()
    }
}

/// Means of `t` `[C, X, Y, Z]` over blocks of `block`^3 voxels, `[C, blocks]`.
fn block_means(t: Tensor<4>, block: usize) -> Tensor<2> {
    let [c, x, y, z] = t.dims();
    let (bx, by, bz) = (x / block, y / block, z / block);
    t.reshape([c * bx, block, by, block, bz * block])
        .mean_dim(3)
        .mean_dim(1) // [c * bx, 1, by, 1, bz * block]
        .reshape([c * bx * by, bz, block])
        .mean_dim(2) // [c * bx * by, bz, 1]
        .reshape([c, bx * by * bz])
}

/// `residual` `[C, X, Y, Z]` minus, at every voxel, the mean of the residual over the
/// voxels of its phase bin (per channel).
fn minus_phase_means(residual: Tensor<4>, bins: &[u8]) -> Tensor<4> {
    let dims = residual.dims();
    let [c, x, y, z] = dims;
    let n = x * y * z;
    assert_eq!(bins.len(), n, "one phase bin per voxel");
    let device: Device = residual.device();
    let (one_hot, averaging) = bin_matrices(bins, &device); // [K, N], [N, K]
    let flat = residual.reshape([c, n]);
    let bin_means = flat.clone().matmul(averaging); // [C, K]
    let explained = bin_means.matmul(one_hot); // [C, N]
    (flat - explained).reshape(dims)
}

/// The one-hot matrix of the bins `[K, N]` and its transpose with every column divided by
/// the bin's count `[N, K]` (empty bins stay zero).
fn bin_matrices(bins: &[u8], device: &Device) -> (Tensor<2>, Tensor<2>) {
    let n = bins.len();
    let mut one_hot = vec![0.0f32; PHASE_BINS * n];
    for (i, &b) in bins.iter().enumerate() {
        one_hot[b as usize * n + i] = 1.0;
    }
    (
        tensor_from(one_hot, [PHASE_BINS, n], device),
        averaging_matrix(bins, |_| true, device),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn residual(values: impl Fn(usize, usize, usize, usize) -> f32, side: usize) -> Tensor<4> {
        let mut data = Vec::with_capacity(3 * side * side * side);
        for c in 0..3 {
            for x in 0..side {
                for y in 0..side {
                    for z in 0..side {
                        data.push(values(c, x, y, z));
                    }
                }
            }
        }
        tensor_from(data, [3, side, side, side], &Device::default())
    }

    fn term(t: Tensor<4>, block: usize, reference: LowBandReference, bins: &[u8]) -> f32 {
        LowBand { block, reference }
            .term(t, bins)
            .into_scalar::<f32>()
    }

    fn rms(t: Tensor<4>, block: usize) -> f32 {
        term(t, block, LowBandReference::Zero, &[])
    }

    fn spread(t: Tensor<4>, block: usize) -> f32 {
        term(t, block, LowBandReference::CropMean, &[])
    }

    /// Phase bins of a `side`^3 region whose rings are planes x = const, in the voxel
    /// order of `residual` (x slowest).
    fn slab_bins(side: usize, bin_of_x: impl Fn(usize) -> u8) -> Vec<u8> {
        let mut bins = Vec::with_capacity(side * side * side);
        for x in 0..side {
            for _ in 0..side * side {
                bins.push(bin_of_x(x));
            }
        }
        bins
    }

    /// Channel 1 at +0.4 in the 4^3 block at x, y, z in [4, 8) of an 8^3 region, 0 elsewhere.
    fn one_block_shifted(c: usize, x: usize, y: usize, z: usize) -> f32 {
        if c == 1 && x >= 4 && y >= 4 && z >= 4 {
            0.4
        } else {
            0.0
        }
    }

    #[test]
    fn texture_that_averages_out_in_a_block_costs_nothing() {
        // +-0.2 alternating voxel by voxel: every 2^3 and 4^3 block averages to zero.
        let checker = |_c: usize, x: usize, y: usize, z: usize| {
            if (x + y + z).is_multiple_of(2) {
                0.2
            } else {
                -0.2
            }
        };
        assert!(rms(residual(checker, 8), 2).abs() < 1e-5);
        assert!(rms(residual(checker, 8), 4).abs() < 1e-5);
        // A single voxel's block (block 1) sees the texture itself.
        assert!((rms(residual(checker, 4), 1) - 0.2).abs() < 1e-5);
    }

    #[test]
    fn a_shift_of_one_block_is_measured_in_that_block_alone() {
        // Channel 1 of the block at x, y, z in [4, 8) is shifted by 0.4: one block of the
        // 2^3 x 3 channels = 24 has mean 0.4, so the RMS is sqrt(0.16 / 24).
        let expected = (0.16f32 / 24.0).sqrt();
        assert!((rms(residual(one_block_shifted, 8), 4) - expected).abs() < 1e-5);
        // Blocks of 8 cover the whole crop: the mean of channel 1 is 0.4 / 8.
        let expected = ((0.05f32 * 0.05) / 3.0).sqrt();
        assert!((rms(residual(one_block_shifted, 8), 8) - expected).abs() < 1e-5);
    }

    #[test]
    fn the_crop_mean_reference_frees_a_uniform_shift_but_not_a_local_one() {
        // Channel 0 darkened by 0.1 everywhere: what dark pores do to the ground colour.
        let darker = |c: usize, _x: usize, _y: usize, _z: usize| if c == 0 { -0.1 } else { 0.0 };
        assert!((rms(residual(darker, 8), 4) - 0.1 / 3f32.sqrt()).abs() < 1e-5);
        assert!(spread(residual(darker, 8), 4).abs() < 1e-5);
        // One block of channel 1 at +0.4: the crop mean of that channel is 0.05, the
        // deviations 0.35 once and -0.05 seven times, over 24 block means.
        let expected = ((0.35f32 * 0.35 + 7.0 * 0.05 * 0.05) / 24.0).sqrt();
        assert!((spread(residual(one_block_shifted, 8), 4) - expected).abs() < 1e-5);
    }

    #[test]
    fn the_ring_phase_reference_frees_earlywood_darkening_but_not_a_blotch() {
        // Rings are planes x = const; x in [0, 4) is earlywood (bin 0), [4, 8) latewood
        // (bin 4). Channel 2 darker by 0.2 in the earlywood: costs under `zero` and
        // `crop_mean`, nothing under `ring_phase`.
        let bins = slab_bins(8, |x| if x < 4 { 0 } else { 4 });
        let early_dark = |c: usize, x: usize, _y: usize, _z: usize| {
            if c == 2 && x < 4 { -0.2 } else { 0.0 }
        };
        let phase = |t| term(t, 4, LowBandReference::RingPhase, &bins);
        assert!(rms(residual(early_dark, 8), 4) > 0.05);
        assert!(spread(residual(early_dark, 8), 4) > 0.05);
        assert!(phase(residual(early_dark, 8)).abs() < 1e-5);
        // A blotch in one earlywood block (x, y, z in [0, 4)) at -0.4: its bin's mean is
        // -0.1 (a quarter of the bin's voxels), so that block keeps -0.3 and the other
        // three earlywood blocks +0.1; the latewood blocks are untouched. RMS over the
        // 8 blocks x 3 channels = sqrt((0.09 + 3 x 0.01) / 24).
        let blotch = |c: usize, x: usize, y: usize, z: usize| {
            if c == 2 && x < 4 && y < 4 && z < 4 {
                -0.4
            } else {
                0.0
            }
        };
        let expected = ((0.09f32 + 3.0 * 0.01) / 24.0).sqrt();
        assert!((phase(residual(blotch, 8)) - expected).abs() < 1e-5);
    }

    #[test]
    fn phase_bins_wrap_at_whole_years() {
        assert_eq!(
            phase_bins(&[0.0, 0.124, 0.126, 0.99, 1.0, 2.5, -0.25]),
            vec![0, 0, 1, 7, 0, 4, 6]
        );
    }
}
