//! Reading whole input files. Only regular files are opened: reading a FIFO with no writer
//! blocks forever (a `mkfifo` named like a volume or config hung `slice` and `field`), and a
//! folder or device is never what a user meant.

use std::path::Path;

use crate::error::{Result, XylemError};

/// Refuses `path` unless it is a regular file (following links); `expected` says what it
/// should be ("a .npy file"). A path that does not exist is left to the read's own error.
fn check_regular(path: &Path, expected: &str) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => Err(XylemError::input(
            path.display().to_string(),
            format!("is not a regular file (a folder, FIFO or device); expected {expected}"),
        )),
        _ => Ok(()),
    }
}

/// The bytes of a regular file.
pub fn read_bytes(path: &Path, expected: &str) -> Result<Vec<u8>> {
    check_regular(path, expected)?;
    std::fs::read(path).map_err(|e| XylemError::io(path, e))
}

/// The text of a regular file (UTF-8).
pub(crate) fn read_text(path: &Path, expected: &str) -> Result<String> {
    check_regular(path, expected)?;
    std::fs::read_to_string(path).map_err(|e| XylemError::io(path, e))
}
