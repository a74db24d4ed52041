//! Fibres: the long longitudinal cells that make wood look finely streaked along the grain
//! (Mokume appendix A.2.3: fibre size, strength, strength on latewood). Each fibre bundle is a
//! cell of the cross-section `size_mm` wide and `length_mm` long along the grain with its own
//! random pigment offset; value noise blends neighbouring cells, so side faces show fine
//! streaks and end grain a fine speckle.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::noise::value3;
use super::tree::TreePoint;
use crate::config::Checker;
use crate::error::Result;
use crate::frame::mm;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FibreConfig {
    /// Width of a fibre bundle across the grain (mm).
    pub size_mm: f32,
    /// Length along the grain over which a bundle's shade changes (mm).
    pub length_mm: f32,
    /// Amplitude of the log pigment exponent.
    pub strength: f32,
    /// How much weaker the fibres are in latewood (0 = same, 1 = none in latewood).
    #[serde(default)]
    pub latewood_factor: f32,
}

impl FibreConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range("size_mm", self.size_mm, 0.01, 10.0, "a width in mm")?;
        check.range("length_mm", self.length_mm, 0.05, 1000.0, "a length in mm")?;
        check.range("strength", self.strength, 0.0, 2.0, "a log exponent")?;
        check.range("latewood_factor", self.latewood_factor, 0.0, 1.0, "a share")
    }
}

#[derive(Clone, Debug)]
pub struct Fibres {
    seed: u64,
    scale: Vec3,
    strength: f32,
    latewood_factor: f32,
}

impl Fibres {
    pub fn new(cfg: &FibreConfig, seed: u64) -> Self {
        let across = 1.0 / mm(cfg.size_mm);
        Self {
            seed,
            scale: Vec3::new(across, across, 1.0 / mm(cfg.length_mm)),
            strength: cfg.strength,
            latewood_factor: cfg.latewood_factor,
        }
    }

    /// Fibre value in [-1, 1] at a tree point.
    #[inline]
    pub fn value(&self, t: &TreePoint) -> f32 {
        value3(self.seed, t.frame_point() * self.scale)
    }

    /// Log pigment offset of a fibre value at latewood weight `latewood`.
    #[inline]
    pub fn offset(&self, value: f32, latewood: f32) -> f32 {
        self.strength * value * (1.0 - self.latewood_factor * latewood)
    }
}
