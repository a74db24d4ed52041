//! Pigment: the Beer's-law colour model of Liu et al. 2016 section 4.3. All colours of a
//! point are read as c = base^(exp(delta)): `base` is the ring colour, `delta` a sum of small
//! log-exponent offsets (per-year variation, 3D noise, fibres, knot darkening). Modulating the
//! optical depth rather than the colour keeps every variation on the same absorption curve, so
//! darker wood also gets more saturated, as real wood does. Because a power law commutes with
//! the display gamma, the exponent acts the same on display-referred values.
//!
//! This file holds the small 3D noise term: gradient noise in tree space, stretched along the
//! grain so it reads as streaky colour variation on side faces and blotches on end grain.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::noise::fbm3;
use super::tree::TreePoint;
use crate::config::Checker;
use crate::error::Result;
use crate::frame::mm;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PigmentConfig {
    /// Amplitude of the log pigment exponent (0.1: about +-10% optical depth).
    pub amplitude: f32,
    /// Feature size across the grain (mm).
    pub scale_mm: f32,
    /// How many times longer the features are along the grain.
    #[serde(default = "default_stretch")]
    pub stretch: f32,
    /// Octaves of the fractal sum.
    #[serde(default = "default_octaves")]
    pub octaves: u32,
}

fn default_stretch() -> f32 {
    4.0
}
fn default_octaves() -> u32 {
    2
}

impl PigmentConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range("amplitude", self.amplitude, 0.0, 2.0, "a log exponent")?;
        check.range("scale_mm", self.scale_mm, 0.05, 1000.0, "a size in mm")?;
        check.range("stretch", self.stretch, 0.1, 100.0, "a ratio")?;
        check.count("octaves", self.octaves as usize, 1, 6, "octaves")
    }
}

/// The 3D noise term of the pigment exponent.
#[derive(Clone, Debug)]
pub(crate) struct PigmentNoise {
    seed: u64,
    amplitude: f32,
    /// Tree-space point to noise lattice: 1/scale across, 1/(scale stretch) along the grain.
    scale: Vec3,
    octaves: u32,
}

impl PigmentNoise {
    pub(crate) fn new(cfg: &PigmentConfig, seed: u64) -> Self {
        let across = 1.0 / mm(cfg.scale_mm);
        Self {
            seed,
            amplitude: cfg.amplitude,
            scale: Vec3::new(across, across, across / cfg.stretch),
            octaves: cfg.octaves,
        }
    }

    /// Log-exponent offset at a tree point.
    #[inline]
    pub(crate) fn offset(&self, t: &TreePoint) -> f32 {
        self.amplitude * fbm3(self.seed, t.frame_point() * self.scale, self.octaves)
    }
}

/// Applies a log pigment exponent to a base colour: base^(exp(delta)).
#[inline]
pub fn absorb(base: Vec3, delta: f32) -> Vec3 {
    if delta == 0.0 {
        return base;
    }
    let e = delta.exp();
    let c = base.max(Vec3::splat(1e-4));
    Vec3::new(c.x.powf(e), c.y.powf(e), c.z.powf(e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn more_pigment_is_darker_and_more_saturated() {
        let base = Vec3::new(0.8, 0.6, 0.4);
        let dark = absorb(base, 0.5);
        assert!(dark.x < base.x && dark.z < base.z);
        assert!(dark.x / dark.z > base.x / base.z, "ratio grows with depth");
        assert_eq!(absorb(base, 0.0), base);
    }
}
