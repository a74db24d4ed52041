//! Writes a comparison sheet of two species presets and the ring image of a field, to look
//! at the sheet layout: `cargo run --release --example sheet_preview -- OUT.png`.

use xylem::field::{GrowthField, RingImage};
use xylem::io::save_png;
use xylem::presets::{load_field_preset, load_species_preset};
use xylem::procedural::ProceduralWood;
use xylem::report::{Column, comparison_sheet};

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "sheet_preview.png".into());
    let oak = ProceduralWood::new(&load_species_preset("oak").unwrap());
    let soft = ProceduralWood::new(&load_species_preset("softwood").unwrap());
    let field = GrowthField::from_config(&load_field_preset("knots").unwrap());
    let rings = RingImage(&field);
    let columns = vec![
        ("oak".to_string(), Column::Texture(&oak)),
        ("softwood".to_string(), Column::Texture(&soft)),
        ("rings".to_string(), Column::Texture(&rings)),
        ("missing".to_string(), Column::Images(vec![])),
    ];
    save_png(&comparison_sheet(&columns, 96), std::path::Path::new(&out)).unwrap();
}
