//! Figure (Liu et al. 2016 section 4.5): a distortion f mapping a point of the real
//! (distorted) tree to the idealised tree where the model is evaluated,
//! f(p) = p + m_r(p) r + m_t(p) t, with r and t the unit radial and tangential directions around
//! the pith and m_r, m_t smooth noise. Radial displacement bends the rings (blister, quilted
//! figure); tangential displacement leaves the rings and bends the fibres (curly figure). Short
//! wavelengths along the grain with long ones across give the ripples of fiddleback figure.
//!
//! The fibre direction f implies is J_f^-1 applied to the idealised direction
//! (see [`super::direction`]).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::checks::check_sizes;
use super::noise::fbm3;
use super::tree::{TreePoint, radial_frame};
use crate::config::Checker;
use crate::error::Result;
use crate::field::PithAxis;
use crate::frame::mm;
use crate::rng::mix64;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FigureConfig {
    /// Amplitude of the radial displacement (mm).
    pub radial_mm: f32,
    /// Amplitude of the tangential displacement (mm).
    pub tangential_mm: f32,
    /// Wavelength of the displacement noise across the grain and along it (mm).
    pub wavelength_mm: [f32; 2],
    /// Octaves of the fractal noise.
    #[serde(default = "default_octaves")]
    pub octaves: u32,
}

fn default_octaves() -> u32 {
    2
}

impl FigureConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "radial_mm",
            self.radial_mm,
            0.0,
            100.0,
            "a displacement in mm",
        )?;
        check.range(
            "tangential_mm",
            self.tangential_mm,
            0.0,
            100.0,
            "a displacement in mm",
        )?;
        check_sizes(
            check,
            "wavelength_mm",
            self.wavelength_mm,
            10_000.0,
            "wavelengths",
        )?;
        check.count("octaves", self.octaves as usize, 1, 6, "octaves")
    }
}

#[derive(Clone, Debug)]
pub struct Figure {
    seed: u64,
    radial: f32,
    tangential: f32,
    scale: Vec3,
    octaves: u32,
}

impl Figure {
    pub fn new(cfg: &FigureConfig, seed: u64) -> Self {
        let across = 1.0 / mm(cfg.wavelength_mm[0]);
        Self {
            seed,
            radial: mm(cfg.radial_mm),
            tangential: mm(cfg.tangential_mm),
            scale: Vec3::new(across, across, 1.0 / mm(cfg.wavelength_mm[1])),
            octaves: cfg.octaves,
        }
    }

    /// f(p): the point of the idealised tree that `p` shows.
    #[inline]
    pub fn apply(&self, pith: &PithAxis, p: Vec3) -> Vec3 {
        let Some((radial, tangential)) = radial_frame(pith, p) else {
            return p;
        };
        let q = TreePoint::new(pith, p).frame_point() * self.scale;
        let m_r = self.radial * fbm3(mix64(self.seed ^ 0x52), q, self.octaves);
        let m_t = self.tangential * fbm3(mix64(self.seed ^ 0x54), q, self.octaves);
        p + m_r * radial + m_t * tangential
    }
}
