//! CIE Lab colour (D65 white, sRGB input) and the colour metrics: the distance between the
//! mean colours (`dE_mean`, CIE76) and between the spreads (`dE_std`, the Euclidean norm of
//! the difference of the per-channel standard deviations), both in Delta E units.

use crate::image2::Image2;

/// D65 reference white in XYZ.
const WHITE: [f32; 3] = [0.950_47, 1.0, 1.088_83];

fn srgb_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn lab_f(t: f32) -> f32 {
    const D: f32 = 6.0 / 29.0;
    if t > D * D * D {
        t.cbrt()
    } else {
        t / (3.0 * D * D) + 4.0 / 29.0
    }
}

/// One sRGB colour (components in [0, 1], clamped) as Lab (L in [0, 100]).
pub fn srgb_to_lab(rgb: [f32; 3]) -> [f32; 3] {
    let [r, g, b] = rgb.map(srgb_to_linear);
    let x = 0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b;
    let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175 * b;
    let z = 0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b;
    let [fx, fy, fz] = [x / WHITE[0], y / WHITE[1], z / WHITE[2]].map(lab_f);
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// An RGB (or grey) image as a 3-channel Lab image.
pub(crate) fn image_to_lab(img: &Image2) -> Image2 {
    let rgb = img.with_channels(3);
    let data = rgb
        .data
        .chunks_exact(3)
        .flat_map(|p| srgb_to_lab([p[0], p[1], p[2]]))
        .collect();
    Image2 {
        width: img.width,
        height: img.height,
        channels: 3,
        data,
    }
}

/// Mean and standard deviation of each Lab channel.
pub(crate) fn lab_stats(lab: &Image2) -> ([f32; 3], [f32; 3]) {
    let n = (lab.width * lab.height).max(1) as f64;
    let mut sum = [0f64; 3];
    let mut sq = [0f64; 3];
    for px in lab.data.chunks_exact(3) {
        for c in 0..3 {
            sum[c] += px[c] as f64;
            sq[c] += (px[c] as f64) * (px[c] as f64);
        }
    }
    let mean = sum.map(|s| s / n);
    let std = [0, 1, 2].map(|c| (sq[c] / n - mean[c] * mean[c]).max(0.0).sqrt() as f32);
    (mean.map(|m| m as f32), std)
}

/// `(dE_mean, dE_std)` between two Lab images.
pub(crate) fn colour_differences(reference: &Image2, candidate: &Image2) -> (f32, f32) {
    let (m1, s1) = lab_stats(reference);
    let (m2, s2) = lab_stats(candidate);
    let dist = |a: [f32; 3], b: [f32; 3]| {
        a.iter()
            .zip(&b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f32>()
            .sqrt()
    };
    (dist(m1, m2), dist(s1, s2))
}
