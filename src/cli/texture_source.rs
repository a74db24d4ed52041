//! Where a command's solid texture comes from (slice, render): a volume file, a growth field
//! (its ring image in grey) or a species config (procedural wood), and how it is seen: with a
//! fit's grain shading or plain.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use glam::Vec3;
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrainShaded, GrowthField, RingImage};
use xylem::procedural::{ProceduralWood, SpeciesConfig, WithFibreDirection};
use xylem::texture::{FirstChannels, SolidTexture};

#[derive(Args, Debug)]
#[group(required = true, multiple = false)]
pub struct TextureSource {
    /// A volume (`.npy`, float32 [X, Y, Z, C]; RGB first, fibre direction in channels 3..6
    /// if present), looked up trilinearly.
    #[arg(long, value_name = "V.npy")]
    pub volume: Option<PathBuf>,
    /// A growth-field config; its ring localisation image I(G) is shown in grey.
    #[arg(long, value_name = "FILE")]
    pub field: Option<PathBuf>,
    /// A species config (TOML, see configs/species/): the procedural wood model.
    #[arg(long, value_name = "FILE")]
    pub procedural: Option<PathBuf>,
}

/// `--grain-shading FIT`: see the texture with a fit's grain shading (end grain darker than
/// side grain, DESIGN "Grain shading"), as `xylem run` and `xylem synth` show the NCA's
/// volume; a texture file alone carries no white balance, so slices and renders of it are
/// plain without this.
#[derive(Args, Debug)]
pub struct ShadingSource {
    /// A fit (`fit.toml` of `xylem fit`, or a folder holding one) whose grain shading the
    /// texture is seen with: for a volume or procedural model at that fit's white balance
    /// (a run's `synth/volume.npy`, `fit/procedural.toml`).
    #[arg(long, value_name = "FIT")]
    pub grain_shading: Option<PathBuf>,
}

impl ShadingSource {
    /// `texture`, seen with the fit's grain shading when one is given (a fit without one,
    /// where the photos did not show it, leaves the texture plain).
    pub fn apply(&self, texture: Box<dyn SolidTexture>) -> Result<Box<dyn SolidTexture>> {
        let Some(path) = &self.grain_shading else {
            return Ok(texture);
        };
        let file = if path.is_dir() {
            path.join("fit.toml")
        } else {
            path.clone()
        };
        let fit = FieldConfig::load(&file)?;
        let Some(colour) = fit.base_colour else {
            anyhow::bail!(
                "{}: --grain-shading needs a fit with a [base_colour] section (the fit.toml \
                 that `xylem fit` writes)",
                file.display()
            );
        };
        Ok(Box::new(GrainShaded::new(
            texture,
            Some(&colour.white_balance),
        )))
    }
}

/// The procedural model with its fibre direction in channels 3..6 (owned, for renders).
struct ProceduralWithFibres(ProceduralWood);

impl SolidTexture for ProceduralWithFibres {
    fn channels(&self) -> usize {
        WithFibreDirection(&self.0).channels()
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        WithFibreDirection(&self.0).eval(p, out)
    }
}

impl TextureSource {
    /// The texture with every channel it has (colour first; a procedural model adds its
    /// fibre direction), and a short description for messages.
    pub fn load(&self) -> Result<(Box<dyn SolidTexture>, String)> {
        if let Some(path) = &self.volume {
            let vol = xylem::io::npy::read_volume(path)?;
            return Ok((Box::new(vol), format!("volume {}", path.display())));
        }
        if let Some(path) = &self.procedural {
            let wood = ProceduralWood::new(&SpeciesConfig::load(path)?);
            return Ok((
                Box::new(ProceduralWithFibres(wood)),
                format!("species {}", path.display()),
            ));
        }
        let path = self.field.as_ref().expect("clap requires one source");
        let field = GrowthField::from_config(&FieldConfig::load(path)?);
        Ok((
            Box::new(RingImage(field)),
            format!("field {}", path.display()),
        ))
    }

    /// The texture's colour only (at most 3 channels), for images.
    pub fn load_colour(&self) -> Result<(Box<dyn SolidTexture>, String)> {
        let (texture, what) = self.load()?;
        let n = texture.channels().min(3);
        Ok((Box::new(FirstChannels { inner: texture, n }), what))
    }
}
