//! The guide image of each trained face for the guided loss: the ring phase of every pixel,
//! (cos 2 pi G, sin 2 pi G) with G the fitted growth field in years (rings at whole years),
//! sampled at the pixel centres of the training grid's faces. Generated face pixels lie on
//! the same centres, so a generated pixel and the photo pixel beside it carry the same phase.
//! Planes inside a crop get theirs from G at their own voxels (`phase_channels`).

use crate::frame::Face;
use crate::image2::Image2;
use crate::slice::slice_face;
use crate::texture::SolidTexture;

/// Guide channels per pixel.
pub(crate) const GUIDE_CHANNELS: usize = 2;

/// The phase guide of `face` at `n` x `n` pixels.
pub fn phase_guide(growth: &dyn SolidTexture, face: Face, n: usize) -> Image2 {
    let g = slice_face(growth, face, n);
    let mut out = Image2::filled(n, n, GUIDE_CHANNELS, 0.0);
    for (px, v) in out.data.chunks_exact_mut(GUIDE_CHANNELS).zip(g.data.iter()) {
        px.copy_from_slice(&phase(*v));
    }
    out
}

/// (cos, sin) of 2 pi G.
fn phase(g: f32) -> [f32; 2] {
    let angle = std::f32::consts::TAU * g.rem_euclid(1.0);
    [angle.cos(), angle.sin()]
}

/// The phase guide of G values in planar layout: `[2, N]` from `[N]`.
pub fn phase_channels(g: &[f32]) -> Vec<f32> {
    let n = g.len();
    let mut out = vec![0.0f32; GUIDE_CHANNELS * n];
    for (i, v) in g.iter().enumerate() {
        let [c, s] = phase(*v);
        out[i] = c;
        out[n + i] = s;
    }
    out
}

/// Phase guides of the faces in `faces` (file order; `None` for the others).
pub fn phase_guides(growth: &dyn SolidTexture, faces: &[Face], n: usize) -> [Option<Image2>; 6] {
    Face::ALL.map(|f| faces.contains(&f).then(|| phase_guide(growth, f, n)))
}
