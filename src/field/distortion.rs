//! Seeded random rate grids: smooth, azimuthally periodic variations of the growth rate that
//! turn circular rings into the wavy, uneven rings of real wood.
//!
//! log R is a random Fourier series over (height, azimuth, radius) with amplitudes falling as
//! 1 / (1 + frequency), normalised to the requested standard deviation over the grid nodes.

use std::f32::consts::{PI, TAU};

use super::config::DistortionConfig;
use crate::rng::Rng;

/// The relative rates (flat, `(ih * n_a + ia) * n_r + ir`) for a grid of `[n_h, n_a, n_r]`.
pub(crate) fn random_rates(cfg: &DistortionConfig, [n_h, n_a, n_r]: [usize; 3]) -> Vec<f32> {
    let mut rng = Rng::substream(cfg.seed, 0x6469_7374); // "dist"
    let mut log_rate = vec![0.0f32; n_h * n_a * n_r];
    for wh in 0..=cfg.height_waves {
        for wa in 0..=cfg.azimuthal_waves {
            for wr in 0..=cfg.radial_waves {
                if wh + wa + wr == 0 {
                    continue; // a constant term only rescales time
                }
                let amp = rng.normal() / (1.0 + (wh + wa + wr) as f32);
                let (ph, pa, pr) = (
                    rng.range(0.0, TAU),
                    rng.range(0.0, TAU),
                    rng.range(0.0, TAU),
                );
                for ih in 0..n_h {
                    let th = (wh as f32 * PI * ih as f32 / (n_h.max(2) - 1) as f32 + ph).cos();
                    for ia in 0..n_a {
                        let ta = (wa as f32 * TAU * ia as f32 / n_a as f32 + pa).cos();
                        for ir in 0..n_r {
                            let tr = (wr as f32 * PI * ir as f32 / (n_r - 1) as f32 + pr).cos();
                            log_rate[(ih * n_a + ia) * n_r + ir] += amp * th * ta * tr;
                        }
                    }
                }
            }
        }
    }
    let n = log_rate.len() as f32;
    let mean = log_rate.iter().sum::<f32>() / n;
    let std = (log_rate.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / n).sqrt();
    let scale = if std > 1e-12 {
        cfg.amplitude / std
    } else {
        0.0
    };
    log_rate
        .iter()
        .map(|v| ((v - mean) * scale).exp())
        .collect()
}
