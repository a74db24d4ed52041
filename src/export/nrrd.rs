//! NRRD files (`.nrrd`, raw float32 little-endian, header + data in one file).
//!
//! Axis order, fastest first (the NRRD convention): channel, z, y, x, which is exactly the
//! memory order of xylem's `[X, Y, Z, C]` volumes, so the data is written as is. The header's
//! `space directions` and `space origin` place voxel (i, j, k) at its xylem voxel centre
//! ((i + 0.5)/nx - 0.5, ...), so tools that honour them (3D Slicer, pynrrd + numpy) see the
//! volume in cube coordinates.

use std::path::Path;

use crate::error::{Result, XylemError};
use crate::io::write_atomic;
use crate::volume::Volume;

fn header(volume: &Volume) -> String {
    let [nx, ny, nz] = volume.dims;
    let step = |n: usize| 1.0 / n as f64;
    let origin = |n: usize| -0.5 + 0.5 / n as f64;
    format!(
        "NRRD0004\n\
         # xylem volume: axes fastest first = channel, z, y, x (xylem [X, Y, Z, C] in memory)\n\
         type: float\n\
         dimension: 4\n\
         space: right-anterior-superior\n\
         sizes: {c} {nz} {ny} {nx}\n\
         space directions: none (0,0,{sz}) (0,{sy},0) ({sx},0,0)\n\
         kinds: vector domain domain domain\n\
         labels: \"channel\" \"z\" \"y\" \"x\"\n\
         endian: little\n\
         encoding: raw\n\
         space origin: ({ox},{oy},{oz})\n\n",
        c = volume.channels,
        sx = step(nx),
        sy = step(ny),
        sz = step(nz),
        ox = origin(nx),
        oy = origin(ny),
        oz = origin(nz),
    )
}

/// Writes a volume as NRRD (atomically).
pub fn write_nrrd(path: &Path, volume: &Volume) -> Result<()> {
    write_atomic(path, |w| {
        w.write_all(header(volume).as_bytes())?;
        for chunk in volume.data.chunks(1 << 16) {
            let bytes: Vec<u8> = chunk.iter().flat_map(|v| v.to_le_bytes()).collect();
            w.write_all(&bytes)?;
        }
        Ok(())
    })
}

fn bad(path: &Path, message: impl Into<String>) -> XylemError {
    XylemError::input(path.display().to_string(), message)
}

/// Reads a raw float32 NRRD written by [`write_nrrd`] (sizes `C Z Y X`).
pub fn read_nrrd(path: &Path) -> Result<Volume> {
    let bytes = std::fs::read(path).map_err(|e| XylemError::io(path, e))?;
    let split = bytes
        .windows(2)
        .position(|w| w == b"\n\n")
        .ok_or_else(|| bad(path, "NRRD header does not end with a blank line"))?;
    let text = String::from_utf8_lossy(&bytes[..split]);
    if !text.starts_with("NRRD") {
        return Err(bad(path, "not a NRRD file"));
    }
    let field = |name: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("{name}: ")))
            .ok_or_else(|| bad(path, format!("NRRD header lacks `{name}`")))
    };
    if field("type")? != "float" || field("encoding")? != "raw" || field("endian")? != "little" {
        return Err(bad(path, "only raw little-endian float NRRD is supported"));
    }
    let sizes: Vec<usize> = field("sizes")?
        .split_whitespace()
        .map(|s| {
            s.parse()
                .map_err(|_| bad(path, format!("bad NRRD size {s:?}")))
        })
        .collect::<Result<_>>()?;
    let [c, nz, ny, nx] = sizes[..] else {
        return Err(bad(
            path,
            format!("expected 4 sizes (channel z y x), got {sizes:?}"),
        ));
    };
    let data: Vec<f32> = bytes[split + 2..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
        .collect();
    Volume::from_data([nx, ny, nz], c, data).map_err(|e| bad(path, e.to_string()))
}
