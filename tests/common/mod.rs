//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The real Mokume data folder: `XYLEM_MOKUME_DIR`, or `../shared/data/mokume` beside the
/// checkout. CI has it; a missing folder fails the test (set XYLEM_SKIP_REAL_DATA=1 to skip
/// explicitly on a machine without the data).
pub fn mokume_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("XYLEM_MOKUME_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mokume"));
    if dir.join("CN03").is_dir() && dir.join("H11").is_dir() {
        return Some(dir);
    }
    if std::env::var_os("XYLEM_SKIP_REAL_DATA").is_some() {
        eprintln!(
            "skipping: no Mokume data at {} (XYLEM_SKIP_REAL_DATA set)",
            dir.display()
        );
        return None;
    }
    panic!(
        "Mokume data not found at {}; set XYLEM_MOKUME_DIR (or XYLEM_SKIP_REAL_DATA=1 to skip)",
        dir.display()
    );
}

/// A fresh scratch folder for one test (removed first if a previous run left it).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("xylem-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}
