//! The standard image set every solid texture gets: six faces, the two validation cuts and
//! the unfolded cross, written into an output folder.

use crate::error::Result;
use crate::frame::{Face, Plane};
use crate::image2::Image2;
use crate::io::{OutputDir, save_png};
use crate::slice::{slice_faces, slice_plane, unfold_cross};
use crate::texture::SolidTexture;

/// Background of the empty tiles of the unfolded cross.
pub const CROSS_BACKGROUND: f32 = 0.15;

/// Images of one texture: faces in file order A..F, then cut1 and cut2.
pub struct SliceSet {
    pub faces: [Image2; 6],
    pub cut1: Image2,
    pub cut2: Image2,
}

impl SliceSet {
    /// Samples the faces and cuts at n x n.
    pub fn render(texture: &dyn SolidTexture, n: usize) -> Self {
        Self {
            faces: slice_faces(texture, n),
            cut1: slice_plane(texture, &Plane::cut1(), n, n),
            cut2: slice_plane(texture, &Plane::cut2(), n, n),
        }
    }

    /// The unfolded cross of the faces.
    pub fn cross(&self) -> Image2 {
        unfold_cross(&self.faces, CROSS_BACKGROUND)
    }

    /// Writes `faces/A.png`..`F.png`, `cuts/cut1.png`, `cuts/cut2.png` and `unfolded.png`
    /// (each name with `suffix` before `.png`, e.g. "_arl").
    pub fn write(&self, out: &OutputDir, suffix: &str) -> Result<()> {
        for face in Face::ALL {
            save_png(
                &self.faces[face.index()],
                &out.path(format!("faces/{face}{suffix}.png")),
            )?;
        }
        save_png(&self.cut1, &out.path(format!("cuts/cut1{suffix}.png")))?;
        save_png(&self.cut2, &out.path(format!("cuts/cut2{suffix}.png")))?;
        save_png(&self.cross(), &out.path(format!("unfolded{suffix}.png")))
    }
}
