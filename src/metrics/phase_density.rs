//! Pore density by ring phase: where in the ring the dark pores sit. Wood is ring-porous
//! (chestnut, oak: pores crowd the earlywood at the start of each ring), semi-ring- or
//! diffuse-porous; a texture that scatters pores evenly has a flat curve. Comparing a
//! texture's curve with the photo's says whether its pores are in the right part of the ring
//! whatever their exact places.
//!
//! Per pixel: the ring phase frac(G) from the growth field on the same plane (G in years,
//! rings at whole years), and whether it is a pore: its high-passed lightness (see
//! [`super::anisotropy::high_passed_lightness`]) is more than `PORE_DEPTH` Lab L below its
//! surroundings. The curve is the fraction of pore pixels in each of `bins` equal phase bins.

use super::anisotropy::high_passed_lightness;
use crate::error::{Result, XylemError};
use crate::image2::Image2;

/// Lightness drop (Lab L units) below the blurred surroundings that makes a pixel a pore.
pub const PORE_DEPTH: f32 = 8.0;

/// Pore and pixel counts per phase bin of one or more images, to pool several faces.
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseDensity {
    pores: Vec<f64>,
    pixels: Vec<f64>,
}

impl PhaseDensity {
    pub fn new(bins: usize) -> Self {
        Self {
            pores: vec![0.0; bins.max(1)],
            pixels: vec![0.0; bins.max(1)],
        }
    }

    /// Adds an RGB image and its growth-field map (1 channel, G in years, any size: it is
    /// resampled to the image's 256 px measuring size).
    pub fn add(&mut self, image: &Image2, growth: &Image2) -> Result<()> {
        let hp = high_passed_lightness(image);
        if growth.channels != 1 || growth.width == 0 || growth.height == 0 {
            return Err(XylemError::input(
                "phase density",
                format!(
                    "growth map of {}x{}x{}; expected one channel of G",
                    growth.width, growth.height, growth.channels
                ),
            ));
        }
        let g = if (growth.width, growth.height) == (hp.width, hp.height) {
            growth.clone()
        } else {
            growth.resized(hp.width, hp.height)
        };
        let bins = self.pores.len();
        for (&l, &t) in hp.data.iter().zip(&g.data) {
            let b = ((t.rem_euclid(1.0) * bins as f32) as usize).min(bins - 1);
            self.pixels[b] += 1.0;
            if l < -PORE_DEPTH {
                self.pores[b] += 1.0;
            }
        }
        Ok(())
    }

    /// Fraction of pore pixels per bin (0 where a bin has no pixels).
    pub fn curve(&self) -> Vec<f32> {
        self.pores
            .iter()
            .zip(&self.pixels)
            .map(|(p, n)| if *n > 0.0 { (p / n) as f32 } else { 0.0 })
            .collect()
    }
}

/// Pearson correlation of two pore-density curves (0 if either is flat).
pub use crate::series::pearson as curve_correlation;

/// Least-squares slope of curve `a` on the `reference` curve (0 if the reference is flat).
/// The correlation says whether a texture's pores sit at the right ring phases; the slope
/// says how strongly: 1 when its pore density rises and falls over the ring as much as the
/// reference's, under 1 when it also scatters pores where the reference's ring is clean
/// (faint pore bands), over 1 when its bands are starker.
pub use crate::series::slope as curve_slope;
