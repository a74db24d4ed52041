//! The ring warp: a monotone piecewise-linear remapping of the stem time so that listed ring
//! positions land on integer years.
//!
//! A fitted growth field (`xylem fit`) knows where the annual rings are only as iso-values of
//! its raw stem time, which are not evenly spaced (Mokume 5.2.3 reads them off the peaks of
//! the grey map M). Warping G through these values makes every consumer of the field (the
//! ring image I(G), colour bars over G, the procedural model's ring phase) see the fitted
//! rings at whole years without knowing about the fit. Below the first ring the warp is the
//! straight line from (0, 0) to the first ring, so G stays 0 on the pith; beyond the last ring
//! it continues with the mean ring spacing.

use super::config::RingsConfig;

#[derive(Clone, Debug, PartialEq)]
pub struct RingWarp {
    /// Raw stem times of consecutive rings, strictly increasing, first > 0.
    at: Vec<f32>,
    first_year: f32,
    /// Mean raw spacing between consecutive rings (extrapolation beyond the last one).
    mean_spacing: f32,
}

impl RingWarp {
    /// The warp of a validated `[growth.rings]` section.
    pub fn new(cfg: &RingsConfig) -> Self {
        let first_year = cfg.first_year as f32;
        let n = cfg.at.len();
        let mean_spacing = if n >= 2 {
            (cfg.at[n - 1] - cfg.at[0]) / (n - 1) as f32
        } else {
            cfg.at[0] / first_year
        };
        Self {
            at: cfg.at.clone(),
            first_year,
            mean_spacing,
        }
    }

    /// The warped time (years) of a raw stem time.
    pub fn apply(&self, g: f32) -> f32 {
        let first = self.at[0];
        if g <= first {
            return g * self.first_year / first;
        }
        let last = self.at.len() - 1;
        if g >= self.at[last] {
            return self.first_year + last as f32 + (g - self.at[last]) / self.mean_spacing;
        }
        // The ring just below g: at[i] <= g < at[i + 1].
        let i = self.at.partition_point(|&a| a <= g) - 1;
        self.first_year + i as f32 + (g - self.at[i]) / (self.at[i + 1] - self.at[i])
    }

    /// d apply / d g at `g` (the warp's local slope), for converting raw-time tolerances.
    pub fn slope(&self, g: f32) -> f32 {
        let first = self.at[0];
        if g <= first {
            return self.first_year / first;
        }
        let last = self.at.len() - 1;
        if g >= self.at[last] {
            return 1.0 / self.mean_spacing;
        }
        let i = self.at.partition_point(|&a| a <= g) - 1;
        1.0 / (self.at[i + 1] - self.at[i])
    }
}
