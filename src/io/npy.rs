//! `.npy` (NumPy format 1.0) reading and writing of little-endian float32 arrays.

use std::path::Path;

use super::atomic::write_atomic;
use crate::error::{Result, XylemError};
use crate::volume::Volume;

const MAGIC: &[u8] = b"\x93NUMPY";

fn header(shape: &[usize]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut text = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {tuple}, }}");
    // Pad so that data starts at a multiple of 64 bytes (magic 6 + version 2 + length 2).
    let unpadded = MAGIC.len() + 2 + 2 + text.len() + 1;
    text.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    text.push('\n');
    let mut out = Vec::with_capacity(10 + text.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(text.len() as u16).to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out
}

/// Writes a C-order float32 array of `shape` atomically.
pub fn write_npy(path: &Path, shape: &[usize], data: &[f32]) -> Result<()> {
    let expected: usize = shape.iter().product();
    if expected != data.len() {
        return Err(XylemError::input(
            path.display().to_string(),
            format!("{} values for npy shape {shape:?}", data.len()),
        ));
    }
    write_atomic(path, |w| {
        w.write_all(&header(shape))?;
        for chunk in data.chunks(1 << 16) {
            let bytes: Vec<u8> = chunk.iter().flat_map(|v| v.to_le_bytes()).collect();
            w.write_all(&bytes)?;
        }
        Ok(())
    })
}

/// Writes a volume as `[X, Y, Z, C]` float32.
pub fn write_volume(path: &Path, volume: &Volume) -> Result<()> {
    let [x, y, z] = volume.dims;
    write_npy(path, &[x, y, z, volume.channels], &volume.data)
}

fn bad(path: &Path, message: impl Into<String>) -> XylemError {
    XylemError::input(path.display().to_string(), message)
}

/// Parses the header dictionary: only little-endian float32 in C order is accepted.
fn parse_header(path: &Path, text: &str) -> Result<Vec<usize>> {
    if header_value(text, "descr") != Some("'<f4'") {
        return Err(bad(
            path,
            format!("npy dtype must be little-endian float32 ('<f4'); header is {text:?}"),
        ));
    }
    if header_value(text, "fortran_order") != Some("False") {
        return Err(bad(
            path,
            "npy array must be in C order (fortran_order False)",
        ));
    }
    let start = text
        .find("'shape': (")
        .ok_or_else(|| bad(path, "npy header has no shape"))?
        + 10;
    let end = start
        + text[start..]
            .find(')')
            .ok_or_else(|| bad(path, "npy shape is not closed"))?;
    text[start..end]
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<usize>()
                .map_err(|_| bad(path, format!("npy shape entry {s:?} is not a size")))
        })
        .collect()
}

/// The literal after `'key': ` in a header dictionary, up to the next `,` or `}` (the
/// whole value, so `'<f4'` does not match a crafted `'<f4x'` or a key inside a string).
fn header_value<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    let pattern = format!("'{key}': ");
    let mut found = text.match_indices(&pattern);
    let (at, _) = found.next()?;
    if found.next().is_some() {
        return None; // a key given twice is not a header numpy writes
    }
    let rest = &text[at + pattern.len()..];
    let end = rest.find([',', '}'])?;
    Some(rest[..end].trim())
}

/// Reads a float32 `.npy` file: (shape, data).
pub fn read_npy(path: &Path) -> Result<(Vec<usize>, Vec<f32>)> {
    let bytes = super::read::read_bytes(path, "a .npy file")?;
    if bytes.len() < 10 || &bytes[..6] != MAGIC {
        return Err(bad(path, "not a .npy file (missing \\x93NUMPY magic)"));
    }
    let (header_len, offset) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 => {
            if bytes.len() < 12 {
                return Err(bad(path, "truncated npy header"));
            }
            (
                u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
                12,
            )
        }
        v => return Err(bad(path, format!("unsupported npy version {v}"))),
    };
    let data_start = offset + header_len;
    if bytes.len() < data_start {
        return Err(bad(path, "truncated npy header"));
    }
    let text = String::from_utf8_lossy(&bytes[offset..data_start]);
    let shape = parse_header(path, &text)?;
    let payload = &bytes[data_start..];
    // Checked: a crafted shape whose product wraps around would pass as an empty array.
    let count = shape
        .iter()
        .try_fold(4usize, |acc, &d| acc.checked_mul(d))
        .ok_or_else(|| bad(path, format!("npy shape {shape:?} is too large to address")))?
        / 4;
    if payload.len() != count * 4 {
        return Err(bad(
            path,
            format!(
                "npy shape {shape:?} needs {} bytes of data, file has {}",
                count * 4,
                payload.len()
            ),
        ));
    }
    let data = payload
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    Ok((shape, data))
}

/// Reads a `[X, Y, Z, C]` float32 volume.
pub fn read_volume(path: &Path) -> Result<Volume> {
    let (shape, data) = read_npy(path)?;
    if shape.len() != 4 {
        return Err(bad(
            path,
            format!("volume must have shape [X, Y, Z, C], got {shape:?}"),
        ));
    }
    if shape.contains(&0) {
        return Err(bad(
            path,
            format!("volume shape {shape:?} has an empty axis; expected [X, Y, Z, C], all > 0"),
        ));
    }
    Volume::from_data([shape[0], shape[1], shape[2]], shape[3], data)
}
