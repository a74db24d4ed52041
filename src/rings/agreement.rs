//! How well one ring-localisation image agrees with another (issue 13's figures): the
//! Pearson correlation, best over shifts of up to 2 px, and the precision and recall of
//! ring pixels within 2 px.
//!
//! Ring pixels are the crest of each band: at or above half white and a local maximum along
//! the row or the column (every line crosses one of them), away from the border.

use crate::fit::metrics::shifted_correlation;
use crate::image2::Image2;

/// Pixels of shift forgiven by the correlation and distance accepted for a ring pixel.
pub const TOLERANCE_PX: usize = 2;
/// Pixels at the border left out (the U-Net's output is unreliable there).
pub(crate) const BORDER_PX: usize = 5;
/// A band's crest must reach this grey level.
const CREST_LEVEL: f32 = 0.5;

/// Agreement of a predicted ring image with a reference one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Agreement {
    /// Pearson correlation, best over shifts of up to [`TOLERANCE_PX`].
    pub correlation: f32,
    /// Share of predicted ring pixels within [`TOLERANCE_PX`] of a reference ring pixel.
    pub precision: f32,
    /// Share of reference ring pixels within [`TOLERANCE_PX`] of a predicted ring pixel.
    pub recall: f32,
}

/// The agreement of `predicted` with `reference` (one-channel images of one size).
pub fn agreement(predicted: &Image2, reference: &Image2) -> Agreement {
    let p = ring_pixels(predicted);
    let r = ring_pixels(reference);
    Agreement {
        correlation: shifted_correlation(predicted, reference, BORDER_PX, TOLERANCE_PX),
        precision: share_near(&p, &r, predicted.width),
        recall: share_near(&r, &p, predicted.width),
    }
}

/// The crest pixels of the bands of a ring image, row-major, border left out.
pub(crate) fn ring_pixels(img: &Image2) -> Vec<bool> {
    let (w, h) = (img.width, img.height);
    let at = |r: usize, c: usize| img.get(r, c, 0);
    let mut out = vec![false; w * h];
    for r in BORDER_PX..h.saturating_sub(BORDER_PX) {
        for c in BORDER_PX..w.saturating_sub(BORDER_PX) {
            let v = at(r, c);
            // Strict on one side, so a flat stretch along a line is not a crest and a crest
            // two pixels wide counts once.
            let row_crest = v >= at(r, c - 1) && v > at(r, c + 1);
            let col_crest = v >= at(r - 1, c) && v > at(r + 1, c);
            out[r * w + c] = v >= CREST_LEVEL && (row_crest || col_crest);
        }
    }
    out
}

/// Share of `from`'s set pixels with a set pixel of `to` within the tolerance (square
/// window); 0 when `from` has none.
fn share_near(from: &[bool], to: &[bool], width: usize) -> f32 {
    let height = from.len() / width.max(1);
    let t = TOLERANCE_PX as isize;
    let (mut total, mut near) = (0usize, 0usize);
    for r in 0..height as isize {
        for c in 0..width as isize {
            if !from[r as usize * width + c as usize] {
                continue;
            }
            total += 1;
            let found = (-t..=t).any(|dr| {
                (-t..=t).any(|dc| {
                    let (rr, cc) = (r + dr, c + dc);
                    rr >= 0
                        && cc >= 0
                        && rr < height as isize
                        && cc < width as isize
                        && to[rr as usize * width + cc as usize]
                })
            });
            near += usize::from(found);
        }
    }
    if total == 0 {
        0.0
    } else {
        near as f32 / total as f32
    }
}
