//! The picture `xylem compare --sheet` writes: reference, candidate and their difference side
//! by side, captioned. The difference is |reference - candidate| per channel, amplified 4x so
//! that small colour shifts are visible.

use crate::image2::Image2;
use crate::report::captioned_row;

/// Amplification of the difference tile.
const GAIN: f32 = 4.0;

/// Reference | candidate | difference (candidate resized to the reference's size).
pub fn difference_sheet(reference: &Image2, candidate: &Image2) -> Image2 {
    let reference = reference.with_channels(3);
    let candidate = candidate
        .with_channels(3)
        .resized(reference.width, reference.height);
    let data = reference
        .data
        .iter()
        .zip(&candidate.data)
        .map(|(a, b)| ((a - b).abs() * GAIN).min(1.0))
        .collect();
    let diff = Image2 {
        data,
        ..reference.clone()
    };
    captioned_row(&[
        ("reference".to_string(), &reference),
        ("candidate".to_string(), &candidate),
        (format!("diff x{GAIN}"), &diff),
    ])
}
