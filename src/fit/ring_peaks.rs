//! Ring iso-values from the peaks of a grey map over G (Mokume 5.2.3: "apply a threshold and
//! extract the location of the centres of each detected area").
//!
//! A decision: the map whose peaks are read is not the optimised M itself but M refitted at
//! a fine resolution once G is fixed: the mean ring-image grey of all face pixels binned by
//! their G ([`profile_peaks`], 16 bins per year). The optimised M has 128 nodes over the
//! cube's range of G, about 7 per year, while a sharp ring is a tenth of a year wide; its
//! peaks then sit up to a node away from the rings, which shifts every fitted ring by a
//! visible fraction of a ring width. Binned means are the least-squares M for the fitted G
//! and resolve the ring centres to a sixteenth of a year.
//!
//! Runs of nodes above min + threshold x (max - min) are rings; each ring sits at the centroid
//! of its run weighted by the height above the threshold. Runs touching either end of the map
//! are dropped: they are cut off by the data range, so their centroid would be biased (the
//! ring warp extrapolates past the last ring anyway). Where a ring was missed (a face region
//! without visible rings leaves a flat stretch of M), a gap wider than `gap_factor` median
//! spacings is filled with evenly spaced rings, so the ring count stays plausible.

use super::config::RingPeakConfig;
use super::grey_map::{GRange, binned_means};

/// Ring positions in t (map coordinates in [0, 1]), increasing.
pub fn ring_peaks(map: &[f32], cfg: &RingPeakConfig) -> Vec<f32> {
    let n = map.len();
    let lo = map.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = map.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
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
pub(crate) fn median_spacing(peaks: &[f32]) -> Option<f32> {
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

/// Ring positions, in the units of `values`, from grey `targets` (ring images) binned by
/// `values` (G, or r) into `bins` bins and lightly smoothed (3-bin box).
pub fn profile_peaks(
    values: &[f32],
    targets: &[f32],
    bins: usize,
    cfg: &RingPeakConfig,
) -> Vec<f32> {
    let range = GRange::of(values, 0.0);
    if range.hi.partial_cmp(&range.lo) != Some(std::cmp::Ordering::Greater) {
        return Vec::new();
    }
    let ts: Vec<f32> = values.iter().map(|&v| range.t(v)).collect();
    let profile = box3(&binned_means(&ts, targets, bins.max(4)));
    ring_peaks(&profile, cfg)
        .into_iter()
        .map(|t| range.g(t))
        .collect()
}

fn box3(v: &[f32]) -> Vec<f32> {
    (0..v.len())
        .map(|i| {
            let lo = i.saturating_sub(1);
            let hi = (i + 1).min(v.len() - 1);
            v[lo..=hi].iter().sum::<f32>() / (hi - lo + 1) as f32
        })
        .collect()
}
