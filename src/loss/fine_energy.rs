//! The pixel-scale energy term of the guided loss (`[loss.guided] fine_weight`): how much a
//! patch's lightness changes from one pixel to the next, down the rows, along the columns
//! and in the 2x2 checkerboard, against the photo window's.
//!
//! Why: the NCA's pores were stippled, 1 px dots in a checkerboard where the photos have
//! continuous dashes (BENCHMARKS "Pixel-scale energy"). The sliced Wasserstein term sees
//! each pixel's filter responses as one point of a distribution: a band of dots and a band
//! of dashes of the same darkness give nearly the same distribution. The mean square of
//! these three differences is what differs: a dash along the grain has almost none along
//! it and no checkerboard; a stipple has both. Compared as log ratios, so a faint and a
//! contrasted face weigh alike and the term is zero only when each energy matches.

use burn::tensor::{Tensor, TensorData};

use super::filters::LUMA;

/// Added to every energy before the log: far below a photo's (about 1e-3 in the loss's
/// colour units, where the mean colour is 0.5), so it only guards a flat patch.
const ENERGY_EPS: f32 = 1e-6;

/// The three energies of an image `[3, h, w]` (h, w >= 2): mean squared difference between
/// vertical neighbours, between horizontal neighbours, and of the 2x2 checkerboard
/// `a - b - c + d`, as `[3]`.
pub(crate) fn fine_energies(image: Tensor<3>) -> Tensor<1> {
    let [_, h, w] = image.dims();
    let device = image.device();
    let luma =
        Tensor::<1>::from_data(TensorData::new(LUMA.to_vec(), [3]), &device).reshape([3, 1, 1]);
    let l = (image * luma).sum_dim(0); // [1, h, w]
    let top = l.clone().narrow(1, 0, h - 1); // [1, h - 1, w]
    let bottom = l.clone().narrow(1, 1, h - 1);
    let left = l.clone().narrow(2, 0, w - 1); // [1, h, w - 1]
    let right = l.narrow(2, 1, w - 1);
    let down = (bottom.clone() - top.clone()).square().mean(); // [1]
    let across = (right - left).square().mean();
    // (top row's horizontal difference) - (bottom row's): the checkerboard a - b - c + d
    let top_diff = top.clone().narrow(2, 1, w - 1) - top.narrow(2, 0, w - 1); // [1, h - 1, w - 1]
    let bottom_diff = bottom.clone().narrow(2, 1, w - 1) - bottom.narrow(2, 0, w - 1);
    let checker = (top_diff - bottom_diff).square().mean();
    Tensor::cat(vec![down, across, checker], 0)
}

/// ln(energy + ENERGY_EPS) of each energy `[3]`: what [`fine_distance`] compares.
pub(crate) fn log_energies(energies: Tensor<1>) -> Tensor<1> {
    energies.add_scalar(ENERGY_EPS).log()
}

/// Mean over the three energies of (ln generated - ln target)^2, `[1]`; `target_log` from
/// [`log_energies`] of the window.
pub(crate) fn fine_distance(generated: Tensor<1>, target_log: &Tensor<1>) -> Tensor<1> {
    (log_energies(generated) - target_log.clone())
        .square()
        .mean()
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::Device;

    fn image(h: usize, w: usize, f: impl Fn(usize, usize) -> f32) -> Tensor<3> {
        let mut v = Vec::with_capacity(3 * h * w);
        for _ in 0..3 {
            for r in 0..h {
                for c in 0..w {
                    v.push(f(r, c));
                }
            }
        }
        Tensor::from_data(TensorData::new(v, [3, h, w]), &Device::default())
    }

    fn energies(e: [f32; 3]) -> Tensor<1> {
        Tensor::from_data(TensorData::new(e.to_vec(), [3]), &Device::default())
    }

    fn values(t: Tensor<1>) -> Vec<f32> {
        crate::loss::image_tensor::tensor_values(t).unwrap()
    }

    #[test]
    fn a_checkerboard_has_checker_energy_and_vertical_stripes_only_across() {
        let checker = values(fine_energies(image(8, 8, |r, c| ((r + c) % 2) as f32)));
        // every neighbour differs by 1; the checkerboard a - b - c + d is +-2
        assert!((checker[0] - 1.0).abs() < 1e-5 && (checker[1] - 1.0).abs() < 1e-5);
        assert!((checker[2] - 4.0).abs() < 1e-5);
        let stripes = values(fine_energies(image(8, 8, |_, c| (c % 2) as f32)));
        assert!(
            stripes[0].abs() < 1e-6,
            "no change down a column: {stripes:?}"
        );
        assert!((stripes[1] - 1.0).abs() < 1e-5);
        assert!(
            stripes[2].abs() < 1e-6,
            "stripes are no checkerboard: {stripes:?}"
        );
    }

    #[test]
    fn the_distance_is_zero_on_the_target_and_grows_with_the_ratio() {
        let e = [1e-3f32, 2e-3, 5e-4];
        let same = energies(e);
        let target = log_energies(energies(e));
        let zero = values(fine_distance(same, &target))[0];
        assert!(zero.abs() < 1e-8, "{zero}");
        let double = energies(e.map(|x| 2.0 * x));
        let half = energies(e.map(|x| 0.5 * x));
        let (d2, d05) = (
            values(fine_distance(double, &target))[0],
            values(fine_distance(half, &target))[0],
        );
        // ln 2 squared, for twice and for half the energy alike (up to ENERGY_EPS, a
        // thousandth of these energies)
        assert!((d2 - 2f32.ln().powi(2)).abs() < 5e-3, "{d2}");
        assert!((d05 - d2).abs() < 5e-3, "{d05} vs {d2}");
    }
}
