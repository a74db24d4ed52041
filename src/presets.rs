//! Built-in presets, compiled into the binary so the default demo needs no files. The same
//! files live under `configs/` for users to copy and edit.

use std::path::Path;

use crate::XylemError;
use crate::config::ConfigFile;
use crate::field::FieldConfig;
use crate::procedural::SpeciesConfig;

/// Growth-field presets: (name, TOML text).
pub const FIELD_PRESETS: &[(&str, &str)] = &[
    ("minimal", include_str!("../configs/fields/minimal.toml")),
    ("straight", include_str!("../configs/fields/straight.toml")),
    ("far", include_str!("../configs/fields/far.toml")),
    (
        "distorted",
        include_str!("../configs/fields/distorted.toml"),
    ),
    (
        "knot_alive",
        include_str!("../configs/fields/knot_alive.toml"),
    ),
    (
        "knot_dead",
        include_str!("../configs/fields/knot_dead.toml"),
    ),
    ("knots", include_str!("../configs/fields/knots.toml")),
];

/// Species presets of the procedural wood model: (name, TOML text).
pub const SPECIES_PRESETS: &[(&str, &str)] = &[
    ("oak", include_str!("../configs/species/oak.toml")),
    ("chestnut", include_str!("../configs/species/chestnut.toml")),
    ("maple", include_str!("../configs/species/maple.toml")),
    ("walnut", include_str!("../configs/species/walnut.toml")),
    ("softwood", include_str!("../configs/species/softwood.toml")),
    ("burl", include_str!("../configs/species/burl.toml")),
];

fn find(presets: &[(&'static str, &'static str)], name: &str) -> Option<&'static str> {
    presets.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

fn names(presets: &[(&'static str, &'static str)]) -> Vec<&'static str> {
    presets.iter().map(|(n, _)| *n).collect()
}

fn unknown(kind: &str, name: &str, presets: &[(&'static str, &'static str)]) -> XylemError {
    XylemError::input(
        format!("$preset {name:?}"),
        format!(
            "unknown {kind} preset; built-in presets: {}",
            names(presets).join(", ")
        ),
    )
}

/// The TOML text of a field preset.
pub(crate) fn field_preset(name: &str) -> Option<&'static str> {
    find(FIELD_PRESETS, name)
}

/// Parses a built-in field preset.
pub fn load_field_preset(name: &str) -> crate::Result<FieldConfig> {
    let text = field_preset(name).ok_or_else(|| unknown("field", name, FIELD_PRESETS))?;
    FieldConfig::parse(text, Path::new(&format!("<preset {name}>")))
}

/// The TOML text of a species preset.
pub fn species_preset(name: &str) -> Option<&'static str> {
    find(SPECIES_PRESETS, name)
}

/// Species preset names, for error messages.
pub fn species_preset_names() -> Vec<&'static str> {
    names(SPECIES_PRESETS)
}

/// Parses a built-in species preset.
pub fn load_species_preset(name: &str) -> crate::Result<SpeciesConfig> {
    let text = species_preset(name).ok_or_else(|| unknown("species", name, SPECIES_PRESETS))?;
    SpeciesConfig::parse(text, Path::new(&format!("<species preset {name}>")))
}

/// The built-in NCA training configs: `configs/nca/quick.toml` (the demo) and
/// `configs/nca/quality.toml` (the default of `xylem run`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NcaPreset {
    /// 128^3 grid, 1500 iterations of 24^3 crops: the demo.
    Quick,
    /// Native 256 px / 256^3, 3000 iterations.
    Quality,
}

impl NcaPreset {
    pub fn name(self) -> &'static str {
        match self {
            NcaPreset::Quick => "quick",
            NcaPreset::Quality => "quality",
        }
    }

    /// The config's TOML text.
    pub fn text(self) -> &'static str {
        match self {
            NcaPreset::Quick => include_str!("../configs/nca/quick.toml"),
            NcaPreset::Quality => include_str!("../configs/nca/quality.toml"),
        }
    }
}
