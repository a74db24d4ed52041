//! The species config: one TOML file per species under `configs/species/`.
//!
//! It holds the growth field as the foundation's component structs (`pith`, `growth`,
//! `knots`, so [`SpeciesConfig::field_config`] rebuilds the exact [`FieldConfig`]), the colour
//! sections of the procedural model and a `seed` for everything random in them (pore and ray
//! placement, fibres, noise, year-to-year variation, burl buds). The field's own distortion
//! keeps its own seed, so changing `seed` moves pores and rays but not the rings.
//!
//! Physical sizes are given in millimetres (`*_mm` keys) and converted with
//! 1 cube unit = `frame::CM_PER_UNIT` cm = 40 mm. Colours are display-referred sRGB in [0, 1].

use serde::{Deserialize, Serialize};

use super::burl::BurlConfig;
use super::fibres::FibreConfig;
use super::figure::FigureConfig;
use super::knot_colour::KnotColourConfig;
use super::pigment::PigmentConfig;
use super::pores::PoreConfig;
use super::rays::RayConfig;
use super::rings::RingConfig;
use crate::config::{Checker, ConfigFile};
use crate::error::Result;
use crate::field::{FieldConfig, GrowthConfig, KnotConfig, PithConfig};

/// Most ray layers a species may have (each costs one cell lookup per point).
pub(crate) const MAX_RAY_LAYERS: usize = 4;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeciesConfig {
    /// A label for messages and outputs.
    #[serde(default)]
    pub name: String,
    /// Seed of every random choice of the colour model.
    pub seed: u64,
    pub pith: PithConfig,
    pub growth: GrowthConfig,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub knots: Vec<KnotConfig>,
    pub rings: RingConfig,
    /// Small 3D colour noise (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pigment: Option<PigmentConfig>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fibres: Option<FibreConfig>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pores: Option<PoreConfig>,
    /// Ray layers (e.g. large and fine rays), each with its own cells and colour.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rays: Vec<RayConfig>,
    /// Colour of knots (used only when `knots` is not empty).
    #[serde(default)]
    pub knot_colour: KnotColourConfig,
    /// Figure: radial and tangential displacement of the lookup point (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub figure: Option<FigureConfig>,
    /// Burl (Moyer 2003): buds pushing the wood around in several blended levels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub burl: Option<BurlConfig>,
}

impl SpeciesConfig {
    /// The growth field of this species, as `xylem field --config` reads it.
    pub fn field_config(&self) -> FieldConfig {
        FieldConfig {
            pith: self.pith.clone(),
            growth: self.growth.clone(),
            knots: self.knots.clone(),
            base_colour: None,
        }
    }
}

impl ConfigFile for SpeciesConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        self.field_config().validate(check)?;
        self.rings.validate(&check.nested("rings"))?;
        if let Some(p) = &self.pigment {
            p.validate(&check.nested("pigment"))?;
        }
        if let Some(f) = &self.fibres {
            f.validate(&check.nested("fibres"))?;
        }
        if let Some(p) = &self.pores {
            p.validate(&check.nested("pores"))?;
        }
        check.list_length(
            "rays",
            self.rays.len(),
            0,
            MAX_RAY_LAYERS,
            &format!("layers; at most {MAX_RAY_LAYERS} are supported"),
        )?;
        for (i, r) in self.rays.iter().enumerate() {
            r.validate(&check.nested(&format!("rays[{i}]")))?;
        }
        self.knot_colour.validate(&check.nested("knot_colour"))?;
        if let Some(f) = &self.figure {
            f.validate(&check.nested("figure"))?;
        }
        if let Some(b) = &self.burl {
            b.validate(&check.nested("burl"))?;
        }
        Ok(())
    }
}
