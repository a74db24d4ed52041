//! NRRD files (`.nrrd`, raw float32 little-endian, header + data in one file).
//!
//! Laid out for the readers people use (VTK/ParaView's `vtkNrrdReader`, 3D Slicer/ITK,
//! pynrrd): x varies fastest, then y, then z, with the channels of one voxel together, so
//! `sizes: C X Y Z` (a 1-channel volume drops the channel axis). VTK ignores `space
//! directions`, so only x-fastest data gives it the right axes; `space` comes after `sizes`
//! because VTK's reader resets its dimension count when it meets `space`. Distances are in
//! centimetres (`space units`, 1 cube unit = 4 cm) and `space origin` is the centre of voxel
//! (0, 0, 0), so tools that honour the geometry see the 4 cm cube centred at the origin.
//! Colour is written as display sRGB with kind `RGB-color`.

use std::path::Path;

use crate::error::{Result, XylemError};
use crate::export::values::Values;
use crate::export::{read_x_fastest, write_x_fastest};
use crate::frame::CM_PER_UNIT;
use crate::io::write_atomic;
use crate::volume::Volume;

fn header(volume: &Volume, values: Values) -> String {
    let [nx, ny, nz] = volume.dims;
    let c = volume.channels;
    let step = |n: usize| f64::from(CM_PER_UNIT) / n as f64;
    // (0.5 - n/2) / n cube units, in one rounding so -1.6 prints as -1.6.
    let origin = |n: usize| f64::from(CM_PER_UNIT) * (1.0 - n as f64) / (2.0 * n as f64);
    let (dimension, sizes, kinds, labels, none) = if c == 1 {
        (3, format!("{nx} {ny} {nz}"), "", "", "")
    } else {
        let kind = if values == Values::Colour && c == 3 {
            "RGB-color "
        } else {
            "vector "
        };
        (
            4,
            format!("{c} {nx} {ny} {nz}"),
            kind,
            "\"channel\" ",
            "none ",
        )
    };
    format!(
        "NRRD0004\n\
         # xylem volume: x fastest, then y, z; one voxel per xylem voxel (cube [-2, 2] cm)\n\
         type: float\n\
         dimension: {dimension}\n\
         sizes: {sizes}\n\
         kinds: {kinds}domain domain domain\n\
         labels: {labels}\"x\" \"y\" \"z\"\n\
         endian: little\n\
         encoding: raw\n\
         space dimension: 3\n\
         space directions: {none}({sx},0,0) (0,{sy},0) (0,0,{sz})\n\
         space origin: ({ox},{oy},{oz})\n\
         space units: \"cm\" \"cm\" \"cm\"\n\n",
        sx = step(nx),
        sy = step(ny),
        sz = step(nz),
        ox = origin(nx),
        oy = origin(ny),
        oz = origin(nz),
    )
}

/// Writes a volume as NRRD (atomically); `values` sets the channel kind.
pub fn write_nrrd(path: &Path, volume: &Volume, values: Values) -> Result<()> {
    write_atomic(path, |w| {
        w.write_all(header(volume, values).as_bytes())?;
        write_x_fastest(w, volume)
    })
}

fn bad(path: &Path, message: impl Into<String>) -> XylemError {
    XylemError::input(path.display().to_string(), message)
}

/// Reads a raw float32 NRRD written by [`write_nrrd`] (sizes `[C] X Y Z`, x fastest).
pub fn read_nrrd(path: &Path) -> Result<Volume> {
    let bytes = crate::io::read_bytes(path, "a NRRD file")?;
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
    let (c, [nx, ny, nz]) = match sizes[..] {
        [nx, ny, nz] => (1, [nx, ny, nz]),
        [c, nx, ny, nz] => (c, [nx, ny, nz]),
        _ => {
            return Err(bad(
                path,
                format!("expected 3 or 4 sizes ([channel] x y z), got {sizes:?}"),
            ));
        }
    };
    if c == 0 || [nx, ny, nz].contains(&0) {
        return Err(bad(
            path,
            format!("sizes {sizes:?}: expected every size > 0 (an empty volume)"),
        ));
    }
    let payload = &bytes[split + 2..];
    let count = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(nz))
        .and_then(|n| n.checked_mul(c))
        .filter(|&n| n.checked_mul(4) == Some(payload.len()))
        .ok_or_else(|| {
            bad(
                path,
                format!("{} data bytes for sizes {sizes:?} float32", payload.len()),
            )
        })?;
    Ok(read_x_fastest(&payload[..4 * count], [nx, ny, nz], c))
}
