//! Shared by the fit benchmarks (`bench_fit.rs`, `bench_rings.rs`): where the real samples
//! are, their Markdown tables' headers and means.

use std::path::PathBuf;

/// The real Mokume samples: `XYLEM_MOKUME_DIR`, or `../shared/data/mokume` beside the
/// checkout.
pub fn mokume_dir() -> PathBuf {
    std::env::var_os("XYLEM_MOKUME_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mokume"))
}

/// Prints the header and rule of a Markdown table whose columns are `columns`, separated
/// by " | ".
pub fn table_header(columns: &str) {
    println!("| {columns} |");
    println!("|{}", "---|".repeat(columns.split(" | ").count()));
}

/// The mean of `values` (0 for none).
pub fn mean(values: impl IntoIterator<Item = f32>) -> f32 {
    let v: Vec<f32> = values.into_iter().collect();
    v.iter().sum::<f32>() / v.len().max(1) as f32
}
