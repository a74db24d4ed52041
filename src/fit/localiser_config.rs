//! Settings of the ring localiser (`[localiser]` of the fit config). Lengths are pixels at a
//! 256 px face and scale with the photo's side, so a 512 px photo is read at the same
//! physical scale.

use serde::{Deserialize, Serialize};

use crate::config::Checker;
use crate::error::Result;

/// The classical ring localiser's settings (see `rings::localise` for the steps).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LocaliserConfig {
    /// Width of the local mean and contrast the lightness is normalised by (lighting
    /// gradients, stains and colour differences between faces vanish below this scale).
    pub normalise_sigma: f32,
    /// Weight of the pore density subtracted from the normalised lightness before anything
    /// else (0: none). In ring-porous wood a ring is a band of *many* small dark pores, which
    /// the lightness alone reads as single dashes along the fibres; their local density is
    /// dark exactly on the band.
    pub pore_weight: f32,
    /// Width of the local mean a pixel must be darker than to count as pore.
    pub pore_highpass_sigma: f32,
    /// Width over which the pore pixels' darkness is averaged into a density.
    pub pore_density_sigma: f32,
    /// Smoothing before the gradient of the structure tensor.
    pub gradient_sigma: f32,
    /// Window of the structure tensor that gives the ring direction (several pores wide, so
    /// single pores do not turn it).
    pub window_sigma: f32,
    /// Half length of the average along the ring direction that turns rows of pores into
    /// bands.
    pub along_half: f32,
    /// Offsets across the rings at which the dark-valley response compares the band with
    /// its sides (a ring line is darker than the wood at these distances on both sides).
    pub valley_offsets: Vec<f32>,
    /// Half length of the second average along the rings, applied to the response (joins
    /// broken ring lines).
    pub response_along_half: f32,
    /// Blur of the response.
    pub response_sigma: f32,
    /// Percentile of the response mapped to black; below it nothing is a ring.
    pub low_percentile: f32,
    /// Percentile of the response mapped to white.
    pub high_percentile: f32,
    /// Width of the blur whose maximum with the lines widens them to bands as wide as the
    /// U-Net's (the fit reads the edges of thresholded bands).
    pub band_sigma: f32,
}

impl Default for LocaliserConfig {
    fn default() -> Self {
        Self {
            normalise_sigma: 16.0,
            pore_weight: 2.0,
            pore_highpass_sigma: 5.0,
            pore_density_sigma: 5.0,
            gradient_sigma: 1.5,
            window_sigma: 8.0,
            along_half: 12.0,
            valley_offsets: vec![2.0, 3.0, 4.0, 5.0],
            response_along_half: 6.0,
            response_sigma: 1.0,
            low_percentile: 80.0,
            high_percentile: 97.0,
            band_sigma: 4.0,
        }
    }
}

impl LocaliserConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        let px = "pixels at 256 px";
        check.range("normalise_sigma", self.normalise_sigma, 1.0, 256.0, px)?;
        check.range("pore_weight", self.pore_weight, 0.0, 16.0, "a weight")?;
        check.range(
            "pore_highpass_sigma",
            self.pore_highpass_sigma,
            0.5,
            64.0,
            px,
        )?;
        check.range("pore_density_sigma", self.pore_density_sigma, 0.5, 64.0, px)?;
        check.range("gradient_sigma", self.gradient_sigma, 0.0, 16.0, px)?;
        check.range("window_sigma", self.window_sigma, 0.5, 64.0, px)?;
        check.range("along_half", self.along_half, 0.0, 64.0, px)?;
        check.range(
            "response_along_half",
            self.response_along_half,
            0.0,
            64.0,
            px,
        )?;
        check.range("response_sigma", self.response_sigma, 0.0, 16.0, px)?;
        check.range("band_sigma", self.band_sigma, 0.0, 16.0, px)?;
        if self.valley_offsets.is_empty() {
            return Err(check.error(
                "valley_offsets",
                "is empty; expected offsets in pixels at 256 px such as [2.0, 3.0, 4.0, 5.0]",
            ));
        }
        for &o in &self.valley_offsets {
            check.range("valley_offsets", o, 0.5, 64.0, px)?;
        }
        check.range(
            "low_percentile",
            self.low_percentile,
            0.0,
            99.0,
            "a percentile",
        )?;
        check.range(
            "high_percentile",
            self.high_percentile,
            self.low_percentile + 0.5,
            100.0,
            "a percentile above low_percentile",
        )
    }
}
