//! Annual rings: the earlywood-to-latewood profile within a year and the two colour maps
//! along G (Liu et al. 2016 section 4.2; Mokume section 5.3.1).
//!
//! The ring phase is the fractional part of the ring time T (years; see [`super::years`]).
//! Phase 0 is the ring boundary, where the previous year's latewood meets this year's
//! earlywood: the ring localisation image I(T) peaks there, as the U-Net's rings do on real
//! photos. Within a year the latewood weight rises from 0 to 1 between `transition[0]` and
//! `transition[1]` (a blend of a linear ramp and a smoothstep, `smooth`), and just after the
//! boundary the previous latewood fades out over `boundary` so the step is not a
//! one-pixel jump.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::checks::{check_interval, check_years};
use super::colour_map::{ColourMap, ColourMapConfig};
use crate::config::Checker;
use crate::error::Result;
use crate::field::smin::smoothstep;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingConfig {
    /// Earlywood colour along the ring time, from `years[0]` (heartwood side) to `years[1]`.
    pub earlywood: ColourMapConfig,
    /// Latewood colour along the ring time.
    pub latewood: ColourMapConfig,
    /// Ring times (years) that map to the first and last entries of the colour maps.
    pub years: [f32; 2],
    /// Ring phases where the earlywood-to-latewood blend starts and ends.
    pub transition: [f32; 2],
    /// Shape of that blend: 0 = linear ramp, 1 = smoothstep.
    #[serde(default = "default_smooth")]
    pub smooth: f32,
    /// Ring phase over which the previous year's latewood fades out after the boundary.
    #[serde(default = "default_boundary")]
    pub boundary: f32,
    /// Standard deviation of the log ring width from year to year (0 = rings follow G).
    #[serde(default)]
    pub width_variation: f32,
    /// Correlation of the log ring width with the previous year's (0 = independent years).
    #[serde(default = "default_width_correlation")]
    pub width_correlation: f32,
    /// Standard deviation of a per-year change of the pigment exponent (darker or lighter
    /// years), Beer's-law style.
    #[serde(default)]
    pub colour_variation: f32,
    /// Years added to G before the ring phase is taken: moves earlywood, latewood and the
    /// pore zone along each ring while the ring images (integer G) stay. 0 for the presets,
    /// whose ring boundary is at integer G like a synthetic sample's ring lines; the inverse
    /// procedural fit sets it for photographed samples, whose ring images (the Mokume
    /// U-Net's) lie on the earlywood pore band instead (CN03: pores at phases 0.6-1.0 of the
    /// fitted field).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub phase_offset: f32,
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

fn default_smooth() -> f32 {
    0.5
}
fn default_boundary() -> f32 {
    0.03
}
fn default_width_correlation() -> f32 {
    0.5
}

impl RingConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        self.earlywood.validate(&check.nested("earlywood"))?;
        self.latewood.validate(&check.nested("latewood"))?;
        check_years(check, self.years, "ring times in years")?;
        check_interval(
            check,
            "transition",
            self.transition,
            0.0,
            1.0,
            "ring phases",
        )?;
        check.range("smooth", self.smooth, 0.0, 1.0, "the smoothstep share")?;
        check.range(
            "boundary",
            self.boundary,
            0.0,
            self.transition[0].max(0.0),
            "a ring phase no later than transition[0]",
        )?;
        check.range(
            "phase_offset",
            self.phase_offset,
            -1.0,
            1.0,
            "years (a ring phase shift)",
        )?;
        check.range(
            "width_variation",
            self.width_variation,
            0.0,
            1.5,
            "the standard deviation of the log ring width",
        )?;
        check.range(
            "width_correlation",
            self.width_correlation,
            0.0,
            0.99,
            "a year-to-year correlation",
        )?;
        check.range(
            "colour_variation",
            self.colour_variation,
            0.0,
            2.0,
            "the standard deviation of the per-year pigment exponent",
        )
    }
}

/// The ring colour model built from a validated [`RingConfig`].
#[derive(Clone, Debug)]
pub struct Rings {
    earlywood: ColourMap,
    latewood: ColourMap,
    year0: f32,
    inv_span: f32,
    start: f32,
    inv_ramp: f32,
    smooth: f32,
    boundary: f32,
}

impl Rings {
    pub fn new(cfg: &RingConfig) -> Self {
        Self {
            earlywood: ColourMap::from_config(&cfg.earlywood),
            latewood: ColourMap::from_config(&cfg.latewood),
            year0: cfg.years[0],
            inv_span: 1.0 / (cfg.years[1] - cfg.years[0]),
            start: cfg.transition[0],
            inv_ramp: 1.0 / (cfg.transition[1] - cfg.transition[0]),
            smooth: cfg.smooth,
            boundary: cfg.boundary,
        }
    }

    /// Latewood weight in [0, 1] at a ring phase in [0, 1).
    #[inline]
    pub fn latewood(&self, phase: f32) -> f32 {
        let ramp = ((phase - self.start) * self.inv_ramp).clamp(0.0, 1.0);
        let shaped = ramp + self.smooth * (ramp * ramp * (3.0 - 2.0 * ramp) - ramp);
        let fading = if self.boundary > 0.0 {
            1.0 - smoothstep(0.0, self.boundary, phase)
        } else {
            0.0
        };
        shaped.max(fading)
    }

    /// Position along the colour maps of ring time `time`, in [0, 1].
    #[inline]
    pub(crate) fn map_position(&self, time: f32) -> f32 {
        ((time - self.year0) * self.inv_span).clamp(0.0, 1.0)
    }

    /// Base colour (before pigment variation) at ring time `time` with latewood weight `t`.
    #[inline]
    pub fn colour(&self, time: f32, latewood: f32) -> Vec3 {
        let g = self.map_position(time);
        self.earlywood
            .sample(g)
            .lerp(self.latewood.sample(g), latewood)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rings(boundary: f32) -> Rings {
        Rings::new(&RingConfig {
            earlywood: ColourMapConfig::constant([0.9, 0.8, 0.7]),
            latewood: ColourMapConfig::constant([0.5, 0.3, 0.2]),
            years: [0.0, 30.0],
            transition: [0.4, 0.8],
            smooth: 1.0,
            boundary,
            width_variation: 0.0,
            width_correlation: 0.5,
            phase_offset: 0.0,
            colour_variation: 0.0,
        })
    }

    #[test]
    fn profile_rises_through_the_year_and_falls_at_the_boundary() {
        let r = rings(0.05);
        assert_eq!(r.latewood(0.2), 0.0);
        assert_eq!(r.latewood(0.9), 1.0);
        assert!((r.latewood(0.6) - 0.5).abs() < 1e-6);
        assert!(r.latewood(0.01) > 0.8, "previous latewood still there");
        assert_eq!(r.latewood(0.06), 0.0);
        let no_blur = rings(0.0);
        assert_eq!(no_blur.latewood(0.0), 0.0);
        let mid = r.colour(10.0, 0.5);
        assert!((mid - Vec3::new(0.7, 0.55, 0.45)).length() < 1e-5);
    }
}
