//! The fixed filter bank: random zero-mean RGB filters and oriented Gaussian-derivative
//! filters on luminance, per kernel size. Nothing here is trained; the bank is a function of
//! the config and its seed only.
//!
//! Why both: random filters respond to colour edges and arbitrary small patterns (pores,
//! speckle) with no built-in preference; oriented first and second derivatives respond to
//! the elongated structure wood is made of (ring edges, fibre streaks, ray flecks) at known
//! angles. Filters are zero-mean so a flat patch gives no response: the flat colour is the
//! colour term's business, and the features then describe structure only.

use burn::tensor::{Device, Tensor, TensorData};

use super::config::FilterConfig;
use crate::rng::Rng;

/// Rec. 709 luminance weights: oriented filters act on luminance.
pub(crate) const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// The two opponent colour axes (red-green, yellow-blue), orthogonal to grey.
fn opponent_axes() -> [[f32; 3]; 2] {
    let s2 = std::f32::consts::FRAC_1_SQRT_2;
    let s6 = 1.0 / 6f32.sqrt();
    [[s2, -s2, 0.0], [s6, s6, -2.0 * s6]]
}

/// One kernel size's filters.
#[derive(Clone, Debug)]
pub(crate) struct FilterBank {
    /// Kernel side (odd).
    pub size: usize,
    /// `[F, 3, k, k]`, each filter of unit L2 norm.
    pub weights: Tensor<4>,
}

/// Builds the banks of `cfg` on `device`, one per kernel size, seeded by `seed`.
pub(crate) fn filter_banks(cfg: &FilterConfig, seed: u64, device: &Device) -> Vec<FilterBank> {
    cfg.kernel_sizes
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            let mut rng = Rng::substream(seed, 0x4649_4c54 + i as u64);
            let mut data = Vec::new();
            for _ in 0..cfg.random {
                data.extend(random_filter(&mut rng, k, cfg.random_smoothing));
            }
            for o in 0..cfg.orientations {
                let angle = std::f32::consts::PI * o as f32 / cfg.orientations as f32;
                data.extend(oriented_filter(k, angle, 1, cfg.elongation));
                data.extend(oriented_filter(k, angle, 2, cfg.elongation));
            }
            let chroma = if cfg.chroma > 0.0 { 2 } else { 0 };
            for axis in opponent_axes().iter().take(chroma) {
                data.extend(chroma_filter(k, axis, cfg.chroma));
            }
            let count = cfg.random + 2 * cfg.orientations + chroma;
            FilterBank {
                size: k,
                weights: Tensor::from_data(TensorData::new(data, [count, 3, k, k]), device),
            }
        })
        .collect()
}

/// A random filter `[3, k, k]`: normal entries, each channel smoothed by a Gaussian of
/// `smoothing` px (none at 0) and made zero-mean, unit norm.
fn random_filter(rng: &mut Rng, k: usize, smoothing: f32) -> Vec<f32> {
    let mut w: Vec<f32> = (0..3 * k * k).map(|_| rng.normal()).collect();
    if smoothing > 0.0 {
        for channel in w.chunks_exact_mut(k * k) {
            smooth_in_window(channel, k, smoothing);
        }
    }
    if k > 1 {
        for channel in w.chunks_exact_mut(k * k) {
            let mean = channel.iter().sum::<f32>() / (k * k) as f32;
            channel.iter_mut().for_each(|v| *v -= mean);
        }
    }
    normalise(&mut w);
    w
}

/// The `order`-th (1 or 2) derivative of a Gaussian across direction `angle` (radians, from
/// the image's x axis), on luminance: `[3, k, k]`, zero-mean, unit norm. Sigma along the
/// filter's line is a quarter of the kernel side so the kernel holds +-2 sigma; across it
/// the sigma is that divided by `elongation` (at least half a pixel).
fn oriented_filter(k: usize, angle: f32, order: u32, elongation: f32) -> Vec<f32> {
    let r = (k as f32 - 1.0) / 2.0;
    let along = (k as f32 / 4.0).max(0.5);
    let sigma = (along / elongation).max(0.5);
    let (s, c) = angle.sin_cos();
    let mut base = vec![0.0f32; k * k];
    for (i, v) in base.iter_mut().enumerate() {
        let (y, x) = ((i / k) as f32 - r, (i % k) as f32 - r);
        let n = (x * c + y * s) / sigma;
        let t = (-x * s + y * c) / along;
        let g = (-(n * n + t * t) / 2.0).exp();
        *v = match order {
            1 => -n * g,
            _ => (n * n - 1.0) * g,
        };
    }
    on_colour_axis(&mut base, &LUMA)
}

/// A round second derivative of a Gaussian (sigma a quarter of the kernel side) on one colour
/// axis: `[3, k, k]`, zero-mean, of norm `norm`. Grey images give no response.
fn chroma_filter(k: usize, axis: &[f32; 3], norm: f32) -> Vec<f32> {
    let r = (k as f32 - 1.0) / 2.0;
    let sigma = (k as f32 / 4.0).max(0.5);
    let mut base: Vec<f32> = (0..k * k)
        .map(|i| {
            let (y, x) = ((i / k) as f32 - r, (i % k) as f32 - r);
            let q = (x * x + y * y) / (sigma * sigma);
            (q - 2.0) * (-q / 2.0).exp()
        })
        .collect();
    let mut w = on_colour_axis(&mut base, axis);
    w.iter_mut().for_each(|v| *v *= norm);
    w
}

/// A spatial kernel `[k, k]` made zero-mean and applied along one colour axis: `[3, k, k]`
/// of unit norm (channel c holds the kernel times `axis[c]`).
fn on_colour_axis(base: &mut [f32], axis: &[f32; 3]) -> Vec<f32> {
    let mean = base.iter().sum::<f32>() / base.len() as f32;
    base.iter_mut().for_each(|v| *v -= mean);
    let mut w: Vec<f32> = axis
        .iter()
        .flat_map(|a| base.iter().map(move |v| v * a))
        .collect();
    normalise(&mut w);
    w
}

/// Separable Gaussian smoothing of a `[k, k]` kernel inside its own window (taps falling
/// outside are dropped and the rest renormalised, so the edges keep their level).
fn smooth_in_window(kernel: &mut [f32], k: usize, sigma: f32) {
    let taps: Vec<f32> = (0..k)
        .map(|d| (-((d * d) as f32) / (2.0 * sigma * sigma)).exp())
        .collect();
    let along = |src: &[f32], at: &dyn Fn(usize, usize) -> usize| -> Vec<f32> {
        let mut out = vec![0.0f32; k * k];
        for line in 0..k {
            for i in 0..k {
                let (mut sum, mut weight) = (0.0f32, 0.0f32);
                for j in 0..k {
                    let t = taps[i.abs_diff(j)];
                    sum += t * src[at(line, j)];
                    weight += t;
                }
                out[at(line, i)] = sum / weight;
            }
        }
        out
    };
    let rows = along(kernel, &|line, i| line * k + i);
    let both = along(&rows, &|line, i| i * k + line);
    kernel.copy_from_slice(&both);
}

fn normalise(w: &mut [f32]) {
    let norm = w.iter().map(|v| v * v).sum::<f32>().sqrt().max(1e-12);
    w.iter_mut().for_each(|v| *v /= norm);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mean squared difference of horizontally neighbouring taps over the mean square:
    /// 2 for white noise, small for a smooth kernel.
    fn roughness(w: &[f32], k: usize) -> f32 {
        let (mut diff, mut power) = (0.0f32, 0.0f32);
        for row in w.chunks_exact(k) {
            for pair in row.windows(2) {
                diff += (pair[1] - pair[0]).powi(2);
            }
            power += row.iter().map(|v| v * v).sum::<f32>();
        }
        diff / power * (k as f32 / (k - 1) as f32)
    }

    #[test]
    fn smoothed_random_filters_are_smooth_zero_mean_and_of_unit_norm() {
        let k = 9;
        let draw = |smoothing| random_filter(&mut Rng::substream(7, 1), k, smoothing);
        let (white, smooth) = (draw(0.0), draw(1.0));
        let (rw, rs) = (roughness(&white, k), roughness(&smooth, k));
        assert!(rw > 1.0, "white noise roughness {rw}");
        assert!(rs < 0.5 * rw, "smoothed {rs} vs white {rw}");
        for w in [&white, &smooth] {
            let norm = w.iter().map(|v| v * v).sum::<f32>().sqrt();
            assert!((norm - 1.0).abs() < 1e-4, "norm {norm}");
            for channel in w.chunks_exact(k * k) {
                assert!(channel.iter().sum::<f32>().abs() < 1e-4, "channel mean");
            }
        }
    }
}
