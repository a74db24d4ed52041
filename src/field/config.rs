//! The growth-field config (TOML under `configs/fields/`). Plain serde structs: unknown keys
//! are errors, every value is range-checked by [`FieldConfig::validate`] with a message that
//! names the key. The smallest valid file is
//!
//! ```toml
//! [pith]
//! origin = [0.0, 0.0, -2.5]     # cube units (1 unit = 4 cm)
//! direction = [0.0, 1.0, 0.1]   # need not be normalised
//! [growth]
//! years_per_unit = 12.0
//! ```
//!
//! and means G(p) = years_per_unit x distance(p, pith axis) exactly.
//!
//! The component structs ([`PithConfig`], [`GrowthConfig`], [`KnotConfig`]) are reused by the
//! configs of later stages (procedural wood, fit output), which hold them as fields.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::base_colour::BaseColour;
use crate::config::{Checker, ConfigFile};
use crate::error::Result;

/// Largest coordinate accepted anywhere (cube units): 100 units = 4 m.
const MAX_COORD: f32 = 100.0;

/// Most knots a field may have.
pub(crate) const MAX_KNOTS: usize = 64;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldConfig {
    pub pith: PithConfig,
    pub growth: GrowthConfig,
    /// Knots (branches), each a strand with its own time field merged into the stem's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub knots: Vec<KnotConfig>,
    /// A colour bar over G fitted to face photos (written by `xylem fit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_colour: Option<BaseColour>,
}

/// The pith axis: the line the tree grew around.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PithConfig {
    /// A point on the axis, cube units; also the zero of the height coordinate.
    pub origin: [f32; 3],
    /// Axis direction (need not be normalised). By convention close to +y (faces B and D are
    /// the end grain).
    pub direction: [f32; 3],
    /// The direction the fibres run when the photos show it differs from the axis (tilted or
    /// spiral grain; measured by `xylem fit`, `fit::fibre_direction`). Absent: along the axis.
    /// Read by the NCA's grain noise; the procedural model grows its vessels along the axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fibre_direction: Option<[f32; 3]>,
}

/// Radial growth: years per unit of radius, optionally modulated by a rate grid R.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrowthConfig {
    /// Years of growth per cube unit of radius (12 = rings 3.3 mm apart).
    pub years_per_unit: f32,
    /// Rate grid resolution [n_h, n_a, n_r]: heights along the pith, azimuths, radii.
    #[serde(default = "default_grid")]
    pub grid: [usize; 3],
    /// Rates are clamped to at least this (relative to 1) so rings never cross.
    #[serde(default = "default_min_rate")]
    pub min_rate: f32,
    /// Explicit rate grid (relative rates, 1 = undistorted), flattened with index
    /// `(ih * n_a + ia) * n_r + ir`. Written by `xylem fit`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rates: Option<Vec<f32>>,
    /// A seeded random rate grid (smooth distortions) instead of explicit `rates`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distortion: Option<DistortionConfig>,
    /// Heights covered by the grid along the pith (cube units from the origin). Default: the
    /// cube's extent along the axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_range: Option<[f32; 2]>,
    /// Radii covered by the grid's radial nodes (cube units). Default: from the nearest to the
    /// farthest point of the cube.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_range: Option<[f32; 2]>,
    /// Azimuths covered by the grid's azimuth nodes, `[start, end]` in radians around the
    /// pith (phi = 0 towards +z, see docs/DESIGN.md), end - start <= 2 pi; the ends are
    /// clamped. Default: the full circle, periodic. `xylem fit` pins the cube's wedge.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub azimuth_range: Option<[f32; 2]>,
    /// Where the annual rings are, if not at integer values of the stem time (fitted fields).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rings: Option<RingsConfig>,
}

/// Annual ring positions of a fitted field: G is warped piecewise-linearly so that the ring
/// at raw stem time `at[i]` lands on year `first_year + i` (see `field::ring_warp`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingsConfig {
    /// Raw stem times (years_per_unit x integral of R, before knots) of consecutive rings,
    /// strictly increasing and > 0.
    pub at: Vec<f32>,
    /// The year number the first listed ring gets (>= 1).
    pub first_year: u32,
}

/// Smooth random growth-rate variation, generated from a seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DistortionConfig {
    pub seed: u64,
    /// Standard deviation of the log rate over the grid (0.3: ring widths vary by ~30%).
    pub amplitude: f32,
    /// Highest number of waves around the pith.
    #[serde(default = "default_azimuthal_waves")]
    pub azimuthal_waves: usize,
    /// Highest number of half-waves across the radial range.
    #[serde(default = "default_radial_waves")]
    pub radial_waves: usize,
    /// Highest number of half-waves along the height range.
    #[serde(default = "default_height_waves")]
    pub height_waves: usize,
}

/// One knot after Larsson et al. 2022: a straight strand from `origin` (normally on the
/// pith) along `direction`, with its own time field t_b = years_per_unit x distance / speed,
/// joined to the stem by a power smooth minimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KnotConfig {
    /// Where the knot starts (cube units), normally a point of the pith axis.
    pub origin: [f32; 3],
    /// Direction the branch grew (away from the pith; need not be normalised).
    pub direction: [f32; 3],
    /// Radial growth speed of the branch relative to the stem (< 1: denser knot rings and a
    /// knot radius of speed x stem radius).
    #[serde(default = "default_knot_speed")]
    pub speed: f32,
    /// Power smooth-minimum exponent outside the knot (lower: wider, softer distortion).
    #[serde(default = "default_k_stem")]
    pub k_stem: f32,
    /// Exponent inside the knot (higher: sharper knot edge).
    #[serde(default = "default_k_knot")]
    pub k_knot: f32,
    /// Width (years of t_s - t_b) of the transition between the two exponents.
    #[serde(default = "default_k_width")]
    pub k_width: f32,
    /// The knot's influence fades out between these distances from its axis, in knot radii.
    #[serde(default = "default_reach")]
    pub reach: [f32; 2],
    /// Stem time (years) at which the branch died; absent for an alive knot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub death: Option<f32>,
    /// Smoothing factor reached long after death (negative: the distortion inverts).
    #[serde(default = "default_dead_factor")]
    pub dead_factor: f32,
    /// Years after death over which the factor goes from 1 to `dead_factor`.
    #[serde(default = "default_dead_transition")]
    pub dead_transition: f32,
    /// Increase of the smooth-minimum exponent per year after death (tighter union).
    #[serde(default = "default_dead_sharpen")]
    pub dead_sharpen: f32,
    /// Butterfly asymmetry of a dead knot in [0, 1]: 0 = uniform, 1 = distortion only above
    /// and below the knot (along the pith), none at its sides.
    #[serde(default)]
    pub butterfly: f32,
}

fn default_grid() -> [usize; 3] {
    [8, 16, 16]
}
fn default_min_rate() -> f32 {
    0.05
}
fn default_azimuthal_waves() -> usize {
    3
}
fn default_radial_waves() -> usize {
    4
}
fn default_height_waves() -> usize {
    2
}
fn default_knot_speed() -> f32 {
    0.12
}
fn default_k_stem() -> f32 {
    1.5
}
fn default_k_knot() -> f32 {
    5.0
}
fn default_k_width() -> f32 {
    2.0
}
fn default_reach() -> [f32; 2] {
    [3.0, 6.0]
}
fn default_dead_factor() -> f32 {
    -0.5
}
fn default_dead_transition() -> f32 {
    3.0
}
fn default_dead_sharpen() -> f32 {
    0.5
}

impl ConfigFile for FieldConfig {
    /// Range checks of every value; keys in messages are relative to `check`'s prefix.
    fn validate(&self, check: &Checker) -> Result<()> {
        self.pith.validate(&check.nested("pith"))?;
        self.growth.validate(&check.nested("growth"))?;
        // Evaluation costs grow with the knot count (1000 knots took 9 s at 32^3, 10000
        // over 2 min); real cubes have a handful.
        check.count(
            "knots",
            self.knots.len(),
            0,
            MAX_KNOTS,
            "number of [[knots]]",
        )?;
        for (i, knot) in self.knots.iter().enumerate() {
            knot.validate(&check.nested(&format!("knots[{i}]")))?;
        }
        if let Some(colour) = &self.base_colour {
            colour.validate(&check.nested("base_colour"))?;
        }
        Ok(())
    }
}

impl PithConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.vector("origin", self.origin, MAX_COORD, "a point in cube units")?;
        check.direction("direction", self.direction)?;
        match self.fibre_direction {
            Some(d) => check.direction("fibre_direction", d),
            None => Ok(()),
        }
    }

    /// The unit fibre direction: `fibre_direction` if given, else the axis (a validated
    /// config's directions are non-zero).
    pub fn fibre_axis(&self) -> Vec3 {
        Vec3::from(self.fibre_direction.unwrap_or(self.direction)).normalize()
    }
}

impl GrowthConfig {
    /// Number of entries of the rate grid.
    pub(crate) fn grid_len(&self) -> usize {
        self.grid.iter().product()
    }

    /// The range of `min_rate`, here and in the fit that writes it (`fit::config`).
    pub(crate) fn check_min_rate(check: &Checker, min_rate: f32) -> Result<()> {
        check.range(
            "min_rate",
            min_rate,
            1e-4,
            1.0,
            "the smallest relative growth rate",
        )
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.positive(
            "years_per_unit",
            self.years_per_unit,
            10_000.0,
            "years per cube unit of radius",
        )?;
        let [nh, na, nr] = self.grid;
        check.count("grid[0]", nh, 1, 64, "the number of heights n_h")?;
        check.count("grid[1]", na, 4, 128, "the number of azimuths n_a")?;
        check.count("grid[2]", nr, 2, 128, "the number of radii n_r")?;
        Self::check_min_rate(check, self.min_rate)?;
        if self.rates.is_some() && self.distortion.is_some() {
            return Err(check.error(
                "rates",
                "and `growth.distortion` are both set; give one or the other",
            ));
        }
        if let Some(rates) = &self.rates {
            if rates.len() != self.grid_len() {
                return Err(check.error(
                    "rates",
                    format!(
                        "has {} values; expected n_h x n_a x n_r = {nh} x {na} x {nr} = {} (index (ih*n_a + ia)*n_r + ir)",
                        rates.len(),
                        self.grid_len()
                    ),
                ));
            }
            if let Some(i) = rates.iter().position(|r| !r.is_finite() || r.abs() > 1e3) {
                return Err(check.error(
                    "rates",
                    format!("[{i}] = {}: expected a finite relative rate", rates[i]),
                ));
            }
        }
        if let Some(d) = &self.distortion {
            d.validate(&check.nested("distortion"), na)?;
        }
        if let Some([lo, hi]) = self.height_range
            && !(lo.is_finite() && hi.is_finite() && hi > lo)
        {
            return Err(check.error(
                "height_range",
                format!("= [{lo}, {hi}]: expected [low, high] with low < high"),
            ));
        }
        if let Some([lo, hi]) = self.radius_range
            && !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo)
        {
            return Err(check.error(
                "radius_range",
                format!("= [{lo}, {hi}]: expected [low, high] with 0 <= low < high"),
            ));
        }
        if let Some([lo, hi]) = self.azimuth_range {
            let turn = std::f32::consts::TAU;
            if !(lo.is_finite() && hi.is_finite() && hi > lo && hi - lo <= turn + 1e-4)
                || lo.abs() > 2.0 * turn
            {
                return Err(check.error(
                    "azimuth_range",
                    format!(
                        "= [{lo}, {hi}]: expected [start, end] in radians with start < end, \
                         end - start <= 2 pi and |start| <= 4 pi"
                    ),
                ));
            }
        }
        if let Some(rings) = &self.rings {
            rings.validate(&check.nested("rings"))?;
        }
        Ok(())
    }
}

impl RingsConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.list_length(
            "at",
            self.at.len(),
            1,
            100_000,
            "values; expected 1 to 100000 ring positions",
        )?;
        if let Some(i) = self.at.iter().position(|a| !(a.is_finite() && *a > 0.0)) {
            return Err(check.error(
                "at",
                format!("[{i}] = {}: expected a finite stem time > 0", self.at[i]),
            ));
        }
        if let Some(i) = self.at.windows(2).position(|w| w[1] <= w[0]) {
            return Err(check.error(
                "at",
                format!(
                    "[{}] = {} is not above [{i}] = {}: ring positions must increase strictly",
                    i + 1,
                    self.at[i + 1],
                    self.at[i]
                ),
            ));
        }
        check.count(
            "first_year",
            self.first_year as usize,
            1,
            1_000_000,
            "the year of the first listed ring",
        )
    }
}

impl DistortionConfig {
    pub fn validate(&self, check: &Checker, n_a: usize) -> Result<()> {
        check.range(
            "amplitude",
            self.amplitude,
            0.0,
            2.0,
            "the standard deviation of the log growth rate",
        )?;
        check.count(
            "azimuthal_waves",
            self.azimuthal_waves,
            0,
            n_a / 2,
            "waves around the pith (at most n_a / 2)",
        )?;
        check.count(
            "radial_waves",
            self.radial_waves,
            0,
            32,
            "radial half-waves",
        )?;
        check.count(
            "height_waves",
            self.height_waves,
            0,
            32,
            "height half-waves",
        )
    }
}

impl KnotConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.vector(
            "origin",
            self.origin,
            MAX_COORD,
            "the knot's start point in cube units",
        )?;
        check.direction("direction", self.direction)?;
        check.range(
            "speed",
            self.speed,
            0.005,
            1.0,
            "the knot's growth speed relative to the stem",
        )?;
        check.range(
            "k_stem",
            self.k_stem,
            0.2,
            50.0,
            "a smooth-minimum exponent",
        )?;
        check.range(
            "k_knot",
            self.k_knot,
            0.2,
            50.0,
            "a smooth-minimum exponent",
        )?;
        check.positive(
            "k_width",
            self.k_width,
            1000.0,
            "a transition width in years",
        )?;
        let [near, far] = self.reach;
        if !(near.is_finite() && far.is_finite() && near > 0.0 && far > near) {
            return Err(check.error(
                "reach",
                format!("= [{near}, {far}]: expected [near, far] knot radii with 0 < near < far"),
            ));
        }
        if let Some(death) = self.death {
            check.range(
                "death",
                death,
                0.0,
                10_000.0,
                "the stem time of death in years",
            )?;
        }
        check.range(
            "dead_factor",
            self.dead_factor,
            -2.0,
            1.0,
            "the smoothing factor long after death",
        )?;
        check.positive("dead_transition", self.dead_transition, 1000.0, "years")?;
        check.range(
            "dead_sharpen",
            self.dead_sharpen,
            0.0,
            10.0,
            "exponent increase per year",
        )?;
        check.range(
            "butterfly",
            self.butterfly,
            0.0,
            1.0,
            "the butterfly asymmetry",
        )
    }

    /// An alive knot along a ray with the default shape parameters.
    pub fn alive(origin: [f32; 3], direction: [f32; 3]) -> Self {
        Self {
            origin,
            direction,
            speed: default_knot_speed(),
            k_stem: default_k_stem(),
            k_knot: default_k_knot(),
            k_width: default_k_width(),
            reach: default_reach(),
            death: None,
            dead_factor: default_dead_factor(),
            dead_transition: default_dead_transition(),
            dead_sharpen: default_dead_sharpen(),
            butterfly: 0.0,
        }
    }
}

impl GrowthConfig {
    /// An undistorted growth section.
    pub fn uniform(years_per_unit: f32) -> Self {
        Self {
            years_per_unit,
            grid: default_grid(),
            min_rate: default_min_rate(),
            rates: None,
            distortion: None,
            height_range: None,
            radius_range: None,
            azimuth_range: None,
            rings: None,
        }
    }
}
