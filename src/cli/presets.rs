//! Where a command's config comes from: a file or a built-in preset (growth fields and
//! species).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::config::ConfigFile;
use xylem::field::FieldConfig;
use xylem::presets::{load_field_preset, load_species_preset, species_preset_names};
use xylem::procedural::SpeciesConfig;

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

#[derive(Args, Debug)]
#[group(required = true, multiple = false)]
pub struct SpeciesSource {
    /// Species config of the procedural model (TOML, see configs/species/).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// A built-in species preset: oak, chestnut, maple, walnut, softwood, burl.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
}

impl SpeciesSource {
    /// The config and a description of where it came from.
    pub fn load(&self) -> Result<(SpeciesConfig, String)> {
        if let Some(path) = &self.config {
            return Ok((SpeciesConfig::load(path)?, path.display().to_string()));
        }
        let name = self.preset.as_deref().unwrap_or_default();
        Ok((
            load_species_preset(name)?,
            format!("built-in species preset {name}"),
        ))
    }
}

/// `--species NAME` of `run` and `demo`: a built-in species preset, checked when the command
/// line is parsed (before any stage runs).
pub fn species_name(name: &str) -> std::result::Result<String, String> {
    let names = species_preset_names();
    if names.contains(&name) {
        Ok(name.to_string())
    } else {
        Err(format!(
            "unknown species preset {name:?}; built-in presets: {}",
            names.join(", ")
        ))
    }
}

/// `--nca-preset`: the built-in NCA configs, as clap lists them.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum NcaPresetArg {
    /// 128^3 grid, 1500 iterations: the demo, about 8 minutes in all.
    Quick,
    /// Native 256 px / 256^3, 3000 iterations: about 21 minutes for CN03 on 2 cores.
    Quality,
}

impl From<NcaPresetArg> for xylem::presets::NcaPreset {
    fn from(arg: NcaPresetArg) -> Self {
        match arg {
            NcaPresetArg::Quick => Self::Quick,
            NcaPresetArg::Quality => Self::Quality,
        }
    }
}
