//! What a run compares: the reference images (photos of the faces, the true cuts of a
//! synthetic sample) and the textures set beside them (fitted rings, base colour, the
//! procedural model, the NCA's volume), loaded once for the sheet, renders and metrics.

use std::path::Path;

use super::procedural_step::PROCEDURAL_FILE;
use crate::config::ConfigFile;
use crate::field::{BaseColourTexture, ColourSpace, FieldConfig, GrainShaded, GrowthField};
use crate::frame::Face;
use crate::image2::Image2;
use crate::io::load_rgb;
use crate::io::npy::read_volume;
use crate::procedural::photograph::{Photograph, photographed};
use crate::procedural::{ProceduralWood, SpeciesConfig};
use crate::report::SHEET_ROWS;
use crate::run_folder::RunLayout;
use crate::texture::SolidTexture;
use crate::volume::Volume;
use crate::{Result, XylemError};

/// The textures and references of one finished run folder.
pub(crate) struct Compared {
    pub fit: FieldConfig,
    /// The NCA's volume, seen with the fit's grain shading.
    pub nca: GrainShaded<Volume>,
    /// The base colour at the sample's white balance, seen with the grain shading.
    pub base: GrainShaded<BaseColourTexture>,
    /// The procedural model: the truth of a synthetic sample (seen through the photograph
    /// that made its faces); otherwise the fit's `procedural.toml` (seen with the grain
    /// shading: its colours are matched to the photos' mean), or without one the `species`
    /// preset on the fitted field.
    pub procedural: Box<dyn SolidTexture>,
    /// Photos of the faces and, for a synthetic sample, the true cuts (SHEET_ROWS order).
    pub reference: Vec<Option<Image2>>,
    /// The sample is synthetic: its procedural model is the truth.
    pub synthetic: bool,
}

impl Compared {
    /// Loads the fit and volume of `layout`; `species` names the preset shown on the fitted
    /// field when the sample has no truth of its own.
    pub(super) fn load(layout: &RunLayout, sample: &Path, species: &str) -> Result<Self> {
        let fit = FieldConfig::load(&layout.fit_file())?;
        let base = base_colour(&fit, &layout.fit_file())?;
        let nca = GrainShaded::new(
            read_volume(&layout.volume())?,
            Some(&base.colour.white_balance),
        );
        let truth = truth_species(sample)?;
        let synthetic = truth.is_some();
        let fitted = layout.fit_dir().join(PROCEDURAL_FILE);
        let procedural: Box<dyn SolidTexture> = match truth {
            Some((t, photograph)) => Box::new(photographed(
                ProceduralWood::new(&t),
                &photograph,
                t.pith.fibre_axis(),
            )),
            None if fitted.is_file() => Box::new(GrainShaded::new(
                ProceduralWood::new(&SpeciesConfig::load(&fitted)?),
                Some(&base.colour.white_balance),
            )),
            None => Box::new(ProceduralWood::new(&species_on_field(species, &fit)?)),
        };
        Ok(Self {
            base: GrainShaded::new(base.clone(), Some(&base.colour.white_balance)),
            procedural,
            reference: reference_column(sample)?,
            synthetic,
            fit,
            nca,
        })
    }
}

/// The truth of a synthetic sample: its species and how it was photographed (plainly when
/// the sample predates `truth/photograph.toml`).
fn truth_species(sample: &Path) -> Result<Option<(SpeciesConfig, Photograph)>> {
    let path = sample.join("truth/species.toml");
    if !path.is_file() {
        return Ok(None);
    }
    let photograph = sample.join("truth/photograph.toml");
    let photograph = if photograph.is_file() {
        Photograph::load(&photograph)?
    } else {
        Photograph::default()
    };
    Ok(Some((SpeciesConfig::load(&path)?, photograph)))
}

/// A species preset's colours on the fitted growth field.
fn species_on_field(name: &str, fit: &FieldConfig) -> Result<SpeciesConfig> {
    let mut species = crate::presets::load_species_preset(name)?;
    species.pith = fit.pith.clone();
    species.growth = fit.growth.clone();
    species.knots = fit.knots.clone();
    Ok(species)
}

/// The base colour of a fit in real colour, for cuts and volumes.
fn base_colour(fit: &FieldConfig, path: &Path) -> Result<BaseColourTexture> {
    let colour = fit
        .base_colour
        .clone()
        .ok_or_else(|| XylemError::ConfigValue {
            path: path.to_path_buf(),
            key: "base_colour".into(),
            message: "is missing: the fit wrote no base colour".into(),
        })?;
    Ok(BaseColourTexture::new(
        GrowthField::from_config(fit),
        colour,
        ColourSpace::Shown(None),
    ))
}

/// Photos of the faces, and the true cuts when the sample has them.
fn reference_column(sample: &Path) -> Result<Vec<Option<Image2>>> {
    SHEET_ROWS
        .iter()
        .map(|row| {
            let path = match Face::parse(row) {
                Some(face) => sample.join(format!("{face}_col.png")),
                None => sample.join(format!("truth/{row}.png")),
            };
            path.is_file().then(|| load_rgb(&path)).transpose()
        })
        .collect()
}
