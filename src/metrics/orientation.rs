//! Grain-direction agreement (`orient`) from the structure tensor. Per pixel, the smoothed
//! tensor J = G * [gx^2, gx gy; gx gy, gy^2] of the luminance gradient gives the
//! double-angle vector v = (Jxx - Jyy, 2 Jxy), whose angle is twice the dominant gradient
//! direction and whose length (lambda1 - lambda2) says how oriented the pixel is. The score
//! is sum(v_ref . v_cand) / sum(|v_ref| |v_cand|): the mean cos(2 delta theta), weighted
//! towards pixels oriented in both images. 1: the same grain direction everywhere; 0:
//! unrelated; -1: perpendicular. Sigmas follow the image width (values at 256 px).

use crate::image_filter::structure_tensor;
use crate::image2::Image2;

/// Pre-smoothing of the luminance before differentiation (px at 256).
const PRE_SIGMA: f32 = 1.0;
/// Integration scale of the tensor (px at 256): about a pore's neighbourhood.
const TENSOR_SIGMA: f32 = 4.0;

/// Double-angle orientation field: (Jxx - Jyy, 2 Jxy) per pixel.
pub(crate) fn orientation_field(img: &Image2) -> Vec<[f32; 2]> {
    let scale = img.width as f32 / 256.0;
    let [jxx, jxy, jyy] =
        structure_tensor(&img.luminance(), PRE_SIGMA * scale, TENSOR_SIGMA * scale);
    (0..jxx.data.len())
        .map(|i| [jxx.data[i] - jyy.data[i], 2.0 * jxy.data[i]])
        .collect()
}

/// Weighted mean cos(2 delta theta) of two equally sized images.
pub(crate) fn orientation_agreement(reference: &Image2, candidate: &Image2) -> f32 {
    let a = orientation_field(reference);
    let b = orientation_field(candidate);
    let (mut dot, mut norm) = (0f64, 0f64);
    for (va, vb) in a.iter().zip(&b) {
        dot += (va[0] * vb[0] + va[1] * vb[1]) as f64;
        norm += ((va[0] * va[0] + va[1] * va[1]).sqrt() * (vb[0] * vb[0] + vb[1] * vb[1]).sqrt())
            as f64;
    }
    if norm <= 1e-30 {
        return 0.0;
    }
    (dot / norm) as f32
}
