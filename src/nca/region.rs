//! A box of voxels of the n^3 training grid: the whole volume, or a crop of it.
//!
//! Training at 2 cores cannot afford to unroll a whole 128^3 or 256^3 volume every iteration,
//! so it unrolls crops that touch the faces (`placement`). A crop keeps its place in the grid: its voxel centres, position channels and
//! conditioning are those of the full volume, so the model trained on crops is the model of
//! the full volume. Only the replicate padding at the crop's inner sides is artificial (there
//! the crop ends inside the wood); the faces the loss looks at are real cube faces.

use burn::tensor::{Device, Tensor};
use glam::Vec3;

use super::tensors::tensor_from;
use crate::frame::voxel_centre;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    /// Side of the whole grid (voxels).
    pub grid: usize,
    /// First voxel index along x, y, z.
    pub offset: [usize; 3],
    /// Voxels along x, y, z.
    pub dims: [usize; 3],
}

impl Region {
    /// The whole n^3 grid.
    pub fn whole(grid: usize) -> Self {
        Self {
            grid,
            offset: [0; 3],
            dims: [grid; 3],
        }
    }

    /// Corner crop `corner` (0..8; bit 0 = high x, bit 1 = high y, bit 2 = high z) of side
    /// `crop`.
    pub fn corner(grid: usize, crop: usize, corner: usize) -> Self {
        let crop = crop.min(grid);
        let at = |bit: usize| {
            if corner >> bit & 1 == 1 {
                grid - crop
            } else {
                0
            }
        };
        Self {
            grid,
            offset: [at(0), at(1), at(2)],
            dims: [crop; 3],
        }
    }

    pub fn voxels(&self) -> usize {
        self.dims.iter().product()
    }

    /// Centre of local voxel (i, j, k) in cube coordinates.
    pub fn voxel_point(&self, i: usize, j: usize, k: usize) -> Vec3 {
        Vec3::new(
            voxel_centre(self.offset[0] + i, self.grid),
            voxel_centre(self.offset[1] + j, self.grid),
            voxel_centre(self.offset[2] + k, self.grid),
        )
    }

    /// Position channels `[3, X, Y, Z]`: 2 x voxel centre = 2 (i/n - 0.5 + 0.5/n), in
    /// (-1, 1), of the grid (not of the crop).
    pub fn positions(&self, device: &Device) -> Tensor<4> {
        let [dx, dy, dz] = self.dims;
        let n = dx * dy * dz;
        let mut data = vec![0.0f32; 3 * n];
        for i in 0..dx {
            for j in 0..dy {
                for k in 0..dz {
                    let p = 2.0 * self.voxel_point(i, j, k);
                    let v = (i * dy + j) * dz + k;
                    data[v] = p.x;
                    data[n + v] = p.y;
                    data[2 * n + v] = p.z;
                }
            }
        }
        tensor_from(data, [3, dx, dy, dz], device)
    }

    /// The position channels a model sees (`ModelSpec::positions`): [`Self::positions`], or
    /// zeros `[3, X, Y, Z]` for a model that does not see its place.
    pub fn position_inputs(&self, seen: bool, device: &Device) -> Tensor<4> {
        if seen {
            self.positions(device)
        } else {
            let [dx, dy, dz] = self.dims;
            Tensor::zeros([3, dx, dy, dz], device)
        }
    }
}
