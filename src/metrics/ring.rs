//! Ring alignment (`ring_ncc`): do the ring bands of the candidate lie where the reference's
//! do? Both luminances are band-passed (a difference of Gaussians that keeps ring-scale
//! structure and drops pores, noise and slow shading), then correlated (Pearson) over their
//! common interior for every shift up to `max_shift` pixels in each direction; the best
//! correlation is the score (1: identical bands, 0: unrelated, < 0: bands where gaps are).
//! The shift tolerance forgives a ring placed a pixel or two off, which a growth-field fit
//! cannot avoid. Scales are given for a 256 px image and follow the image width.

use crate::image_filter::gaussian_blur;
use crate::image2::Image2;
use crate::series::pearson;

/// Band-pass and shift settings at 256 px (scaled with the image width).
#[derive(Clone, Copy, Debug)]
pub struct RingSettings {
    /// Fine Gaussian sigma (px at 256): removes pores and noise.
    pub fine_sigma: f32,
    /// Coarse Gaussian sigma (px at 256): removes shading; ring bands lie between the two.
    pub coarse_sigma: f32,
    /// Largest shift tried in each direction (px at 256).
    pub max_shift: f32,
}

impl Default for RingSettings {
    fn default() -> Self {
        Self {
            fine_sigma: 2.0,
            coarse_sigma: 16.0,
            max_shift: 3.0,
        }
    }
}

/// Band-passed luminance: blur(fine) - blur(coarse).
pub(crate) fn band_pass(img: &Image2, settings: &RingSettings) -> Image2 {
    let scale = img.width as f32 / 256.0;
    let lum = img.luminance();
    let fine = gaussian_blur(&lum, settings.fine_sigma * scale);
    let coarse = gaussian_blur(&lum, settings.coarse_sigma * scale);
    let data = fine
        .data
        .iter()
        .zip(&coarse.data)
        .map(|(f, c)| f - c)
        .collect();
    Image2 { data, ..fine }
}

/// Best Pearson correlation of the band-passed luminances over shifts (images of equal size).
pub fn ring_ncc(reference: &Image2, candidate: &Image2, settings: &RingSettings) -> f32 {
    let a = band_pass(reference, settings);
    let b = band_pass(candidate, settings);
    let s = ((settings.max_shift * reference.width as f32 / 256.0).round() as usize)
        .min(reference.width.min(reference.height).saturating_sub(2) / 2);
    shifted_correlation(&a, &b, 0, s)
}

/// The best Pearson correlation of two equally sized images' first channels over shifts of `b`
/// by up to `shift` pixels in rows and columns, on `a`'s interior `border + shift` pixels in
/// from every edge (so every shifted `b` pixel exists); forgives a ring placed a pixel or two
/// off, as DESIGN section 8's ring alignment does.
pub fn shifted_correlation(a: &Image2, b: &Image2, border: usize, shift: usize) -> f32 {
    let (w, h) = (a.width, a.height);
    let m = border + shift;
    let s = shift as isize;
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    let mut best = f32::NEG_INFINITY;
    for dy in -s..=s {
        for dx in -s..=s {
            xs.clear();
            ys.clear();
            for y in m..h.saturating_sub(m) {
                let yb = (y as isize + dy) as usize;
                for x in m..w.saturating_sub(m) {
                    let xb = (x as isize + dx) as usize;
                    xs.push(a.get(y, x, 0));
                    ys.push(b.get(yb, xb, 0));
                }
            }
            best = best.max(pearson(&xs, &ys));
        }
    }
    best
}
