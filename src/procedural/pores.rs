//! Pores (vessels): tubes along the grain that show as dots on end grain and as short dashes
//! on side faces (Liu et al. 2016 section 4.6; Mokume appendix A.2.3).
//!
//! One pore at most per cylindrical cell (see [`super::cells`]), at a hashed position. Its
//! size and the chance that it exists depend on the ring phase at the pore's centre: inside
//! the pore zone (phase below `zone[0]`, blended over `zone[1]`) they take the earlywood
//! values, after it the latewood values. Ring-porous woods (oak, chestnut) have big, frequent
//! earlywood pores and tiny rare latewood ones; semi-ring-porous woods (walnut) a wide soft
//! zone; diffuse-porous woods (maple) equal values. The weight is Wyvill's kernel of the
//! distance to the pore axis, the pore being a round-ended tube `length_mm` long.
//!
//! Vessels are not exactly parallel to the pith: they wander around the stem. Without that,
//! a plane cutting the tubes at a slight angle crosses the azimuth cells at a regular rate
//! and shows the pores in a lattice. So the azimuth of the lookup is shifted by smooth noise
//! (`wander_mm` around the stem, varying over ~10 cells across and ~3 cell lengths along the
//! grain), which bends whole neighbourhoods of tubes together and keeps them in their cells.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::cells::{CylinderCells, wyvill};
use super::checks::{check_colour, check_sizes};
use super::noise::{fract, hash_units3, value3};
use super::tree::TreePoint;
use super::years::YearTable;
use crate::config::Checker;
use crate::error::Result;
use crate::field::smin::smoothstep;
use crate::frame::mm;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoreConfig {
    /// Cell size (mm): radial, tangential, along the grain. One pore at most per cell.
    pub cell_mm: [f32; 3],
    /// Pore radius (mm) in the pore zone (earlywood) and after it (latewood).
    pub radius_mm: [f32; 2],
    /// Relative random variation of the radius (0.3: +-15%).
    #[serde(default)]
    pub radius_variation: f32,
    /// Length of an earlywood pore along the grain (mm); smaller pores are shorter in
    /// proportion.
    pub length_mm: f32,
    /// How far the tubes wander around the stem (mm).
    #[serde(default)]
    pub wander_mm: f32,
    /// Chance that a cell holds a pore, in the pore zone and after it.
    pub occurrence: [f32; 2],
    /// End of the pore zone (ring phase) and the half-width of its soft edge.
    pub zone: [f32; 2],
    /// Colour of an open pore (display-referred).
    pub colour: [f32; 3],
    /// How much a pore's centre takes the pore colour.
    pub opacity: f32,
}

impl PoreConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check_sizes(check, "cell_mm", self.cell_mm, 100.0, "cell sizes")?;
        check_sizes(check, "radius_mm", self.radius_mm, 10.0, "pore radii")?;
        let largest =
            self.radius_mm[0].max(self.radius_mm[1]) * (1.0 + 0.5 * self.radius_variation);
        let room = 0.5 * self.cell_mm[0].min(self.cell_mm[1]);
        if largest > room {
            return Err(check.error(
                "radius_mm",
                format!(
                    "= {:?}: the largest pore (radius {largest} mm with radius_variation) must fit \
                     its cell: at most half the smaller of cell_mm[0], cell_mm[1] ({room} mm)",
                    self.radius_mm
                ),
            ));
        }
        check.range(
            "radius_variation",
            self.radius_variation,
            0.0,
            1.0,
            "a relative spread",
        )?;
        check.range("wander_mm", self.wander_mm, 0.0, 100.0, "a distance in mm")?;
        check.range(
            "length_mm",
            self.length_mm,
            1e-3,
            self.cell_mm[2],
            "a pore length no longer than cell_mm[2]",
        )?;
        for (i, o) in self.occurrence.iter().enumerate() {
            check.range(&format!("occurrence[{i}]"), *o, 0.0, 1.0, "a probability")?;
        }
        check.range(
            "zone[0]",
            self.zone[0],
            0.0,
            1.0,
            "the ring phase where the pore zone ends",
        )?;
        check.range(
            "zone[1]",
            self.zone[1],
            0.0,
            0.5,
            "the half-width of the zone edge",
        )?;
        check_colour(check, "colour", self.colour)?;
        check.range("opacity", self.opacity, 0.0, 1.0, "an opacity")
    }
}

#[derive(Clone, Debug)]
pub struct Pores {
    cells: CylinderCells,
    radius: [f32; 2],
    variation: f32,
    half_length: f32,
    occurrence: [f32; 2],
    zone: [f32; 2],
    /// Half-extents of the largest pore (for keeping pores inside their cells).
    largest: Vec3,
    wander: f32,
    /// Tree-space point to wander-noise lattice.
    wander_scale: Vec3,
    wander_seed: u64,
    pub colour: Vec3,
    pub opacity: f32,
}

impl Pores {
    pub fn new(cfg: &PoreConfig, seed: u64) -> Self {
        let size = Vec3::from(cfg.cell_mm.map(mm));
        let radius = cfg.radius_mm.map(mm);
        let variation = cfg.radius_variation;
        let r_max = radius[0].max(radius[1]) * (1.0 + 0.5 * variation);
        let half_length = 0.5 * mm(cfg.length_mm);
        Self {
            cells: CylinderCells::new(seed, size),
            radius,
            variation,
            half_length,
            occurrence: cfg.occurrence,
            zone: cfg.zone,
            largest: Vec3::new(r_max, r_max, half_length),
            wander: mm(cfg.wander_mm),
            wander_scale: Vec3::new(0.1 / size.y, 0.1 / size.y, 1.0 / (3.0 * size.z)),
            wander_seed: crate::rng::mix64(seed ^ 0x57),
            colour: Vec3::from(cfg.colour),
            opacity: cfg.opacity,
        }
    }

    /// Share of the pore zone's (earlywood) values at a ring phase: 1 inside, 0 after.
    #[inline]
    pub(crate) fn zone_weight(&self, phase: f32) -> f32 {
        let [end, soft] = self.zone;
        1.0 - smoothstep(end - soft, end + soft + 1e-6, phase)
    }

    /// Pore weight in [0, 1] at a tree point with undistorted radius `rho` = G /
    /// years_per_unit. `years`, the phase offset (years added to G) and `years_per_unit`
    /// give the ring phase at the pore's centre.
    ///
    /// `radial_rate` gives d rho / d r at the point (the local growth rate); it is only called
    /// for points next to a pore, since it costs a rate-grid evaluation.
    #[inline]
    pub fn weight(
        &self,
        tree: &TreePoint,
        rho: f32,
        (years, phase_offset): (&YearTable, f32),
        years_per_unit: f32,
        radial_rate: impl FnOnce() -> f32,
    ) -> f32 {
        let mut phi = tree.phi;
        if self.wander > 0.0 && rho > 0.0 {
            let shift =
                self.wander * value3(self.wander_seed, tree.frame_point() * self.wander_scale);
            let tau = std::f32::consts::TAU;
            phi = tau * fract((phi + shift / rho) / tau);
        }
        let cell = self.cells.locate(rho, phi, tree.h);
        let centre = cell.centre(self.cells.size, self.largest);
        let time = years.time((cell.rho0 + centre.x) * years_per_unit + phase_offset);
        let zone = self.zone_weight(fract(time));
        let occurrence = self.occurrence[1] + (self.occurrence[0] - self.occurrence[1]) * zone;
        let numbers = hash_units3(cell.hash ^ 0x504f);
        if numbers.x >= occurrence {
            return 0.0;
        }
        let base = self.radius[1] + (self.radius[0] - self.radius[1]) * zone;
        let radius = base * (1.0 + self.variation * (numbers.y - 0.5));
        let half_length = self.half_length * radius / self.radius[0].max(self.radius[1]);
        let d = cell.offset(centre);
        // Vessels are long tubes: the along-grain term is raised to the 4th power (a capsule
        // that keeps its full width over most of its length), so an end-grain cut through a
        // pore shows its whole cross-section, not the tip of an ellipsoid.
        let along = (d.z * d.z) / (half_length * half_length);
        let rest = (d.y * d.y) / (radius * radius) + along * along * along * along;
        if rest >= 1.0 {
            return 0.0;
        }
        // rho grows faster than the physical radius where the growth rate is above 1, so in
        // rho the pore's radial radius is scaled by the local rate: it stays round in real
        // space instead of flattening into a tangential dash where rings are narrow. Clamped
        // to the room its cell has.
        let radial = (radius * radial_rate().clamp(0.25, 4.0)).min(self.cells.size.x * 0.5);
        wyvill((d.x * d.x) / (radial * radial) + rest)
    }
}
