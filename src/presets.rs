//! Built-in presets, compiled into the binary so the default demo needs no files. The same
//! files live under `configs/` for users to copy and edit.

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

/// The TOML text of a field preset.
pub fn field_preset(name: &str) -> Option<&'static str> {
    FIELD_PRESETS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
}

/// Preset names, for error messages.
pub fn field_preset_names() -> Vec<&'static str> {
    FIELD_PRESETS.iter().map(|(n, _)| *n).collect()
}

/// Parses a built-in field preset.
pub fn load_field_preset(name: &str) -> crate::Result<crate::field::FieldConfig> {
    let text = field_preset(name).ok_or_else(|| {
        crate::XylemError::input(
            format!("--preset {name:?}"),
            format!(
                "unknown field preset; built-in presets: {}",
                field_preset_names().join(", ")
            ),
        )
    })?;
    crate::field::FieldConfig::parse(text, std::path::Path::new(&format!("<preset {name}>")))
}
