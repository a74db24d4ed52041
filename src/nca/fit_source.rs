//! Where B and G come from: the growth field and base colour of `xylem fit` (issue 4), read
//! from its `fit.toml` (a field config with a `[base_colour]` section). B is the fitted colour
//! bar in real (photo) colour for cuts and volumes (`ColourSpace::Real(None)`); the NCA brings
//! it into its white-balanced space itself (`conditioning::Normalisation`).
//!
//! `xylem train --fit PATH` accepts
//! - a fit folder or its `fit.toml` (the normal case);
//! - a folder holding `fit.toml` (e.g. an earlier training output);
//! - for experiments without a fit: a stand-in fit file (`[field]` = a field config,
//!   `[base_colour]` = `light`, `dark`) or a plain field config without base colour (the ramp
//!   colours then come from the photos: light = 1.1 x, dark = 0.6 x their mean colour); the
//!   stand-in base colour is a two-colour ring ramp B(p) = light + (dark - light) I(G(p)).
//!
//! The resolved fit is copied into the model folder (`fit.toml`) so synthesis rebuilds the
//! same B and G without the sample.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::conditioning::Conditioning;
use crate::config::ConfigFile;
use crate::config::{Checker, load_toml, parse_toml, write_config_copy};
use crate::error::{Result, XylemError};
use crate::field::{BaseColourTexture, ColourSpace, FieldConfig, GrowthField, ring_intensity};
use crate::texture::SolidTexture;

/// File name of the fit inside a model folder.
pub(crate) const FIT_FILE: &str = "fit.toml";

/// A fit: a growth field with its fitted base colour, or (stand-in) a ring colour ramp.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitRecord {
    pub field: FieldConfig,
    /// The stand-in ramp; `None` when `field.base_colour` holds the fitted colour.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_colour: Option<RampColours>,
}

/// Colours of the stand-in base colour, RGB in [0, 1] photo colours.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RampColours {
    /// Colour between the rings.
    pub light: [f32; 3],
    /// Colour on the ring lines (integer years of G).
    pub dark: [f32; 3],
}

impl FitRecord {
    /// Reads a fit file, a plain field config (colours from `photo_mean`), or a folder holding
    /// `fit.toml`.
    pub fn load(path: &Path, photo_mean: Option<[f32; 3]>) -> Result<Self> {
        let file = if path.is_dir() {
            path.join(FIT_FILE)
        } else {
            path.to_path_buf()
        };
        let text =
            crate::io::read_text(&file, "a fit.toml written by `xylem fit` or a field config")?;
        let table: toml::Table = parse_toml(&text, &file)?;
        let record = if table.contains_key("field") {
            load_toml::<FitRecord>(&file)?
        } else {
            let field = FieldConfig::parse(&text, &file)?;
            if field.base_colour.is_some() {
                return Ok(FitRecord {
                    field,
                    base_colour: None,
                });
            }
            let mean = photo_mean.ok_or_else(|| {
                XylemError::input(
                    file.display().to_string(),
                    "a plain field config needs the sample photos for its colours",
                )
            })?;
            FitRecord {
                field,
                base_colour: Some(RampColours {
                    light: mean.map(|m| (1.1 * m).min(1.0)),
                    dark: mean.map(|m| 0.6 * m),
                }),
            }
        };
        record.validate(&Checker::new(&file))?;
        Ok(record)
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        self.field.validate(&check.nested("field"))?;
        let Some(ramp) = &self.base_colour else {
            return Ok(());
        };
        let c = check.nested("base_colour");
        for (key, rgb) in [("light", ramp.light), ("dark", ramp.dark)] {
            for v in rgb {
                c.range(key, v, 0.0, 1.0, "RGB components")?;
            }
        }
        Ok(())
    }

    /// Writes the fit next to a model: a fitted field as the plain field config that
    /// `xylem field --config` also reads, a stand-in with its `[field]` wrapper.
    pub fn save(&self, path: &Path, source: &str) -> Result<()> {
        match self.base_colour {
            None => write_config_copy(path, &self.field, source),
            Some(_) => write_config_copy(path, self, source),
        }
    }

    /// The base colour as a prediction of the photos' mean colour in a cut or volume: the
    /// ground colour B shifted by the fit's mean shift (`ColourSpace::Shown(None)`), what
    /// B plus the NCA's dark pores should average to. The stand-in ramp has no shift: its
    /// own colours.
    pub fn shown_colour(&self) -> Arc<dyn SolidTexture> {
        match (&self.base_colour, &self.field.base_colour) {
            (None, Some(fitted)) => Arc::new(BaseColourTexture::new(
                GrowthField::from_config(&self.field),
                fitted.clone(),
                ColourSpace::Shown(None),
            )),
            _ => self.conditioning().colour,
        }
    }

    /// B and G as solid textures (B in photo colours).
    pub fn conditioning(&self) -> Conditioning {
        let field = Arc::new(GrowthField::from_config(&self.field));
        let colour: Arc<dyn SolidTexture> = match (&self.base_colour, &self.field.base_colour) {
            (Some(ramp), _) => Arc::new(RampTexture {
                field: field.clone(),
                light: Vec3::from(ramp.light),
                dark: Vec3::from(ramp.dark),
            }),
            (None, Some(fitted)) => Arc::new(BaseColourTexture::new(
                GrowthField::from_config(&self.field),
                fitted.clone(),
                ColourSpace::Real(None),
            )),
            (None, None) => unreachable!("load() gives a ramp to fields without base colour"),
        };
        Conditioning {
            fibre_axis: self.field.pith.fibre_axis(),
            growth: field,
            colour,
            grain: None,
            rays: None,
        }
    }
}

/// Loads B and G for training from `--fit` (see the module doc).
pub fn load_fit(fit: &Path, photo_mean: [f32; 3]) -> Result<FitRecord> {
    FitRecord::load(fit, Some(photo_mean))
}

/// The stand-in base colour: a ring ramp over G.
struct RampTexture {
    field: Arc<GrowthField>,
    light: Vec3,
    dark: Vec3,
}

impl SolidTexture for RampTexture {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        let t = ring_intensity(self.field.value(p));
        let c = self.light + (self.dark - self.light) * t;
        out.copy_from_slice(&c.to_array());
    }
}
