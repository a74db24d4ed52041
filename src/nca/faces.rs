//! The cube faces of a state tensor `[C, X, Y, Z]`, laid out exactly as the face table of
//! DESIGN section 2 (`Face::point`): e.g. face A pixel (r, c) is voxel (x = c, y = N-1-r,
//! z = N-1). For a crop, only the faces it touches are returned, each as the patch of the
//! full face image it covers, with the patch's place in that image.
//!
//! Each face is described by the axis it is fixed on (and which end), and which axis runs
//! down its rows and across its columns (and whether reversed); `tests/nca_faces.rs` checks
//! the table voxel by voxel against `Face::pixel_point`.

use burn::tensor::Tensor;

use super::region::Region;
use crate::frame::Face;

/// How a face image sits in the voxel grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaceLayout {
    /// Axis (0 = x, 1 = y, 2 = z) normal to the face, and whether the face is at its high end.
    pub normal: (usize, bool),
    /// Axis along the image rows (top to bottom), and whether it runs from high to low index.
    pub rows: (usize, bool),
    /// Axis along the image columns (left to right), and whether reversed.
    pub cols: (usize, bool),
}

/// The face table of DESIGN section 2 in voxel terms.
pub fn layout(face: Face) -> FaceLayout {
    let (normal, rows, cols) = match face {
        // x = u, y = -v, z = +0.5
        Face::A => ((2, true), (1, true), (0, false)),
        // x = u, y = +0.5, z = v
        Face::B => ((1, true), (2, false), (0, false)),
        // x = -0.5, y = -v, z = u
        Face::C => ((0, false), (1, true), (2, false)),
        // x = u, y = -0.5, z = -v
        Face::D => ((1, false), (2, true), (0, false)),
        // x = +0.5, y = -v, z = -u
        Face::E => ((0, true), (1, true), (2, true)),
        // x = -u, y = -v, z = -0.5
        Face::F => ((2, false), (1, true), (0, true)),
    };
    FaceLayout { normal, rows, cols }
}

/// A face (or the part of it a crop covers) of a state, or a plane parallel to it inside
/// the crop.
#[derive(Clone, Debug)]
pub struct FacePatch {
    pub face: Face,
    /// `[C, h, w]` image, rows and columns as in the face image.
    pub image: Tensor<3>,
    /// Row and column of the patch's top-left pixel in the full face image of the grid.
    pub origin: [usize; 2],
    /// For a plane inside the crop: its own guide channels `[G, h, w]` (the face's guide
    /// image does not hold them); `None` on the face itself.
    pub guide: Option<Tensor<3>>,
}

impl FaceLayout {
    /// Does `region` reach this face?
    pub fn touches(&self, region: &Region) -> bool {
        let (axis, high) = self.normal;
        if high {
            region.offset[axis] + region.dims[axis] == region.grid
        } else {
            region.offset[axis] == 0
        }
    }

    /// Place of the region's patch in the full face image: start index along `axis`, counted
    /// in image order.
    fn start(&self, (axis, reversed): (usize, bool), region: &Region) -> usize {
        if reversed {
            region.grid - region.offset[axis] - region.dims[axis]
        } else {
            region.offset[axis]
        }
    }

    /// The plane `depth` voxels inside the region from this face, parallel to it, with the
    /// face image's rows and columns: `[C, rows, cols]`.
    pub(crate) fn extract_at(&self, state: Tensor<4>, region: &Region, depth: usize) -> Tensor<3> {
        let (axis, high) = self.normal;
        let dim = axis + 1;
        let depth = depth.min(region.dims[axis] - 1);
        let index = if high {
            region.dims[axis] - 1 - depth
        } else {
            depth
        };
        let slice = state.narrow(dim, index, 1).squeeze_dim::<3>(dim); // [C, a, b], a < b remaining axes
        let remaining: Vec<usize> = (0..3).filter(|&a| a != axis).collect();
        let row_first = remaining[0] == self.rows.0;
        let mut image = if row_first {
            slice
        } else {
            slice.swap_dims(1, 2)
        };
        if self.rows.1 {
            image = image.flip([1]);
        }
        if self.cols.1 {
            image = image.flip([2]);
        }
        image
    }
}

/// The patches of every face in `faces` that `region` touches, from a state `[C, X, Y, Z]`.
pub fn face_patches(state: &Tensor<4>, region: &Region, faces: &[Face]) -> Vec<FacePatch> {
    patches_at(state, None, region, faces, 0)
}

/// Planes parallel to each face in `faces` that `region` touches, `depth` voxels inside,
/// from a state `[C, X, Y, Z]`, with their own guides from `guide` (`[G, X, Y, Z]`). Each
/// plane keeps its face's origin: its pixels lie over the same face pixels.
pub(crate) fn inner_patches(
    state: &Tensor<4>,
    guide: &Tensor<4>,
    region: &Region,
    faces: &[Face],
    depth: usize,
) -> Vec<FacePatch> {
    patches_at(state, Some(guide), region, faces, depth)
}

/// For a crop inside the cube: per axis, the plane `depth` voxels in from the crop's side
/// that faces the nearest of `faces` normal to that axis (the farther one when only it is
/// in `faces`), with its guide plane. Its origin is the crop's place on that face, so the
/// guided loss compares it with the photo's window over the same place.
pub(crate) fn nearest_face_planes(
    state: &Tensor<4>,
    guide: &Tensor<4>,
    region: &Region,
    faces: &[Face],
    depth: usize,
) -> Vec<FacePatch> {
    nearest_faces(region, faces)
        .into_iter()
        .map(|face| plane(face, state, Some(guide), region, depth))
        .collect()
}

/// Per axis, the face of `faces` normal to it nearest to `region`'s centre (at most 3).
pub(crate) fn nearest_faces(region: &Region, faces: &[Face]) -> Vec<Face> {
    (0..3)
        .filter_map(|axis| {
            let centre = 2 * region.offset[axis] + region.dims[axis]; // twice the centre
            let high_nearer = centre > region.grid;
            let pick = |high: bool| {
                faces
                    .iter()
                    .copied()
                    .find(|&f| layout(f).normal == (axis, high))
            };
            pick(high_nearer).or_else(|| pick(!high_nearer))
        })
        .collect()
}

/// The plane of `region` parallel to `face`, `depth` voxels in from the crop's side towards
/// it, at the crop's place on the face image, with its guide plane when `guide` is given.
fn plane(
    face: Face,
    state: &Tensor<4>,
    guide: Option<&Tensor<4>>,
    region: &Region,
    depth: usize,
) -> FacePatch {
    let l = layout(face);
    FacePatch {
        face,
        image: l.extract_at(state.clone(), region, depth),
        origin: [l.start(l.rows, region), l.start(l.cols, region)],
        guide: guide.map(|g| l.extract_at(g.clone(), region, depth)),
    }
}

/// The planes `depth` voxels inside every face in `faces` that `region` touches (0 = the
/// faces themselves), each with its guide plane when `guide` is given.
fn patches_at(
    state: &Tensor<4>,
    guide: Option<&Tensor<4>>,
    region: &Region,
    faces: &[Face],
    depth: usize,
) -> Vec<FacePatch> {
    faces
        .iter()
        .copied()
        .filter(|&face| layout(face).touches(region))
        .map(|face| plane(face, state, guide, region, depth))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crop_at(offset: [usize; 3]) -> Region {
        Region {
            grid: 20,
            offset,
            dims: [4; 3],
        }
    }

    #[test]
    fn an_interior_crop_is_compared_with_the_nearest_trained_face_on_each_axis() {
        // Near x = 0 (C), y = high (B), z = low (F); all six faces trained.
        let r = crop_at([2, 14, 3]);
        assert_eq!(
            nearest_faces(&r, &Face::ALL),
            vec![Face::C, Face::B, Face::F]
        );
        // Without C and B the farther face of those axes stands in; without A and F the
        // z axis has none.
        let some = [Face::D, Face::E, Face::A];
        assert_eq!(nearest_faces(&r, &some), vec![Face::E, Face::D, Face::A]);
        assert_eq!(nearest_faces(&r, &[Face::C]), vec![Face::C]);
        // The plane's origin is the crop's place on the face; its guide comes along.
        let state = Tensor::zeros([3, 4, 4, 4], &Default::default());
        let planes = nearest_face_planes(&state, &state, &r, &[Face::C], 1);
        assert_eq!(planes.len(), 1);
        // C's rows run down y (20 - 14 - 4 = 2), its columns along z (3).
        assert_eq!(planes[0].origin, [2, 3]);
        assert_eq!(planes[0].image.dims(), [3, 4, 4]);
        assert!(planes[0].guide.is_some());
    }
}
