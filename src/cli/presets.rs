//! Where a command's growth field comes from: a config file or a built-in preset.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::field::FieldConfig;
use xylem::presets::load_field_preset;

#[derive(Args, Debug)]
#[group(required = true, multiple = false)]
pub struct FieldSource {
    /// Growth-field config (TOML, see configs/fields/).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// A built-in preset: minimal, straight, far, distorted, knot_alive, knot_dead, knots.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
}

impl FieldSource {
    /// The config and a description of where it came from.
    pub fn load(&self) -> Result<(FieldConfig, String)> {
        if let Some(path) = &self.config {
            return Ok((FieldConfig::load(path)?, path.display().to_string()));
        }
        let name = self.preset.as_deref().unwrap_or_default();
        Ok((load_field_preset(name)?, format!("built-in preset {name}")))
    }
}
