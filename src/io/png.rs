//! PNG reading and writing for [`Image2`]. Values are clamped to [0, 1] and quantised to
//! 8 bits on write; 1 channel is written as grey, 3 as RGB, 4 as RGBA.

use std::io::Cursor;
use std::path::Path;

use image::codecs::png::PngDecoder;
use image::{DynamicImage, ImageDecoder, ImageFormat};

use super::atomic::write_bytes_atomic;
use crate::error::{Result, XylemError};
use crate::image2::Image2;

fn to_u8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Encodes an image as PNG bytes.
pub(crate) fn encode_png(img: &Image2) -> Result<Vec<u8>> {
    let bytes: Vec<u8> = img.data.iter().map(|&v| to_u8(v)).collect();
    let (w, h) = (img.width as u32, img.height as u32);
    let dynamic = match img.channels {
        1 => image::GrayImage::from_raw(w, h, bytes).map(DynamicImage::ImageLuma8),
        3 => image::RgbImage::from_raw(w, h, bytes).map(DynamicImage::ImageRgb8),
        4 => image::RgbaImage::from_raw(w, h, bytes).map(DynamicImage::ImageRgba8),
        c => {
            return Err(XylemError::input(
                "PNG encoding",
                format!("{c} channels; PNG output takes 1 (grey), 3 (RGB) or 4 (RGBA)"),
            ));
        }
    }
    .ok_or_else(|| {
        XylemError::input(
            "PNG encoding",
            "image buffer size does not match its dimensions",
        )
    })?;
    let mut out = Cursor::new(Vec::new());
    dynamic
        .write_to(&mut out, ImageFormat::Png)
        .map_err(|e| XylemError::input("PNG encoding", e.to_string()))?;
    Ok(out.into_inner())
}

/// Writes a PNG atomically (temporary file, then rename).
pub fn save_png(img: &Image2, path: &Path) -> Result<()> {
    write_bytes_atomic(path, &encode_png(img)?)
}

/// Largest ratio of decoded pixel bytes to file bytes a PNG can have: deflate, which holds
/// PNG pixel data, compresses at most about 1032:1, so a file claiming more pixels than
/// this allows is truncated or crafted (a 53-byte file claiming 16384 x 16384 pixels),
/// and is refused before its pixel buffer is allocated.
const MAX_PNG_RATIO: u64 = 1100;

fn open(path: &Path) -> Result<DynamicImage> {
    if !path.exists() {
        return Err(XylemError::image(path, "file not found"));
    }
    let bytes = super::read::read_bytes(path, "a PNG image")?;
    let undecodable = |e: image::ImageError| {
        XylemError::image(path, format!("cannot decode as a PNG image: {e}"))
    };
    // Limits all the decoder's allocations (text and colour-profile chunks included) by
    // what the file's size can hold.
    let budget = MAX_PNG_RATIO * bytes.len() as u64 + (1 << 20);
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(budget);
    let decoder = PngDecoder::with_limits(Cursor::new(&bytes[..]), limits).map_err(undecodable)?;
    let (w, h) = decoder.dimensions();
    let pixel_bytes =
        u64::from(w) * u64::from(h) * u64::from(decoder.color_type().bytes_per_pixel());
    if pixel_bytes > budget {
        return Err(XylemError::image(
            path,
            format!(
                "claims {w}x{h} pixels ({pixel_bytes} bytes decoded) in a file of {} bytes, \
                 more than PNG compression can hold: the file is truncated or damaged",
                bytes.len()
            ),
        ));
    }
    DynamicImage::from_decoder(decoder).map_err(undecodable)
}

/// Reads a PNG as RGB in [0, 1] (grey images are expanded).
pub fn load_rgb(path: &Path) -> Result<Image2> {
    let img = open(path)?.to_rgb8();
    let (w, h) = img.dimensions();
    from_bytes(w, h, 3, img.into_raw())
}

/// Reads a PNG as one grey channel in [0, 1] (colour images are converted to luma).
pub fn load_gray(path: &Path) -> Result<Image2> {
    let img = open(path)?.to_luma8();
    let (w, h) = img.dimensions();
    from_bytes(w, h, 1, img.into_raw())
}

/// 8-bit samples as an image in [0, 1].
fn from_bytes(width: u32, height: u32, channels: usize, bytes: Vec<u8>) -> Result<Image2> {
    let data = bytes.into_iter().map(|b| b as f32 / 255.0).collect();
    Image2::from_data(width as usize, height as usize, channels, data)
}
