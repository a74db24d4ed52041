//! The ring localiser: a face photo in, a ring-localisation image out, in the encoding of the
//! Mokume U-Net's `X_arl-unet.png` (bright bands on the rings, dark elsewhere).
//!
//! A classical detector (issue 13; the alternatives tried are in BENCHMARKS "Ring
//! localisation"). On every face of every wood we looked at, softwood or hardwood, side or
//! end grain, the ring line is a dark band: the latewood of a softwood, the row of big
//! earlywood pores of a ring-porous hardwood. So:
//! 1. the Lab lightness, normalised by its local mean and contrast (lighting gradients,
//!    stains and the colour of the wood drop out), minus the local density of dark pores:
//!    on a flat-sawn chestnut face the ring is an oblique band of many short dashes that run
//!    along the fibres, and without the density the structure tensor follows the dashes;
//! 2. the ring direction per pixel from the structure tensor of that lightness;
//! 3. an average along the ring direction, which turns rows of pores into bands and removes
//!    the fibres' fine streaks across them;
//! 4. the dark-valley response across the rings: the mean of the averaged lightness at a few
//!    offsets on both sides minus its value at the pixel (positive on a dark line, whichever
//!    way the pith lies, so the unknown sign of the direction does not matter);
//! 5. the response averaged along the rings once more and blurred, then mapped to [0, 1]
//!    between two percentiles of the face (the ring share of a face is similar on every
//!    face, its contrast is not), and widened to bands as wide as the U-Net's.

use crate::fit::localiser_config::LocaliserConfig;
use crate::image_filter::{gaussian_blur, structure_tensor};
use crate::image2::Image2;
use crate::metrics::lab::image_to_lab;

/// Side at which the config's pixel lengths hold.
const REFERENCE_SIDE: f32 = 256.0;
/// Keeps the contrast normalisation finite on flat photos.
const CONTRAST_FLOOR: f32 = 1e-6;

/// The ring-localisation image (one channel, values in [0, 1]) of an RGB face photo.
pub fn localise(photo: &Image2, cfg: &LocaliserConfig) -> Image2 {
    let scale = photo.width as f32 / REFERENCE_SIDE;
    let light = normalised_lightness(photo, cfg.normalise_sigma * scale);
    let light = minus_pore_density(
        light,
        cfg.pore_weight,
        cfg.pore_highpass_sigma * scale,
        cfg.pore_density_sigma * scale,
    );
    let normals = ring_normals(&light, cfg.gradient_sigma * scale, cfg.window_sigma * scale);
    let bands = along_rings(&light, &normals, cfg.along_half * scale);
    let offsets: Vec<f32> = cfg.valley_offsets.iter().map(|o| o * scale).collect();
    let valley = valley_response(&bands, &normals, &offsets);
    let joined = along_rings(&valley, &normals, cfg.response_along_half * scale);
    let response = gaussian_blur(&joined, cfg.response_sigma * scale);
    let lines = percentile_map(&response, cfg.low_percentile, cfg.high_percentile);
    widen(&lines, cfg.band_sigma * scale)
}

/// Lab lightness / 100 minus its local mean, divided by its local standard deviation.
fn normalised_lightness(photo: &Image2, sigma: f32) -> Image2 {
    let mut light = image_to_lab(photo).channel(0);
    light.data.iter_mut().for_each(|v| *v /= 100.0);
    let mean = gaussian_blur(&light, sigma);
    let mut detail = light;
    for (v, m) in detail.data.iter_mut().zip(&mean.data) {
        *v -= m;
    }
    let mut square = detail.clone();
    square.data.iter_mut().for_each(|v| *v *= *v);
    let variance = gaussian_blur(&square, sigma);
    for (v, s) in detail.data.iter_mut().zip(&variance.data) {
        *v /= (s + CONTRAST_FLOOR).sqrt();
    }
    detail
}

/// `light` minus `weight` times the standardised density of dark detail (how much darker
/// than its `highpass_sigma` surroundings the wood is, averaged over `density_sigma`): a band
/// of many pores becomes one dark band.
fn minus_pore_density(
    light: Image2,
    weight: f32,
    highpass_sigma: f32,
    density_sigma: f32,
) -> Image2 {
    if weight == 0.0 {
        return light;
    }
    let mean = gaussian_blur(&light, highpass_sigma);
    let mut dark = light.clone();
    for (v, m) in dark.data.iter_mut().zip(&mean.data) {
        *v = (m - *v).max(0.0);
    }
    let density = gaussian_blur(&dark, density_sigma);
    let n = density.data.len() as f32;
    let average = density.data.iter().sum::<f32>() / n;
    let variance = density
        .data
        .iter()
        .map(|d| (d - average).powi(2))
        .sum::<f32>()
        / n;
    let spread = (variance + CONTRAST_FLOOR).sqrt();
    let mut out = light;
    for (v, d) in out.data.iter_mut().zip(&density.data) {
        *v -= weight * (d - average) / spread;
    }
    out
}

/// Per pixel the unit vector across the rings (x = column, y = row): the dominant gradient
/// direction of the structure tensor. Its sign is arbitrary.
fn ring_normals(light: &Image2, gradient_sigma: f32, window_sigma: f32) -> Vec<[f32; 2]> {
    let [jxx, jxy, jyy] = structure_tensor(light, gradient_sigma, window_sigma);
    (0..jxx.data.len())
        .map(|i| {
            let angle = 0.5 * (2.0 * jxy.data[i]).atan2(jxx.data[i] - jyy.data[i]);
            [angle.cos(), angle.sin()]
        })
        .collect()
}

/// The mean of `img` over the segment of half length `half` along the ring direction
/// (perpendicular to the normal) through each pixel, sampled every pixel.
fn along_rings(img: &Image2, normals: &[[f32; 2]], half: f32) -> Image2 {
    let steps = half.round() as i32;
    if steps == 0 {
        return img.clone();
    }
    let mut out = Image2::filled(img.width, img.height, 1, 0.0);
    for row in 0..img.height {
        for col in 0..img.width {
            let i = row * img.width + col;
            let [nx, ny] = normals[i];
            let (tx, ty) = (-ny, nx);
            let sum: f32 = (-steps..=steps)
                .map(|s| {
                    let s = s as f32;
                    img.bilinear(row as f32 + s * ty, col as f32 + s * tx, 0)
                })
                .sum();
            out.data[i] = sum / (2 * steps + 1) as f32;
        }
    }
    out
}

/// Mean over `offsets` of the values at +-offset across the rings, minus the pixel's value:
/// positive where the pixel is darker than both sides.
fn valley_response(bands: &Image2, normals: &[[f32; 2]], offsets: &[f32]) -> Image2 {
    let mut out = Image2::filled(bands.width, bands.height, 1, 0.0);
    for row in 0..bands.height {
        for col in 0..bands.width {
            let i = row * bands.width + col;
            let [nx, ny] = normals[i];
            let (r, c) = (row as f32, col as f32);
            let sides: f32 = offsets
                .iter()
                .map(|&k| {
                    bands.bilinear(r + k * ny, c + k * nx, 0)
                        + bands.bilinear(r - k * ny, c - k * nx, 0)
                })
                .sum();
            out.data[i] = sides / (2 * offsets.len()) as f32 - bands.data[i];
        }
    }
    out
}

/// Maps the `low` percentile of `img` to 0 and the `high` one to 1, clamped.
fn percentile_map(img: &Image2, low: f32, high: f32) -> Image2 {
    let mut sorted = img.data.clone();
    sorted.sort_by(f32::total_cmp);
    let at = |p: f32| {
        let k = ((p / 100.0) * (sorted.len() - 1) as f32).round() as usize;
        sorted[k.min(sorted.len() - 1)]
    };
    let (a, b) = (at(low), at(high));
    let span = (b - a).max(f32::MIN_POSITIVE);
    let mut out = img.clone();
    out.data
        .iter_mut()
        .for_each(|v| *v = ((*v - a) / span).clamp(0.0, 1.0));
    out
}

/// The per-pixel maximum of the lines and their blur: thin lines become bands.
fn widen(lines: &Image2, sigma: f32) -> Image2 {
    let blurred = gaussian_blur(lines, sigma);
    let mut out = lines.clone();
    for (v, b) in out.data.iter_mut().zip(&blurred.data) {
        *v = v.max(*b);
    }
    out
}
