//! Volume exports for other tools: NumPy `.npy` (`io::npy`), Mitsuba 3 `.vol`, NRRD.

pub mod mitsuba;
pub mod nrrd;

use std::path::Path;
use std::str::FromStr;

use crate::error::{Result, XylemError};
use crate::volume::Volume;

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Npy,
    Vol,
    Nrrd,
}

impl FromStr for Format {
    type Err = XylemError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "npy" => Ok(Format::Npy),
            "vol" => Ok(Format::Vol),
            "nrrd" => Ok(Format::Nrrd),
            other => Err(XylemError::input(
                format!("--format {other:?}"),
                "expected npy, vol or nrrd",
            )),
        }
    }
}

/// Writes `volume` to `path` in `format` (atomically).
pub fn export(volume: &Volume, format: Format, path: &Path) -> Result<()> {
    match format {
        Format::Npy => crate::io::npy::write_volume(path, volume),
        Format::Vol => mitsuba::write_vol(path, volume),
        Format::Nrrd => nrrd::write_nrrd(path, volume),
    }
}
