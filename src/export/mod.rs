//! Volume exports for other tools: NumPy `.npy` (`io::npy`), Mitsuba 3 `.vol` and a whole
//! Mitsuba scene, NRRD (VTK/ParaView, 3D Slicer), OpenVDB (Blender, Houdini, ...).
//!
//! Colour is clamped to [0, 1] in every format and written linear for renderers (`.vol`,
//! `.vdb`, the Mitsuba scene), display sRGB for viewers (`.npy`, `.nrrd`); see `values`.

pub mod mitsuba;
pub mod mitsuba_scene;
pub mod nrrd;
pub mod values;
pub mod vdb;

use std::path::Path;
use std::str::FromStr;

use crate::error::{Result, XylemError};
use crate::render::RenderConfig;
use crate::volume::Volume;
pub use mitsuba_scene::SceneSize;
pub use values::{Encoding, Values};
use vdb::{VdbClass, VdbGrid, VdbValues};

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Npy,
    Vol,
    Nrrd,
    Vdb,
    /// A folder with `scene.xml` and `color.vol`.
    Mitsuba,
}

const FORMATS: &str = "npy, vol, nrrd, vdb or mitsuba";

impl FromStr for Format {
    type Err = XylemError;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "npy" => Ok(Format::Npy),
            "vol" => Ok(Format::Vol),
            "nrrd" => Ok(Format::Nrrd),
            "vdb" => Ok(Format::Vdb),
            "mitsuba" => Ok(Format::Mitsuba),
            other => Err(XylemError::input(
                format!("format {other:?}"),
                format!("expected {FORMATS}"),
            )),
        }
    }
}

impl Format {
    /// The format a file name asks for by its extension (`.npy`, `.vol`, `.nrrd`, `.vdb`);
    /// a Mitsuba scene is a folder and is only chosen explicitly.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        match ext.to_ascii_lowercase().as_str() {
            "npy" | "vol" | "nrrd" | "vdb" => ext.parse(),
            _ => Err(XylemError::input(
                path.display().to_string(),
                format!(
                    "cannot tell the format from the extension {ext:?}: name the file \
                     .npy, .vol, .nrrd or .vdb, or give the format ({FORMATS})"
                ),
            )),
        }
    }

    /// How this format stores colour.
    pub fn encoding(self) -> Encoding {
        match self {
            Format::Npy | Format::Nrrd => Encoding::DisplaySrgb,
            Format::Vol | Format::Vdb | Format::Mitsuba => Encoding::Linear,
        }
    }
}

/// What an export wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExportSummary {
    /// Colour values outside [0, 1] that were clamped.
    pub clamped: usize,
    /// All values of the volume.
    pub total: usize,
}

/// Writes `volume` to `path` in `format` (atomically; a Mitsuba scene is a folder `path`).
/// `what` names the input in errors.
pub fn export(
    volume: &Volume,
    values: Values,
    format: Format,
    path: &Path,
    what: &str,
) -> Result<ExportSummary> {
    let prepared = values::prepare(volume, values, format.encoding(), what)?;
    let ready = prepared.volume.as_ref();
    match format {
        Format::Npy => crate::io::npy::write_volume(path, ready)?,
        Format::Vol => mitsuba::write_vol(path, ready)?,
        Format::Nrrd => nrrd::write_nrrd(path, ready, values)?,
        Format::Vdb => vdb::write_vdb(path, &[main_grid(ready, values, what)?])?,
        Format::Mitsuba => {
            let size = SceneSize {
                width: 800,
                height: 800,
                spp: 64,
            };
            check_scene_values(values, what)?;
            mitsuba_scene::write_scene(path, ready, &RenderConfig::default_config(), size)?;
        }
    }
    Ok(ExportSummary {
        clamped: prepared.clamped,
        total: volume.data.len(),
    })
}

/// Writes a Mitsuba scene of a colour volume into the folder `dir` with the camera and light
/// of `cfg` (see `mitsuba_scene`).
pub fn export_scene(
    volume: &Volume,
    dir: &Path,
    cfg: &RenderConfig,
    size: SceneSize,
    what: &str,
) -> Result<ExportSummary> {
    let prepared = values::prepare(volume, Values::Colour, Encoding::Linear, what)?;
    mitsuba_scene::write_scene(dir, prepared.volume.as_ref(), cfg, size)?;
    Ok(ExportSummary {
        clamped: prepared.clamped,
        total: volume.data.len(),
    })
}

fn check_scene_values(values: Values, what: &str) -> Result<()> {
    if values == Values::Colour {
        return Ok(());
    }
    Err(XylemError::input(
        what,
        "a Mitsuba scene shows colour: export the volume as colour",
    ))
}

/// The grid a volume becomes in a `.vdb` file: colour is the Vec3S grid `color` (the
/// attribute name Blender's volume shaders read); data keeps its channel count under
/// `values`. Neither is a density, so both are of class "unknown" (a fog volume would be
/// taken for one).
pub fn main_grid<'a>(volume: &'a Volume, values: Values, what: &str) -> Result<VdbGrid<'a>> {
    let (name, class) = match values {
        Values::Colour => ("color", VdbClass::Unknown),
        Values::Data => ("values", VdbClass::Unknown),
    };
    let values = match volume.channels {
        1 => VdbValues::Float(volume),
        3 => VdbValues::Vec3(volume),
        c => {
            return Err(XylemError::input(
                what,
                format!("OpenVDB grids hold 1 or 3 values per voxel; this volume has {c}"),
            ));
        }
    };
    Ok(VdbGrid {
        name,
        values,
        class,
    })
}

/// Writes the voxels of `volume` with x varying fastest, then y, then z, the channels of one
/// voxel together (`.vol`, NRRD), from xylem's z-fastest `[X, Y, Z, C]`.
pub(crate) fn write_x_fastest(w: &mut dyn std::io::Write, volume: &Volume) -> std::io::Result<()> {
    let [nx, ny, nz] = volume.dims;
    let mut row = Vec::with_capacity(nx * volume.channels * 4);
    for k in 0..nz {
        for j in 0..ny {
            row.clear();
            for i in 0..nx {
                for v in volume.voxel(i, j, k) {
                    row.extend_from_slice(&v.to_le_bytes());
                }
            }
            w.write_all(&row)?;
        }
    }
    Ok(())
}

/// The inverse of [`write_x_fastest`]: little-endian float32 `payload` (its length checked by
/// the caller) into `[X, Y, Z, C]`.
pub(crate) fn read_x_fastest(payload: &[u8], dims: [usize; 3], channels: usize) -> Volume {
    let [nx, ny, _] = dims;
    let mut volume = Volume::zeros(dims, channels);
    for (n, chunk) in payload.chunks_exact(4).enumerate() {
        let (ch, voxel) = (n % channels, n / channels);
        let (i, j, k) = (voxel % nx, (voxel / nx) % ny, voxel / (nx * ny));
        let o = volume.offset(i, j, k) + ch;
        volume.data[o] = f32::from_le_bytes(chunk.try_into().expect("4 bytes"));
    }
    volume
}
