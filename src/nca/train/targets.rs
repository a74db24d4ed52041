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
pub fn face_targets(sample: &Sample, size: usize) -> ([Option<Image2>; 6], [f32; 3]) {
    let targets = Face::ALL.map(|face| {
        sample
            .photo(face)
            .map(|photo| resample(photo, size).white_balanced())
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
pub fn match_base_means(
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

/// Resamples a square image to `size` x `size`.
pub fn resample(img: &Image2, size: usize) -> Image2 {
    if img.width == size && img.height == size {
        return img.clone();
    }
    if img.width < size || img.height < size {
        return bilinear(img, size);
    }
    let rows = area_weights(img.height, size);
    let cols = area_weights(img.width, size);
    let mut out = Image2::filled(size, size, img.channels, 0.0);
    for (r, row_w) in rows.iter().enumerate() {
        for (c, col_w) in cols.iter().enumerate() {
            let px = out.pixel_mut(r, c);
            for &(sr, wr) in row_w {
                for &(sc, wc) in col_w {
                    for (o, v) in px.iter_mut().zip(img.pixel(sr, sc)) {
                        *o += wr * wc * v;
                    }
                }
            }
        }
    }
    out
}

/// For each of `m` output pixels, the source pixels of an `n`-pixel axis it covers and their
/// weights (overlap lengths, summing to 1).
fn area_weights(n: usize, m: usize) -> Vec<Vec<(usize, f32)>> {
    let scale = n as f64 / m as f64;
    (0..m)
        .map(|o| {
            let (lo, hi) = (o as f64 * scale, (o + 1) as f64 * scale);
            (lo.floor() as usize..(hi.ceil() as usize).min(n))
                .map(|s| {
                    let overlap = (hi.min(s as f64 + 1.0) - lo.max(s as f64)).max(0.0);
                    (s, (overlap / scale) as f32)
                })
                .collect()
        })
        .collect()
}

/// Bilinear enlargement (pixel centres aligned).
fn bilinear(img: &Image2, size: usize) -> Image2 {
    let mut out = Image2::filled(size, size, img.channels, 0.0);
    let sy = img.height as f32 / size as f32;
    let sx = img.width as f32 / size as f32;
    for r in 0..size {
        for c in 0..size {
            let (y, x) = ((r as f32 + 0.5) * sy - 0.5, (c as f32 + 0.5) * sx - 0.5);
            for ch in 0..img.channels {
                out.pixel_mut(r, c)[ch] = img.bilinear(y, x, ch);
            }
        }
    }
    out
}
