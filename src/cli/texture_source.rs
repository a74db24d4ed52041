//! Where a command's solid texture comes from (slice, render): a volume file, a growth field
//! (its ring image in grey) or a species config (procedural wood).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use glam::Vec3;
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField, RingImage};
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
