//! Mitsuba 3 `gridvolume` files (`.vol`): binary, little-endian. Header: the bytes `VOL`,
//! version byte 3, int32 encoding (1 = float32), int32 x, y, z resolution, int32 channel
//! count, six float32 bounding-box values (xmin, ymin, zmin, xmax, ymax, zmax); then the data
//! with x varying fastest: `data[((z * ny + y) * nx + x) * channels + c]`.
//! xylem volumes are `[X, Y, Z, C]` (z fastest), so writing transposes; the bounding box is
//! the cube [-0.5, 0.5]^3, in which Mitsuba places voxel centres exactly where xylem does.

use std::path::Path;

use crate::error::{Result, XylemError};
use crate::export::{read_x_fastest, write_x_fastest};
use crate::io::write_atomic;
use crate::volume::Volume;

const HEADER_LEN: usize = 48;

/// Writes a volume as a Mitsuba 3 `.vol` file (atomically).
pub fn write_vol(path: &Path, volume: &Volume) -> Result<()> {
    let [nx, ny, nz] = volume.dims;
    let c = volume.channels;
    write_atomic(path, |w| {
        w.write_all(b"VOL")?;
        w.write_all(&[3u8])?;
        for v in [1i32, nx as i32, ny as i32, nz as i32, c as i32] {
            w.write_all(&v.to_le_bytes())?;
        }
        for v in [-0.5f32, -0.5, -0.5, 0.5, 0.5, 0.5] {
            w.write_all(&v.to_le_bytes())?;
        }
        write_x_fastest(w, volume)
    })
}

fn bad(path: &Path, message: impl Into<String>) -> XylemError {
    XylemError::input(path.display().to_string(), message)
}

fn i32_at(bytes: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"))
}

/// Reads a float32 Mitsuba `.vol` file back into `[X, Y, Z, C]` (and its bounding box).
pub fn read_vol(path: &Path) -> Result<(Volume, [f32; 6])> {
    let bytes = crate::io::read_bytes(path, "a Mitsuba .vol file")?;
    if bytes.len() < HEADER_LEN || &bytes[..3] != b"VOL" || bytes[3] != 3 {
        return Err(bad(
            path,
            "not a Mitsuba volume (expected the bytes 'VOL' and version 3)",
        ));
    }
    if i32_at(&bytes, 4) != 1 {
        return Err(bad(path, "only float32 encoding (1) is supported"));
    }
    let dims = [i32_at(&bytes, 8), i32_at(&bytes, 12), i32_at(&bytes, 16)];
    let channels = i32_at(&bytes, 20);
    if dims.iter().any(|&d| d <= 0) || channels <= 0 {
        return Err(bad(
            path,
            format!("bad dimensions {dims:?} x {channels} channels"),
        ));
    }
    let [nx, ny, nz] = dims.map(|d| d as usize);
    let c = channels as usize;
    let bbox: [f32; 6] = std::array::from_fn(|i| {
        f32::from_le_bytes(bytes[24 + 4 * i..28 + 4 * i].try_into().expect("4 bytes"))
    });
    let payload = &bytes[HEADER_LEN..];
    // Checked: crafted dimensions (each up to 2^31) overflow the byte count.
    let needed = [nx, ny, nz, c]
        .iter()
        .try_fold(4usize, |acc, &d| acc.checked_mul(d));
    if needed != Some(payload.len()) {
        let expected = needed.map_or("more than can be addressed".to_string(), |n| {
            format!("expected {n}")
        });
        return Err(bad(
            path,
            format!(
                "{} data bytes for {nx}x{ny}x{nz}x{c} float32 values ({expected})",
                payload.len()
            ),
        ));
    }
    let vol = read_x_fastest(payload, [nx, ny, nz], c);
    Ok((vol, bbox))
}
