//! The loss curve as a small image (`loss.png`): loss per iteration on a log scale (grey
//! dots) and its running mean (dark line), on a white background with a light grid line per
//! decade. Drawn directly into an [`Image2`]; no plotting dependency for one picture.

use crate::image2::Image2;

const MARGIN: usize = 8;

/// Plots `values` (one per iteration) into a `width` x `height` RGB image.
pub(crate) fn loss_plot(values: &[f32], width: usize, height: usize) -> Image2 {
    let mut img = Image2::filled(width, height, 3, 1.0);
    let logs: Vec<f32> = values
        .iter()
        .map(|v| v.max(1e-12).log10())
        .filter(|v| v.is_finite())
        .collect();
    if logs.is_empty() || width <= 2 * MARGIN || height <= 2 * MARGIN {
        return img;
    }
    let lo = logs.iter().copied().fold(f32::INFINITY, f32::min).floor();
    let hi = logs
        .iter()
        .copied()
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil()
        .max(lo + 1.0);
    let (pw, ph) = (width - 2 * MARGIN, height - 2 * MARGIN);
    let to_row = |l: f32| MARGIN + ((hi - l) / (hi - lo) * (ph - 1) as f32).round() as usize;
    let to_col = |i: usize| MARGIN + i * (pw - 1) / logs.len().saturating_sub(1).max(1);
    let mut decade = lo;
    while decade <= hi {
        let r = to_row(decade);
        for c in MARGIN..width - MARGIN {
            img.pixel_mut(r, c).copy_from_slice(&[0.85, 0.85, 0.9]);
        }
        decade += 1.0;
    }
    for (i, &l) in logs.iter().enumerate() {
        let (r, c) = (to_row(l), to_col(i));
        for (dr, dc) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            if r + dr < height && c + dc < width {
                img.pixel_mut(r + dr, c + dc)
                    .copy_from_slice(&[0.5, 0.5, 0.5]);
            }
        }
    }
    let window = (logs.len() / 20).max(1);
    let mut prev: Option<(usize, usize)> = None;
    for i in 0..logs.len() {
        let from = i.saturating_sub(window - 1);
        let mean = logs[from..=i].iter().sum::<f32>() / (i + 1 - from) as f32;
        let point = (to_row(mean), to_col(i));
        if let Some(p) = prev {
            line(&mut img, p, point, [0.1, 0.2, 0.6]);
        }
        prev = Some(point);
    }
    img
}

/// A straight line between two pixels (simple DDA).
fn line(img: &mut Image2, a: (usize, usize), b: (usize, usize), colour: [f32; 3]) {
    let (dr, dc) = (b.0 as f32 - a.0 as f32, b.1 as f32 - a.1 as f32);
    let n = dr.abs().max(dc.abs()).max(1.0) as usize;
    for s in 0..=n {
        let t = s as f32 / n as f32;
        let r = (a.0 as f32 + t * dr).round() as usize;
        let c = (a.1 as f32 + t * dc).round() as usize;
        if r < img.height && c < img.width {
            img.pixel_mut(r, c).copy_from_slice(&colour);
        }
    }
}
