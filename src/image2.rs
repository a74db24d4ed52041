//! A small float image: row-major `[H, W, C]`, values nominally in [0, 1].
//!
//! Slices of solid textures, face photos and ring images all travel as `Image2`; conversion
//! to 8-bit happens only when a PNG is written (`io::png`).

use std::borrow::Borrow;

use crate::error::{Result, XylemError};

#[derive(Clone, Debug, PartialEq)]
pub struct Image2 {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    /// `[H, W, C]`, row-major.
    pub data: Vec<f32>,
}

impl Image2 {
    /// An image filled with `value`.
    pub fn filled(width: usize, height: usize, channels: usize, value: f32) -> Self {
        Self {
            width,
            height,
            channels,
            data: vec![value; width * height * channels],
        }
    }

    /// Wraps existing `[H, W, C]` data, checking its length.
    pub fn from_data(width: usize, height: usize, channels: usize, data: Vec<f32>) -> Result<Self> {
        if data.len() != width * height * channels {
            return Err(XylemError::input(
                "image data",
                format!(
                    "{} values for a {width}x{height}x{channels} image (expected {})",
                    data.len(),
                    width * height * channels
                ),
            ));
        }
        Ok(Self {
            width,
            height,
            channels,
            data,
        })
    }

    fn offset(&self, row: usize, col: usize) -> usize {
        (row * self.width + col) * self.channels
    }

    /// The channel values of one pixel.
    pub fn pixel(&self, row: usize, col: usize) -> &[f32] {
        let o = self.offset(row, col);
        &self.data[o..o + self.channels]
    }

    pub fn pixel_mut(&mut self, row: usize, col: usize) -> &mut [f32] {
        let o = self.offset(row, col);
        let c = self.channels;
        &mut self.data[o..o + c]
    }

    pub fn get(&self, row: usize, col: usize, channel: usize) -> f32 {
        self.data[self.offset(row, col) + channel]
    }

    /// Bilinear lookup at continuous pixel coordinates (pixel centres at integers), clamped at
    /// the border.
    pub fn bilinear(&self, row: f32, col: f32, channel: usize) -> f32 {
        let r = row.clamp(0.0, (self.height - 1) as f32);
        let c = col.clamp(0.0, (self.width - 1) as f32);
        let (r0, c0) = (r.floor() as usize, c.floor() as usize);
        let (r1, c1) = ((r0 + 1).min(self.height - 1), (c0 + 1).min(self.width - 1));
        let (fr, fc) = (r - r0 as f32, c - c0 as f32);
        let top = self.get(r0, c0, channel) * (1.0 - fc) + self.get(r0, c1, channel) * fc;
        let bottom = self.get(r1, c0, channel) * (1.0 - fc) + self.get(r1, c1, channel) * fc;
        top * (1.0 - fr) + bottom * fr
    }

    /// One channel as a single-channel image.
    pub fn channel(&self, channel: usize) -> Image2 {
        let data = self
            .data
            .iter()
            .skip(channel)
            .step_by(self.channels)
            .copied()
            .collect();
        self.grey_of_same_size(data)
    }

    /// A one-channel image of this one's size holding `data` (`height * width` values).
    fn grey_of_same_size(&self, data: Vec<f32>) -> Image2 {
        Image2 {
            width: self.width,
            height: self.height,
            channels: 1,
            data,
        }
    }

    /// Rec. 709 luminance of an RGB image (a grey image is returned as is).
    pub fn luminance(&self) -> Image2 {
        if self.channels < 3 {
            return self.channel(0);
        }
        let data = self
            .data
            .chunks_exact(self.channels)
            .map(|p| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
            .collect();
        self.grey_of_same_size(data)
    }

    /// The image with `channels` channels: grey is repeated, extra channels are dropped.
    pub(crate) fn with_channels(&self, channels: usize) -> Image2 {
        if channels == self.channels {
            return self.clone();
        }
        let mut out = Image2::filled(self.width, self.height, channels, 1.0);
        for (dst, src) in out
            .data
            .chunks_exact_mut(channels)
            .zip(self.data.chunks_exact(self.channels))
        {
            for (c, d) in dst.iter_mut().enumerate() {
                *d = if self.channels == 1 {
                    src[0]
                } else {
                    src[c.min(self.channels - 1)]
                };
            }
        }
        out
    }

    /// Copies `src` into this image with its top-left corner at (row, col); both must have the
    /// same channel count. Parts falling outside are clipped.
    pub(crate) fn blit(&mut self, src: &Image2, row: usize, col: usize) {
        assert_eq!(
            self.channels, src.channels,
            "blit needs equal channel counts"
        );
        for r in 0..src.height.min(self.height.saturating_sub(row)) {
            let w = src.width.min(self.width.saturating_sub(col));
            let d = self.offset(row + r, col);
            let s = src.offset(r, 0);
            self.data[d..d + w * self.channels]
                .copy_from_slice(&src.data[s..s + w * self.channels]);
        }
    }

    /// The `width` x `height` window with its top-left corner at (row, col); an error if it
    /// does not lie inside the image.
    pub fn crop(&self, row: usize, col: usize, width: usize, height: usize) -> Result<Image2> {
        if row + height > self.height || col + width > self.width {
            return Err(XylemError::input(
                "image crop",
                format!(
                    "{width}x{height} at row {row}, column {col} does not fit a {}x{} image",
                    self.width, self.height
                ),
            ));
        }
        let mut data = Vec::with_capacity(width * height * self.channels);
        for r in row..row + height {
            let start = self.offset(r, col);
            data.extend_from_slice(&self.data[start..start + width * self.channels]);
        }
        Image2::from_data(width, height, self.channels, data)
    }

    /// Images placed side by side (left to right) with `gap` pixels of `background` between.
    pub fn hstack<I: Borrow<Image2>>(images: &[I], gap: usize, background: f32) -> Image2 {
        Self::stack(images, gap, background, true)
    }

    /// Images placed one below the other with `gap` pixels of `background` between.
    pub fn vstack<I: Borrow<Image2>>(images: &[I], gap: usize, background: f32) -> Image2 {
        Self::stack(images, gap, background, false)
    }

    /// [`Self::hstack`] (`across`) or [`Self::vstack`]: the images follow each other along
    /// one axis and the output is as thick as the thickest across the other.
    fn stack<I: Borrow<Image2>>(images: &[I], gap: usize, background: f32, across: bool) -> Image2 {
        let images: Vec<&Image2> = images.iter().map(Borrow::borrow).collect();
        let channels = images.iter().map(|i| i.channels).max().unwrap_or(1);
        let along = |i: &Image2| if across { i.width } else { i.height };
        let beside = |i: &Image2| if across { i.height } else { i.width };
        let length =
            images.iter().map(|i| along(i)).sum::<usize>() + gap * images.len().saturating_sub(1);
        let thickness = images.iter().map(|i| beside(i)).max().unwrap_or(0);
        let (width, height) = if across {
            (length, thickness)
        } else {
            (thickness, length)
        };
        let mut out = Image2::filled(width, height, channels, background);
        let mut at = 0;
        for img in images {
            let (row, col) = if across { (0, at) } else { (at, 0) };
            out.blit(&img.with_channels(channels), row, col);
            at += along(img) + gap;
        }
        out
    }

    /// Mean of each channel.
    pub fn channel_means(&self) -> Vec<f32> {
        let n = (self.width * self.height).max(1) as f64;
        let mut sums = vec![0f64; self.channels];
        for px in self.data.chunks_exact(self.channels) {
            for (s, v) in sums.iter_mut().zip(px) {
                *s += *v as f64;
            }
        }
        sums.into_iter().map(|s| (s / n) as f32).collect()
    }

    /// Each channel divided by twice its entry of `means` (DESIGN section 6, white balance: an
    /// image whose channel means these are then averages 0.5); means below
    /// [`MIN_BALANCE_MEAN`] are raised to it, so a black image does not divide by zero.
    pub fn balanced(&self, means: &[f32]) -> Image2 {
        let mut out = self.clone();
        for px in out.data.chunks_exact_mut(self.channels) {
            for (v, m) in px.iter_mut().zip(means) {
                *v /= 2.0 * m.max(MIN_BALANCE_MEAN);
            }
        }
        out
    }

    /// The image white-balanced by its own channel means.
    pub fn white_balanced(&self) -> Image2 {
        self.balanced(&self.channel_means())
    }
}

/// Smallest channel mean a white balance divides by.
pub const MIN_BALANCE_MEAN: f32 = 1e-3;
