//! How a voxel's colour is read from the NCA state: the RGB residual on B, as the Mokume
//! authors do, or the same sum passed through a soft bound that keeps every colour inside
//! [0, 1] however the state drifts (issue 12: stable by construction, not by clamping).
//!
//! The bounds act in photo colour, where [0, 1] is what a PNG or a renderer can show: a tanh
//! (`bounded`) or a softplus corner at each end (`saturating`) of the photo-colour sum x,
//! both increasing and approaching 0 and 1 only asymptotically. Training sees the same map,
//! so the state learns whatever sum gives the colour it wants.

use burn::tensor::activation::softplus as softplus_tensor;
use burn::tensor::{Device, Tensor};
use serde::{Deserialize, Serialize};

use super::tensors::tensor_from;

/// The readout of the colour (`model.readout`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Readout {
    /// RGB = B + state[0..3] (white-balanced), unbounded: the authors' readout, and that of
    /// every model trained before the bound existed.
    #[default]
    Residual,
    /// The same sum, softly bounded to (0, 1) in photo colour by a tanh (slope 1 only at
    /// mid-grey: it also compresses the middle of the range).
    Bounded,
    /// The same sum, identity over most of (0, 1) and saturating smoothly at both ends:
    /// x + s(-x) - s(x - 1) = s(x) - s(x - 1) with s(u) = ln(1 + e^(20 u)) / 20; off by
    /// 1e-4 at 0.3 and 0.7, by 0.035 at 0 and 1.
    Saturating,
}

/// Sharpness of the `saturating` readout's corners (1 / their width in photo colour).
const SATURATION_SHARPNESS: f32 = 20.0;

/// ln(1 + e^(k u)) / k, computed as burn's softplus does (the identity where k u > 20).
fn softplus(u: f32) -> f32 {
    let ku = SATURATION_SHARPNESS * u;
    if ku > 20.0 {
        u
    } else {
        ku.exp().ln_1p() / SATURATION_SHARPNESS
    }
}

impl Readout {
    /// The photo colour of the photo-colour sum `x` (one channel).
    pub fn photo(self, x: f32) -> f32 {
        match self {
            Readout::Residual => x,
            Readout::Bounded => 0.5 + 0.5 * (2.0 * x - 1.0).tanh(),
            // s(x) - s(x - 1) = x + s(-x) - s(x - 1), written without cancellation: the
            // lower half from below, the upper half as 1 minus its mirror image.
            Readout::Saturating if x <= 0.5 => softplus(x) - softplus(x - 1.0),
            Readout::Saturating => 1.0 - (softplus(1.0 - x) - softplus(-x)),
        }
    }

    /// The white-balanced colour `[3, X, Y, Z]` of the white-balanced sum B + state RGB,
    /// differentiable; `white_balance` is the factor from photo to white-balanced colour.
    pub fn white_balanced(
        self,
        sum: Tensor<4>,
        white_balance: [f32; 3],
        device: &Device,
    ) -> Tensor<4> {
        match self {
            Readout::Residual => sum,
            Readout::Bounded | Readout::Saturating => {
                // [3, 1, 1, 1], broadcast over the voxels.
                let wb = tensor_from(white_balance.to_vec(), [3, 1, 1, 1], device);
                let photo = sum / wb.clone();
                let bounded = if self == Readout::Bounded {
                    (photo.mul_scalar(2.0).sub_scalar(1.0))
                        .tanh()
                        .mul_scalar(0.5)
                        .add_scalar(0.5)
                } else {
                    let k = f64::from(SATURATION_SHARPNESS);
                    let lower = softplus_tensor(photo.clone(), k)
                        - softplus_tensor(photo.clone().sub_scalar(1.0), k);
                    let mirror = photo.clone().neg().add_scalar(1.0);
                    let upper = (softplus_tensor(mirror, k)
                        - softplus_tensor(photo.clone().neg(), k))
                    .neg()
                    .add_scalar(1.0);
                    lower.mask_where(photo.greater_elem(0.5), upper)
                };
                bounded * wb
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use burn::tensor::Device;

    use super::*;
    use crate::nca::tensors::to_vec;

    #[test]
    fn bounded_readouts_stay_inside_zero_one_and_keep_mid_grey() {
        for x in [-1e6_f32, -50.0, -1.0, 0.0, 0.25, 0.5, 0.75, 1.0, 3.0, 1e6] {
            for readout in [Readout::Bounded, Readout::Saturating] {
                let p = readout.photo(x);
                assert!((0.0..=1.0).contains(&p), "{readout:?}: {x} -> {p}");
            }
            assert_eq!(Readout::Residual.photo(x), x);
        }
        // The saturating readout is the identity over the middle of the range.
        for x in [0.3_f32, 0.5, 0.7] {
            assert!((Readout::Saturating.photo(x) - x).abs() < 2e-4, "{x}");
        }
        assert!((Readout::Bounded.photo(0.5) - 0.5).abs() < 1e-7);
        // Slope 1 at mid-grey: a small change there passes through unchanged.
        let slope = (Readout::Bounded.photo(0.501) - Readout::Bounded.photo(0.499)) / 0.002;
        assert!((slope - 1.0).abs() < 1e-3, "{slope}");
        // Increasing, so every colour in (0, 1) has one sum that makes it (f32 rounds the
        // far tails to exactly 0 or 1).
        let xs: Vec<f32> = (-40..=60).map(|i| i as f32 * 0.05).collect();
        for readout in [Readout::Bounded, Readout::Saturating] {
            let ps: Vec<f32> = xs.iter().map(|&x| readout.photo(x)).collect();
            assert!(ps.windows(2).all(|w| w[0] <= w[1]), "{readout:?}: {ps:?}");
            let middle = &ps[30..=70]; // x in [-0.5, 1.5]
            assert!(
                middle.windows(2).all(|w| w[0] < w[1]),
                "{readout:?}: {ps:?}"
            );
        }
    }

    /// Training (burn, white-balanced) and synthesis (plain, photo colour) read the same
    /// colour from the same sum.
    #[test]
    fn tensor_readout_matches_the_per_value_one() {
        let device = Device::flex();
        let wb = [0.8_f32, 0.9, 1.1];
        let sums: Vec<f32> = (0..3 * 8).map(|i| (i as f32 - 9.0) * 0.11).collect();
        let tensor = tensor_from(sums.clone(), [3, 2, 2, 2], &device);
        for readout in [Readout::Residual, Readout::Bounded, Readout::Saturating] {
            let got = to_vec(readout.white_balanced(tensor.clone(), wb, &device)).unwrap();
            for (i, (&sum, &g)) in sums.iter().zip(&got).enumerate() {
                let wb = wb[i / 8];
                let want = readout.photo(sum / wb) * wb;
                assert!((g - want).abs() < 1e-5, "{readout:?} {i}: {g} vs {want}");
            }
        }
    }
}
