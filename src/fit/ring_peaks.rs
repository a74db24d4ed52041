//! Ring iso-values from the peaks of the grey map M (Mokume 5.2.3: "apply a threshold and
//! extract the location of the centres of each detected area").
//!
//! Runs of nodes above min + threshold x (max - min) are rings; each ring sits at the centroid
//! of its run weighted by the height above the threshold. Runs touching either end of the map
//! are dropped: they are cut off by the data range, so their centroid would be biased (the
//! ring warp extrapolates past the last ring anyway). Where a ring was missed (a face region
//! without visible rings leaves a flat stretch of M), a gap wider than `gap_factor` median
//! spacings is filled with evenly spaced rings, so the ring count stays plausible.

use super::config::RingPeakConfig;

/// Ring positions in t (map coordinates in [0, 1]), increasing.
pub fn ring_peaks(map: &[f32], cfg: &RingPeakConfig) -> Vec<f32> {
    let n = map.len();
    let lo = map.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = map.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    if !(hi > lo) {
        return Vec::new();
    }
    let threshold = lo + cfg.threshold * (hi - lo);
    let mut peaks = Vec::new();
    let mut k = 0;
    while k < n {
        if map[k] < threshold {
            k += 1;
            continue;
        }
        let start = k;
        while k < n && map[k] >= threshold {
            k += 1;
        }
        if start == 0 || k == n {
            continue;
        }
        let (mut sum_w, mut sum_x) = (0.0f32, 0.0f32);
        for (j, &m) in map.iter().enumerate().take(k).skip(start) {
            let w = m - threshold + 1e-6;
            sum_w += w;
            sum_x += w * j as f32;
        }
        peaks.push(sum_x / sum_w / (n - 1) as f32);
    }
    fill_gaps(&peaks, cfg.gap_factor)
}

/// Median spacing of increasing positions (`None` with fewer than two).
pub fn median_spacing(peaks: &[f32]) -> Option<f32> {
    let gaps: Vec<f32> = peaks.windows(2).map(|w| w[1] - w[0]).collect();
    (!gaps.is_empty()).then(|| super::iso_loss::median(&gaps))
}

fn fill_gaps(peaks: &[f32], gap_factor: f32) -> Vec<f32> {
    let Some(spacing) = median_spacing(peaks) else {
        return peaks.to_vec();
    };
    let mut out = vec![peaks[0]];
    for w in peaks.windows(2) {
        let gap = w[1] - w[0];
        if gap > gap_factor * spacing {
            let parts = (gap / spacing).round().max(1.0) as usize;
            for j in 1..parts {
                out.push(w[0] + gap * j as f32 / parts as f32);
            }
        }
        out.push(w[1]);
    }
    out
}
