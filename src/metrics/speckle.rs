//! Pixel-scale speckle (`speckle`): how much of an image's pixel-to-pixel change is a 2x2
//! checkerboard rather than edges. On the high-passed lightness at 256 px
//! ([`super::anisotropy::high_passed_lightness`]): the mean square of the checkerboard
//! `a - b - c + d` over the mean squares of the vertical and horizontal neighbour
//! differences. White noise scores 1, a pure checkerboard 2, anything smooth at the pixel
//! scale (dashes, ring edges) near 0.
//!
//! Why: the NCA's pores were stippled dots where the photos have continuous dashes; the
//! patch and style statistics hardly see it (BENCHMARKS "Pixel-scale energy"). Measured
//! with quality.toml before the pixel-scale energy term (lrq2ip10): the synthetic
//! chestnut's hidden cut2 .71 against the truth's .30, CN03 C held out .93 against the
//! photo's .69. Like `aniso` it is a property of each image: compare the candidate's with
//! `speckle_ref`.

use super::anisotropy::high_passed_lightness;
use crate::image2::Image2;

/// The checkerboard energy over the neighbour-difference energy (0 for a flat image).
pub fn speckle(img: &Image2) -> f32 {
    let l = high_passed_lightness(img);
    let (w, h) = (l.width, l.height);
    if w < 2 || h < 2 {
        return 0.0;
    }
    let at = |r: usize, c: usize| l.data[r * w + c] as f64;
    let (mut down, mut across, mut checker) = (0f64, 0f64, 0f64);
    for r in 0..h - 1 {
        for c in 0..w - 1 {
            let (a, b, d, e) = (at(r, c), at(r, c + 1), at(r + 1, c), at(r + 1, c + 1));
            down += (d - a) * (d - a);
            across += (b - a) * (b - a);
            checker += (a - b - d + e) * (a - b - d + e);
        }
    }
    if down + across <= 1e-20 {
        return 0.0;
    }
    (checker / (down + across)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(side: usize, mut f: impl FnMut(usize, usize) -> f32) -> Image2 {
        let mut data = Vec::with_capacity(3 * side * side);
        for r in 0..side {
            for c in 0..side {
                let v = f(r, c);
                data.extend([v, v, v]);
            }
        }
        Image2::from_data(side, side, 3, data).unwrap()
    }

    #[test]
    fn a_checkerboard_scores_two_stripes_and_flat_none() {
        let checker = speckle(&grey(256, |r, c| 0.4 + 0.2 * ((r + c) % 2) as f32));
        assert!((checker - 2.0).abs() < 0.05, "{checker}");
        let stripes = speckle(&grey(256, |_, c| 0.4 + 0.2 * ((c / 3) % 2) as f32));
        assert!(stripes < 0.05, "{stripes}");
        assert_eq!(speckle(&grey(256, |_, _| 0.5)), 0.0);
    }

    #[test]
    fn white_noise_scores_about_one() {
        let mut rng = crate::rng::Rng::new(3);
        let noise = grey(256, |_, _| 0.3 + 0.4 * rng.uniform());
        let s = speckle(&noise);
        assert!((s - 1.0).abs() < 0.15, "{s}");
    }
}
