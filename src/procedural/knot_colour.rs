//! Knot colour (Mokume appendix A.2.3; Larsson et al. 2022): inside a knot the wood takes its
//! own colour map along the knot's time (the branch's own rings stay visible through it), is
//! darkened (more pigment: knots are end grain and resinous), and a dead knot gets a dark
//! outline where the bark of the dead branch was overgrown.
//!
//! "Inside" is measured with the growth field's times: a point lies in a knot where the knot's
//! time is smaller than the stem's (it belongs to the branch), blended over `edge_years`.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::checks::{check_colour, check_years};
use super::colour_map::{ColourMap, ColourMapConfig};
use crate::config::Checker;
use crate::error::Result;
use crate::field::FieldSample;
use crate::field::smin::smoothstep;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KnotColourConfig {
    /// Colour along the knot's time, from `years[0]` (the branch's centre) to `years[1]`.
    pub map: ColourMapConfig,
    /// Knot times (years) mapped to the first and last map entries.
    pub years: [f32; 2],
    /// How much the map replaces the ring colour inside the knot (1: rings only via pigment).
    pub opacity: f32,
    /// Extra log pigment exponent inside the knot.
    pub darken: f32,
    /// Softness of the knot's edge (years of stem time minus knot time).
    pub edge_years: f32,
    /// Colour of a dead knot's outline.
    pub outline_colour: [f32; 3],
    /// Width of a dead knot's outline (years inside its edge; 0 = no outline).
    pub outline_years: f32,
}

impl Default for KnotColourConfig {
    fn default() -> Self {
        Self {
            map: ColourMapConfig {
                stops: vec![[0.0, 0.42, 0.25, 0.14], [1.0, 0.58, 0.38, 0.22]],
            },
            years: [0.0, 12.0],
            opacity: 0.6,
            darken: 0.35,
            edge_years: 0.4,
            outline_colour: [0.18, 0.11, 0.07],
            outline_years: 0.5,
        }
    }
}

impl KnotColourConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        self.map.validate(&check.nested("map"))?;
        check_years(check, self.years, "knot times in years")?;
        check.range("opacity", self.opacity, 0.0, 1.0, "an opacity")?;
        check.range("darken", self.darken, -2.0, 3.0, "a log pigment exponent")?;
        check.range("edge_years", self.edge_years, 0.01, 100.0, "years")?;
        check_colour(check, "outline_colour", self.outline_colour)?;
        check.range("outline_years", self.outline_years, 0.0, 100.0, "years")
    }
}

#[derive(Clone, Debug)]
pub(crate) struct KnotColour {
    map: ColourMap,
    year0: f32,
    inv_span: f32,
    pub opacity: f32,
    pub darken: f32,
    edge: f32,
    pub outline_colour: Vec3,
    outline: f32,
}

impl KnotColour {
    pub(crate) fn new(cfg: &KnotColourConfig) -> Self {
        Self {
            map: ColourMap::from_config(&cfg.map),
            year0: cfg.years[0],
            inv_span: 1.0 / (cfg.years[1] - cfg.years[0]),
            opacity: cfg.opacity,
            darken: cfg.darken,
            edge: cfg.edge_years,
            outline_colour: Vec3::from(cfg.outline_colour),
            outline: cfg.outline_years,
        }
    }

    /// How much a point belongs to a knot, in [0, 1].
    #[inline]
    pub(crate) fn mask(&self, s: &FieldSample) -> f32 {
        if !s.knot_time.is_finite() {
            return 0.0;
        }
        smoothstep(-self.edge, self.edge, s.stem - s.knot_time)
    }

    /// The knot's map colour at a point.
    #[inline]
    pub(crate) fn colour(&self, s: &FieldSample) -> Vec3 {
        self.map
            .sample(((s.knot_time - self.year0) * self.inv_span).clamp(0.0, 1.0))
    }

    /// Weight of the dead-knot outline in [0, 1]: a band just inside a dead knot's edge.
    #[inline]
    pub(crate) fn outline(&self, s: &FieldSample) -> f32 {
        if !s.in_dead_knot || self.outline <= 0.0 {
            return 0.0;
        }
        let inside = s.stem - s.knot_time;
        smoothstep(0.0, 0.3 * self.outline, inside)
            * (1.0 - smoothstep(0.7 * self.outline, self.outline, inside))
    }
}
