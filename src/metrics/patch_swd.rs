//! Patch texture distance (`swd`, `swd_L`, `swd_chroma`): the sliced Wasserstein distance
//! between the distributions of small Lab patches of two images, at two scales (the image and
//! its 2x2 average), averaged. Lab is divided by 100, so distances are in Delta E / 100.
//!
//! Each random projection direction is pooled with its horizontally, vertically and doubly
//! flipped copies into one 1D distribution. The distance therefore ignores mirror images
//! (a flipped copy of a wood has exactly the texture distance of the wood itself): where the
//! grain points is measured by `orient` and where the rings lie by `ring_ncc`, and this metric
//! is left to say whether the pores, streaks and speckle are the same. Patches are taken on a
//! grid symmetric under flips, so the invariance is exact.
//!
//! `swd_L` uses lightness patches only and `swd_chroma` the (a, b) patches only, so colour
//! speckle that leaves lightness right shows in the chroma distance alone.

use rayon::prelude::*;

use crate::image2::Image2;
use crate::rng::Rng;

/// Which Lab channels the patches hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchChannels {
    /// L, a and b.
    All,
    /// L only.
    Lightness,
    /// a and b.
    Chroma,
}

impl PatchChannels {
    fn indices(self) -> &'static [usize] {
        match self {
            PatchChannels::All => &[0, 1, 2],
            PatchChannels::Lightness => &[0],
            PatchChannels::Chroma => &[1, 2],
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct PatchSwdSettings {
    /// Patch side (pixels).
    pub patch: usize,
    /// Random directions (each pooled with its 3 mirror images).
    pub projections: usize,
    /// Patches per image and scale at most (a symmetric grid subsample).
    pub max_patches: usize,
    /// Quantiles compared per direction.
    pub quantiles: usize,
    pub seed: u64,
}

impl Default for PatchSwdSettings {
    fn default() -> Self {
        Self {
            patch: 5,
            projections: 32,
            max_patches: 4096,
            quantiles: 256,
            seed: 17,
        }
    }
}

/// The distance between two Lab images (any sizes), averaged over two scales.
pub fn patch_swd(
    reference: &Image2,
    candidate: &Image2,
    channels: PatchChannels,
    settings: &PatchSwdSettings,
) -> f32 {
    let half = |img: &Image2| img.resized((img.width / 2).max(1), (img.height / 2).max(1));
    let fine = scale_distance(reference, candidate, channels, settings, 0);
    let coarse = scale_distance(&half(reference), &half(candidate), channels, settings, 1);
    0.5 * (fine + coarse)
}

fn scale_distance(
    a: &Image2,
    b: &Image2,
    channels: PatchChannels,
    settings: &PatchSwdSettings,
    stream: u64,
) -> f32 {
    let k = settings.patch;
    let ch = channels.indices();
    let pa = patches(a, k, ch, settings.max_patches);
    let pb = patches(b, k, ch, settings.max_patches);
    if pa.is_empty() || pb.is_empty() {
        return f32::NAN;
    }
    let dim = k * k * ch.len();
    let mut rng = Rng::substream(settings.seed, stream);
    let directions: Vec<Vec<f32>> = (0..settings.projections)
        .map(|_| unit_vector(&mut rng, dim))
        .collect();
    let total: f64 = directions
        .par_iter()
        .map(|d| {
            let flips = mirror_images(d, k, ch.len());
            let qa = quantiles(pooled(&pa, dim, &flips), settings.quantiles);
            let qb = quantiles(pooled(&pb, dim, &flips), settings.quantiles);
            qa.iter()
                .zip(&qb)
                .map(|(x, y)| ((x - y) as f64).powi(2))
                .sum::<f64>()
        })
        .sum();
    (total / (settings.projections * settings.quantiles) as f64).sqrt() as f32
}

fn unit_vector(rng: &mut Rng, dim: usize) -> Vec<f32> {
    let v: Vec<f32> = (0..dim).map(|_| rng.normal()).collect();
    let n = v.iter().map(|x| x * x).sum::<f32>().sqrt().max(1e-12);
    v.into_iter().map(|x| x / n).collect()
}

/// Patch positions along an axis of length `len`: at most `count`, symmetric under
/// `x -> len - k - x`.
fn grid(len: usize, k: usize, count: usize) -> Vec<usize> {
    let last = len - k;
    let m = count.clamp(1, last + 1);
    if m == 1 {
        return vec![last / 2];
    }
    (0..m)
        .map(|i| ((i * last) as f64 / (m - 1) as f64).round() as usize)
        .collect()
}

/// Patches `[n, k, k, c]` (row, column, channel) of the Lab channels `ch`, divided by 100.
fn patches(img: &Image2, k: usize, ch: &[usize], max: usize) -> Vec<f32> {
    if img.width < k || img.height < k {
        return Vec::new();
    }
    let per_axis = (max as f64).sqrt().floor() as usize;
    let xs = grid(img.width, k, per_axis);
    let ys = grid(img.height, k, per_axis);
    let mut out = Vec::with_capacity(xs.len() * ys.len() * k * k * ch.len());
    for &y in &ys {
        for &x in &xs {
            for r in 0..k {
                for c in 0..k {
                    for &channel in ch {
                        out.push(img.get(y + r, x + c, channel) / 100.0);
                    }
                }
            }
        }
    }
    out
}

/// A direction and its mirror images (flipped columns, rows, both).
fn mirror_images(d: &[f32], k: usize, c: usize) -> [Vec<f32>; 4] {
    let flip = |rows: bool, cols: bool| {
        let mut out = vec![0.0; d.len()];
        for r in 0..k {
            for col in 0..k {
                let (rr, cc) = (
                    if rows { k - 1 - r } else { r },
                    if cols { k - 1 - col } else { col },
                );
                for ch in 0..c {
                    out[(r * k + col) * c + ch] = d[(rr * k + cc) * c + ch];
                }
            }
        }
        out
    };
    [
        d.to_vec(),
        flip(false, true),
        flip(true, false),
        flip(true, true),
    ]
}

/// All patches projected on all four directions, sorted.
fn pooled(patches: &[f32], dim: usize, directions: &[Vec<f32>; 4]) -> Vec<f32> {
    let mut values: Vec<f32> = patches
        .chunks_exact(dim)
        .flat_map(|p| {
            directions
                .iter()
                .map(move |d| p.iter().zip(d).map(|(a, b)| a * b).sum::<f32>())
        })
        .collect();
    values.sort_unstable_by(f32::total_cmp);
    values
}

/// `q` quantiles (positions (i + 0.5) / q) of sorted values, linearly interpolated.
fn quantiles(sorted: Vec<f32>, q: usize) -> Vec<f32> {
    let m = sorted.len();
    (0..q)
        .map(|i| {
            let t = ((i as f64 + 0.5) * m as f64 / q as f64 - 0.5).clamp(0.0, (m - 1) as f64);
            let j = t.floor() as usize;
            let f = (t - j as f64) as f32;
            sorted[j] * (1.0 - f) + sorted[(j + 1).min(m - 1)] * f
        })
        .collect()
}
