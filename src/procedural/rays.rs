//! Rays: ribbons of cells running outwards along the radius (Liu et al. 2016 section 4.6).
//!
//! One ray at most per cylindrical cell (see [`super::cells`]), an ellipsoid `size_mm[0]` long
//! along the radius, `size_mm[1]` wide around the stem and `size_mm[2]` tall along the grain,
//! weighted by Wyvill's kernel of the anisotropic distance. A ray's centre may lie anywhere in
//! its shell and the ray may be longer than the shell, so a point also looks at the shells
//! within half a ray length; rays then start and end at random radii instead of leaving
//! common gaps. On end grain a ray is a thin radial
//! line, on a radial face (containing the pith) a fleck across the grain, on a tangential face
//! a small spindle. A species can have several layers (e.g. the broad and the fine rays of
//! oak).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::cells::{CylinderCells, wyvill};
use super::checks::{check_colour, check_sizes};
use super::noise::hash_units3;
use crate::config::Checker;
use crate::error::Result;
use crate::frame::mm;

/// Most shells on each side a ray may reach into (bounds the lookups per point).
const MAX_SHELL_REACH: i32 = 4;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayConfig {
    /// Cell size (mm): radial, tangential, along the grain. One ray at most per cell.
    pub cell_mm: [f32; 3],
    /// Ray size (mm): radial length, tangential width, height along the grain.
    pub size_mm: [f32; 3],
    /// Chance that a cell holds a ray.
    pub occurrence: f32,
    /// Relative random variation of the ray size (0.4: +-20%).
    #[serde(default)]
    pub size_variation: f32,
    /// Colour of a ray (display-referred).
    pub colour: [f32; 3],
    /// How much a ray's centre takes the ray colour.
    pub opacity: f32,
}

impl RayConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check_sizes(check, "cell_mm", self.cell_mm, 1000.0, "cell sizes")?;
        check_sizes(check, "size_mm", self.size_mm, 1000.0, "ray sizes")?;
        check.range(
            "size_variation",
            self.size_variation,
            0.0,
            1.0,
            "a relative spread",
        )?;
        let grown = self.size_mm.map(|s| s * (1.0 + 0.5 * self.size_variation));
        if (1..3).any(|a| grown[a] > self.cell_mm[a]) {
            return Err(check.error(
                "size_mm",
                format!(
                    "= {:?}: the largest ray ({grown:?} mm with size_variation) must fit its \
                     cell {:?} mm in width and height",
                    self.size_mm, self.cell_mm
                ),
            ));
        }
        if grown[0] > 2.0 * MAX_SHELL_REACH as f32 * self.cell_mm[0] {
            return Err(check.error(
                "size_mm",
                format!(
                    "[0] = {}: a ray may be at most {} times as long as cell_mm[0] = {}",
                    self.size_mm[0],
                    2 * MAX_SHELL_REACH,
                    self.cell_mm[0]
                ),
            ));
        }
        check.range("occurrence", self.occurrence, 0.0, 1.0, "a probability")?;
        check_colour(check, "colour", self.colour)?;
        check.range("opacity", self.opacity, 0.0, 1.0, "an opacity")
    }
}

#[derive(Clone, Debug)]
pub struct Rays {
    cells: CylinderCells,
    /// Half-extents (radial, tangential, along) of a ray of nominal size.
    half: Vec3,
    variation: f32,
    occurrence: f32,
    pub colour: Vec3,
    pub opacity: f32,
}

impl Rays {
    pub fn new(cfg: &RayConfig, seed: u64) -> Self {
        Self {
            cells: CylinderCells::new(seed, Vec3::from(cfg.cell_mm.map(mm))),
            half: 0.5 * Vec3::from(cfg.size_mm.map(mm)),
            variation: cfg.size_variation,
            occurrence: cfg.occurrence,
            colour: Vec3::from(cfg.colour),
            opacity: cfg.opacity,
        }
    }

    /// Ray weight in [0, 1] at tree coordinates (`rho` = G / years_per_unit): the strongest
    /// of the rays of the shells within reach.
    #[inline]
    pub fn weight(&self, rho: f32, phi: f32, h: f32) -> f32 {
        let largest = self.half * (1.0 + 0.5 * self.variation);
        // A ray's centre lies in its own shell, so only shells meeting
        // [rho - half length, rho + half length] can hold a ray reaching rho.
        let first = self.cells.shell(rho - largest.x);
        let last = self.cells.shell(rho + largest.x);
        let mut best = 0.0f32;
        for shell in first..=last {
            let cell = self.cells.locate_in_shell(shell, rho, phi, h);
            let numbers = hash_units3(cell.hash ^ 0x5241);
            if numbers.x >= self.occurrence {
                continue;
            }
            // Radially the centre may sit anywhere in the shell (the ray reaches out of it);
            // across and along the grain the ray stays inside its cell.
            let mut centre = cell.centre(self.cells.size, largest);
            centre.x = self.cells.size.x * numbers.y;
            let half = self.half * (1.0 + self.variation * (numbers.z - 0.5));
            let d = cell.offset(centre) / half;
            best = best.max(wyvill(d.length_squared()));
        }
        best
    }
}
