//! Where a command's solid texture comes from (render, export): a volume file, or a growth
//! field (its ring image in grey).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::field::{FieldConfig, GrowthField, RingImage};
use xylem::texture::SolidTexture;

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
}

impl TextureSource {
    /// The texture and a short description for captions and config copies.
    pub fn load(&self) -> Result<(Box<dyn SolidTexture>, String)> {
        if let Some(path) = &self.volume {
            let vol = xylem::io::npy::read_volume(path)?;
            return Ok((Box::new(vol), format!("volume {}", path.display())));
        }
        let path = self.field.as_ref().expect("clap requires one source");
        let field = GrowthField::from_config(&FieldConfig::load(path)?);
        Ok((
            Box::new(RingImage(field)),
            format!("field {}", path.display()),
        ))
    }
}
