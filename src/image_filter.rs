//! The image filters shared by the metrics, the ring localiser and the fit: a separable
//! Gaussian blur of single-channel images (clamped borders), its gradient and the structure
//! tensor.

use crate::image2::Image2;

/// A normalised Gaussian kernel of standard deviation `sigma`, radius ceil(3 sigma).
fn kernel(sigma: f32) -> Vec<f32> {
    let r = (3.0 * sigma).ceil().max(1.0) as i32;
    let mut k: Vec<f32> = (-r..=r)
        .map(|i| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp())
        .collect();
    let sum: f32 = k.iter().sum();
    k.iter_mut().for_each(|v| *v /= sum);
    k
}

/// Gaussian blur of channel 0 of `img` (returned as one channel); `sigma <= 0` copies.
pub(crate) fn gaussian_blur(img: &Image2, sigma: f32) -> Image2 {
    let src = img.channel(0);
    if sigma <= 0.0 {
        return src;
    }
    let k = kernel(sigma);
    separable(&src, &k, &k)
}

/// The gradient (d/dx along columns, d/dy along rows) of channel 0 of `img` blurred by a
/// Gaussian of `sigma` px, by derivative-of-Gaussian kernels. Unlike central differences of a
/// blurred image this has no direction bias near the pixel scale (central differences tilt
/// fine dashes 2-4 degrees towards the diagonals).
pub(crate) fn gaussian_gradient(img: &Image2, sigma: f32) -> [Image2; 2] {
    let src = img.channel(0);
    let k = kernel(sigma.max(0.3));
    let r = (k.len() / 2) as f32;
    let sigma2 = sigma.max(0.3).powi(2);
    // Correlation kernel of d/dx (G * I): (j / sigma^2) G(j) at offset j.
    let dk: Vec<f32> = k
        .iter()
        .enumerate()
        .map(|(i, g)| (i as f32 - r) / sigma2 * g)
        .collect();
    [separable(&src, &dk, &k), separable(&src, &k, &dk)]
}

/// Correlates a one-channel image with `along_x` over columns, then `along_y` over rows (odd
/// lengths, centred; clamped borders).
fn separable(src: &Image2, along_x: &[f32], along_y: &[f32]) -> Image2 {
    let (w, h) = (src.width, src.height);
    let rows_done = correlate_lines(&src.data, w, h, along_x, true);
    Image2 {
        width: w,
        height: h,
        channels: 1,
        data: correlate_lines(&rows_done, w, h, along_y, false),
    }
}

/// Correlates every line of a `w` x `h` grid with `kernel` (odd length, centred; clamped
/// borders): the rows when `along_x`, else the columns. Visits pixels in memory order.
fn correlate_lines(data: &[f32], w: usize, h: usize, kernel: &[f32], along_x: bool) -> Vec<f32> {
    let r = (kernel.len() / 2) as isize;
    let mut out = vec![0.0f32; data.len()];
    for y in 0..h {
        for x in 0..w {
            // Position along the line, its length, its first pixel and the step between pixels.
            let (p, len, first, step) = if along_x {
                (x, w, y * w, 1)
            } else {
                (y, h, x, w)
            };
            let mut acc = 0.0;
            for (i, kv) in kernel.iter().enumerate() {
                let q = (p as isize + i as isize - r).clamp(0, len as isize - 1) as usize;
                acc += kv * data[first + q * step];
            }
            out[y * w + x] = acc;
        }
    }
    out
}

/// `img`'s channel 0 minus its Gaussian blur of `sigma` px: the fine texture (pores, fibre
/// streaks) without the ring-scale shading.
pub(crate) fn high_pass(img: &Image2, sigma: f32) -> Image2 {
    let low = gaussian_blur(img, sigma);
    let mut fine = img.channel(0);
    for (v, l) in fine.data.iter_mut().zip(&low.data) {
        *v -= l;
    }
    fine
}

/// The structure tensor (Jxx, Jxy, Jyy) of a one-channel image: central differences of the
/// image blurred by `pre_sigma`, products blurred by `tensor_sigma` (both in pixels).
pub(crate) fn structure_tensor(img: &Image2, pre_sigma: f32, tensor_sigma: f32) -> [Image2; 3] {
    let lum = gaussian_blur(img, pre_sigma);
    let (w, h) = (lum.width, lum.height);
    let at = |x: usize, y: usize| lum.data[y * w + x];
    let mut jxx = Image2::filled(w, h, 1, 0.0);
    let mut jxy = Image2::filled(w, h, 1, 0.0);
    let mut jyy = Image2::filled(w, h, 1, 0.0);
    for y in 0..h {
        for x in 0..w {
            let gx = (at((x + 1).min(w - 1), y) - at(x.saturating_sub(1), y)) * 0.5;
            let gy = (at(x, (y + 1).min(h - 1)) - at(x, y.saturating_sub(1))) * 0.5;
            let i = y * w + x;
            jxx.data[i] = gx * gx;
            jxy.data[i] = gx * gy;
            jyy.data[i] = gy * gy;
        }
    }
    [
        gaussian_blur(&jxx, tensor_sigma),
        gaussian_blur(&jxy, tensor_sigma),
        gaussian_blur(&jyy, tensor_sigma),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_gradient_of_a_ramp_is_its_slope() {
        // I = 0.3 x + 0.1 y (x columns, y rows), read away from the clamped borders.
        let mut img = Image2::filled(32, 32, 1, 0.0);
        for r in 0..32 {
            for c in 0..32 {
                img.pixel_mut(r, c)[0] = 0.3 * c as f32 + 0.1 * r as f32;
            }
        }
        let [gx, gy] = gaussian_gradient(&img, 0.7);
        assert!(
            (gx.get(16, 16, 0) - 0.3).abs() < 1e-3,
            "{}",
            gx.get(16, 16, 0)
        );
        assert!(
            (gy.get(16, 16, 0) - 0.1).abs() < 1e-3,
            "{}",
            gy.get(16, 16, 0)
        );
    }
}
