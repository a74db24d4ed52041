//! Resampling an [`Image2`] to another size: the one implementation every caller shares.
//!
//! Shrinking is a box filter: an output pixel is the plain mean of the input pixels its
//! footprint touches, so a downscale does not alias; for integer ratios (the pipeline's
//! 256 -> 128 training targets, 256 -> 64) the footprints tile the input exactly and the
//! mean is kept; for other ratios a pixel on a footprint's edge counts whole. The two
//! callers differ only when enlarging: displays and metrics ([`Image2::resized`]) repeat
//! pixels (a sheet tile shows the slice's own pixels); training targets
//! ([`Image2::resampled`]) interpolate bilinearly, so a photo smaller than the training grid
//! does not teach the NCA blocky texture.
//!
//! Before this module, training targets used exact fractional overlap weights: the same
//! numbers for integer ratios (powers of two bit for bit), slightly different for others.

use crate::image2::Image2;

/// How an image is enlarged.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Enlarge {
    /// As when shrinking: each output pixel averages the input pixels it touches (pixels
    /// repeat).
    Area,
    /// Linear interpolation between pixel centres.
    Linear,
}

impl Image2 {
    /// The image resampled to `width` x `height` by area: each output pixel is the mean of the
    /// input pixels its footprint touches (enlarging repeats pixels).
    pub fn resized(&self, width: usize, height: usize) -> Image2 {
        self.resample_with(width, height, Enlarge::Area)
    }

    /// The image resampled to `width` x `height` for training: area average when shrinking,
    /// bilinear (pixel centres aligned) when enlarging.
    pub fn resampled(&self, width: usize, height: usize) -> Image2 {
        self.resample_with(width, height, Enlarge::Linear)
    }

    fn resample_with(&self, width: usize, height: usize, enlarge: Enlarge) -> Image2 {
        if self.width == width && self.height == height {
            return self.clone();
        }
        if enlarge == Enlarge::Linear && (width > self.width || height > self.height) {
            return self.bilinear_to(width, height);
        }
        self.area_to(width, height)
    }

    /// Each output pixel the plain mean of the input pixels its footprint touches.
    fn area_to(&self, width: usize, height: usize) -> Image2 {
        let mut out = Image2::filled(width, height, self.channels, 0.0);
        let (sx, sy) = (
            self.width as f32 / width as f32,
            self.height as f32 / height as f32,
        );
        for r in 0..height {
            let (r0, r1) = span(r, sy, self.height);
            for c in 0..width {
                let (c0, c1) = span(c, sx, self.width);
                let n = ((r1 - r0) * (c1 - c0)) as f32;
                let px = out.pixel_mut(r, c);
                for rr in r0..r1 {
                    for cc in c0..c1 {
                        for (o, v) in px.iter_mut().zip(self.pixel(rr, cc)) {
                            *o += v / n;
                        }
                    }
                }
            }
        }
        out
    }

    /// Bilinear interpolation at each output pixel's centre (pixel centres aligned, clamped
    /// at the border by [`Image2::bilinear`]).
    fn bilinear_to(&self, width: usize, height: usize) -> Image2 {
        let mut out = Image2::filled(width, height, self.channels, 0.0);
        let sy = self.height as f32 / height as f32;
        let sx = self.width as f32 / width as f32;
        for r in 0..height {
            for c in 0..width {
                let (y, x) = ((r as f32 + 0.5) * sy - 0.5, (c as f32 + 0.5) * sx - 0.5);
                for (ch, o) in out.pixel_mut(r, c).iter_mut().enumerate() {
                    *o = self.bilinear(y, x, ch);
                }
            }
        }
        out
    }
}

/// Input index range `[lo, hi)` touched by output index `i` at `scale` input pixels per
/// output pixel (at least one pixel).
fn span(i: usize, scale: f32, len: usize) -> (usize, usize) {
    let lo = ((i as f32 * scale).floor() as usize).min(len - 1);
    let hi = (((i + 1) as f32 * scale).ceil() as usize).clamp(lo + 1, len);
    (lo, hi)
}
