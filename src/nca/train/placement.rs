//! Where the training crops of an iteration lie.
//!
//! `corners` is the first trial of DESIGN section 6: the 8 corner crops, each touching three
//! faces. Measured on CN03 and the demo (docs/DESIGN.md, "NCA study") it left the face
//! centres and most of each face out of the loss. `faces` (the default) puts a crop anywhere
//! against a face: a face is drawn among the faces trained on, the crop lies against it and
//! its other two axes start anywhere in the grid, so every part of every trained face is
//! seen and crops at an edge or a corner still touch two or three faces.
//!
//! Either way no crop reaches the inside of the cube, far from every trained face; with
//! F held out, the knot behind F's centre ran away there on H11. `[volume]
//! interior_fraction` draws that share of the fresh crops anywhere in the grid instead
//! ([`draw_fresh`]).

pub use crate::nca::config::Placement;

use crate::frame::Face;
use crate::nca::config::VolumeConfig;
use crate::nca::faces::layout;
use crate::nca::region::Region;
use crate::rng::Rng;

/// Draws the region of a fresh seed: with probability `interior_fraction` anywhere in the
/// grid ([`draw_anywhere`]), otherwise by `placement` ([`draw_region`]). With a fraction of
/// 0 no number is drawn for the choice, so configs without one keep their random stream.
pub fn draw_fresh(volume: &VolumeConfig, faces: &[Face], rng: &mut Rng) -> Region {
    let (grid, crop) = (volume.size, volume.crop);
    if volume.interior_fraction > 0.0 && crop < grid && rng.uniform() < volume.interior_fraction {
        return draw_anywhere(grid, crop, rng);
    }
    draw_region(grid, crop, volume.placement, faces, rng)
}

/// A crop whose offset is uniform on every axis: mostly inside the cube, touching no face.
pub fn draw_anywhere(grid: usize, crop: usize, rng: &mut Rng) -> Region {
    let span = grid.saturating_sub(crop) + 1;
    Region {
        grid,
        offset: [rng.below(span), rng.below(span), rng.below(span)],
        dims: [crop.min(grid); 3],
    }
}

/// Draws the region of one iteration; `faces` are the faces trained on (not empty).
/// The whole grid when `crop >= grid`.
pub fn draw_region(
    grid: usize,
    crop: usize,
    placement: Placement,
    faces: &[Face],
    rng: &mut Rng,
) -> Region {
    if crop >= grid {
        return Region::whole(grid);
    }
    match placement {
        Placement::Corners => Region::corner(grid, crop, rng.below(8)),
        Placement::Faces => {
            let face = faces[rng.below(faces.len().max(1)).min(faces.len() - 1)];
            let (axis, high) = layout(face).normal;
            let span = grid - crop + 1;
            let mut offset = [0usize; 3];
            for (a, o) in offset.iter_mut().enumerate() {
                *o = if a == axis {
                    if high { grid - crop } else { 0 }
                } else {
                    rng.below(span)
                };
            }
            Region {
                grid,
                offset,
                dims: [crop; 3],
            }
        }
    }
}
