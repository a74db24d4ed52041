//! Sampling solid textures on planes: faces, validation cuts, arbitrary planes, and the
//! unfolded cross of all six faces. Rows are evaluated in parallel (rayon).

use rayon::prelude::*;

use crate::frame::{CROSS_TILES, Face, Plane, cross_tile};
use crate::image2::Image2;
use crate::texture::SolidTexture;

/// Samples `texture` at the pixel centres of a `width` x `height` image of `plane`, as seen
/// on that plane (`SolidTexture::eval_on_surface` with the plane's normal).
pub fn slice_plane(
    texture: &dyn SolidTexture,
    plane: &Plane,
    width: usize,
    height: usize,
) -> Image2 {
    let channels = texture.channels();
    let normal = plane.normal();
    let mut data = vec![0.0f32; width * height * channels];
    data.par_chunks_mut(width * channels)
        .enumerate()
        .for_each(|(row, line)| {
            for col in 0..width {
                let p = plane.pixel_point(row, col, width, height);
                let out = &mut line[col * channels..(col + 1) * channels];
                texture.eval_on_surface(p, normal, out);
            }
        });
    Image2 {
        width,
        height,
        channels,
        data,
    }
}

/// The n x n image of one cube face, laid out as the face table says.
pub fn slice_face(texture: &dyn SolidTexture, face: Face, n: usize) -> Image2 {
    slice_plane(texture, &Plane::face(face), n, n)
}

/// All six faces in file order A..F.
pub(crate) fn slice_faces(texture: &dyn SolidTexture, n: usize) -> [Image2; 6] {
    Face::ALL.map(|f| slice_face(texture, f, n))
}

/// The unfolded cross (4 x 3 tiles: B above A, row `C A E F`, D below A) of six face images
/// given in file order; empty tiles are filled with `background`.
pub fn unfold_cross(faces: &[Image2; 6], background: f32) -> Image2 {
    let (w, h) = (faces[0].width, faces[0].height);
    let channels = faces.iter().map(|f| f.channels).max().unwrap_or(1);
    let mut out = Image2::filled(w * CROSS_TILES.0, h * CROSS_TILES.1, channels, background);
    for face in Face::ALL {
        let (tc, tr) = cross_tile(face);
        out.blit(&faces[face.index()].with_channels(channels), tr * h, tc * w);
    }
    out
}
