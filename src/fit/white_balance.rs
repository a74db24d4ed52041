//! White balance of the face photos (DESIGN section 6): each face divided by 2 x its mean
//! colour, so every face averages 0.5 per channel and lighting differences between photos
//! mostly cancel. The means are kept (`field::WhiteBalance`) to go back to real colour.

use crate::field::WhiteBalance;
use crate::frame::Face;
use crate::image2::{Image2, MIN_BALANCE_MEAN as MIN_MEAN};

/// Mean RGB of a photo, each channel at least `MIN_MEAN`.
pub fn photo_mean(photo: &Image2) -> [f32; 3] {
    let m = photo.with_channels(3).channel_means();
    std::array::from_fn(|c| m[c].max(MIN_MEAN))
}

/// White-balance data of the photos of `faces` (`photos` indexed by `Face::index`); faces
/// without a photo get the mean of the others.
pub fn white_balance(photos: &[Option<Image2>; 6], faces: &[Face]) -> WhiteBalance {
    let means: Vec<(Face, [f32; 3])> = faces
        .iter()
        .filter_map(|&f| photos[f.index()].as_ref().map(|p| (f, photo_mean(p))))
        .collect();
    let count = means.len().max(1) as f32;
    let mean: [f32; 3] = std::array::from_fn(|c| {
        (means.iter().map(|(_, m)| m[c]).sum::<f32>() / count).max(MIN_MEAN)
    });
    let mut face_means = [mean; 6];
    for (f, m) in means {
        face_means[f.index()] = m;
    }
    WhiteBalance {
        face_means,
        mean,
        grain: None,
    }
}
