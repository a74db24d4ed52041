//! How much of a photo is vessels: small dark spots and dashes, not the ring lines.
//!
//! A pixel is dark as the pore-density curve counts it
//! ([`super::phase_density::PORE_DEPTH`] below its surroundings in high-passed Lab
//! lightness, at 256 px). Dark pixels join into 8-connected patches; a vessel cut across or
//! along is a patch of a few to a few dozen pixels (chestnut's earlywood dashes: 1-3 px wide,
//! 6-12 px long), while a softwood's dark latewood line runs across the face as one long
//! patch. Only patches of at most [`MAX_VESSEL_PIXELS`] count.

use super::anisotropy::high_passed_lightness;
use super::phase_density::PORE_DEPTH;
use crate::image2::Image2;
use crate::mask_patches::patch_sizes;

/// The largest dark patch (pixels at 256 px) that still counts as a vessel: a dash of 3 x 20.
pub const MAX_VESSEL_PIXELS: usize = 60;

/// The fraction of an RGB image's pixels that lie in vessel-sized dark patches.
pub fn vessel_fraction(image: &Image2) -> f32 {
    let hp = high_passed_lightness(image);
    let dark: Vec<bool> = hp.data.iter().map(|&l| l < -PORE_DEPTH).collect();
    let vessels: usize = patch_sizes(&dark, hp.width)
        .into_iter()
        .filter(|&n| n <= MAX_VESSEL_PIXELS)
        .sum();
    vessels as f32 / dark.len().max(1) as f32
}
