//! Separable Gaussian blur of single-channel images (clamped borders), the one filter the
//! ring and orientation metrics need.

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
pub fn gaussian_blur(img: &Image2, sigma: f32) -> Image2 {
    let src = img.channel(0);
    if sigma <= 0.0 {
        return src;
    }
    let k = kernel(sigma);
    let r = (k.len() / 2) as isize;
    let (w, h) = (src.width as isize, src.height as isize);
    let mut tmp = vec![0.0f32; src.data.len()];
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, kv) in k.iter().enumerate() {
                let xx = (x + i as isize - r).clamp(0, w - 1);
                acc += kv * src.data[(y * w + xx) as usize];
            }
            tmp[(y * w + x) as usize] = acc;
        }
    }
    let mut out = vec![0.0f32; src.data.len()];
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, kv) in k.iter().enumerate() {
                let yy = (y + i as isize - r).clamp(0, h - 1);
                acc += kv * tmp[(yy * w + x) as usize];
            }
            out[(y * w + x) as usize] = acc;
        }
    }
    Image2 {
        width: src.width,
        height: src.height,
        channels: 1,
        data: out,
    }
}
