//! Training targets: the face photos, white-balanced and resampled to the training grid.
//!
//! One voxel of an n^3 training volume is 4 cm / n, so a face photo is resampled to n x n
//! (area average when shrinking, bilinear when enlarging) for the texture to have the same
//! scale in voxels as in target pixels. Each face is divided by twice its mean colour (DESIGN
//! section 6: white balance), so every target has mean 0.5 per channel.

use crate::frame::Face;
use crate::image2::Image2;
use crate::nca::conditioning::Normalisation;
use crate::sample::Sample;
use crate::slice::slice_face;
use crate::texture::SolidTexture;

/// The white-balanced targets at `size` x `size` (`None` for faces not used) and the mean
/// photo colour of the used faces (for B's white balance, see `Normalisation`).
pub(crate) fn face_targets(sample: &Sample, size: usize) -> ([Option<Image2>; 6], [f32; 3]) {
    let targets = Face::ALL.map(|face| {
        sample
            .photo(face)
            .map(|photo| photo.resampled(size, size).white_balanced())
    });
    (targets, photo_mean(sample))
}

/// Mean colour of the loaded photos (each face weighted equally).
pub fn photo_mean(sample: &Sample) -> [f32; 3] {
    let mut sum = [0.0f32; 3];
    let mut count = 0.0f32;
    for photo in Face::ALL.iter().filter_map(|&f| sample.photo(f)) {
        let mean = photo.channel_means();
        for (c, s) in sum.iter_mut().enumerate() {
            *s += mean[c.min(mean.len() - 1)];
        }
        count += 1.0;
    }
    sum.map(|s| s / count.max(1.0))
}

/// Scales each target per channel so that its mean is the mean of the base colour B on that
/// face in the NCA's colour space (`norm`): with these targets the NCA learns texture on top
/// of B and no colour shift of its own. White-balancing each face by its own mean (DESIGN
/// section 6) instead asks the NCA to brighten the darker end-grain faces and darken the side
/// faces, which on CN03 left its interior cuts ~20 levels darker than the photo.
pub(crate) fn match_base_means(
    targets: &mut [Option<Image2>; 6],
    colour: &dyn SolidTexture,
    norm: &Normalisation,
    size: usize,
) {
    for (face, target) in Face::ALL.iter().zip(targets.iter_mut()) {
        let Some(target) = target else { continue };
        let base = slice_face(colour, *face, size).channel_means();
        let own = target.channel_means();
        let factor: Vec<f32> = (0..3)
            .map(|c| base[c] * norm.white_balance[c] / own[c].max(1e-6))
            .collect();
        for px in target.data.chunks_exact_mut(target.channels) {
            for (v, f) in px.iter_mut().zip(&factor) {
                *v *= f;
            }
        }
    }
}
