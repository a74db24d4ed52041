//! The inputs of a fused step that do not change during an unroll: the conditioning
//! channels and the position channels of the region.
//!
//! Unlike the burn path (`model::StepInputs`, which stores the perceived conditioning,
//! `5 K + 3` floats per cell), the fused step perceives the `K` conditioning channels again
//! in every block: that costs ~1% of a step and saves `5 K + 3 - K` floats per cell (0.9 GB
//! at 256^3). Positions are three per-axis tables.

use super::layout::Dims;
use crate::error::{Result, XylemError};
use crate::frame::voxel_centre;
use crate::nca::region::Region;

#[derive(Clone, Debug)]
pub struct FixedInputs {
    pub dims: Dims,
    /// Conditioning channels K.
    pub cond_channels: usize,
    /// `[K, X, Y, Z]`.
    pub cond: Vec<f32>,
    /// Position channel of each index along x, y, z: 2 x the grid's voxel centre (as
    /// `Region::positions`), in (-1, 1).
    pub positions: [Vec<f32>; 3],
}

impl FixedInputs {
    /// Inputs of `region` with conditioning `cond` (`[K, X, Y, Z]` over the region).
    pub fn new(region: &Region, cond: Vec<f32>, cond_channels: usize) -> Result<Self> {
        let dims = Dims(region.dims);
        if dims.0.contains(&0) {
            return Err(XylemError::input(
                "fused NCA region",
                format!("{:?} has an empty axis", region.dims),
            ));
        }
        if cond.len() != cond_channels * dims.cells() {
            return Err(XylemError::input(
                "fused NCA conditioning",
                format!(
                    "{} values for {cond_channels} channels of {:?} cells",
                    cond.len(),
                    region.dims
                ),
            ));
        }
        let positions = std::array::from_fn(|a| {
            (0..region.dims[a])
                .map(|i| 2.0 * voxel_centre(region.offset[a] + i, region.grid))
                .collect()
        });
        Ok(Self {
            dims,
            cond_channels,
            cond,
            positions,
        })
    }

    /// The same inputs with the position tables zeroed when the model does not see its
    /// place (`ModelSpec::positions`).
    pub fn with_positions(mut self, seen: bool) -> Self {
        if !seen {
            for table in &mut self.positions {
                table.fill(0.0);
            }
        }
        self
    }

    /// Channel plane `k` of the conditioning, `[X, Y, Z]`.
    pub(crate) fn cond_plane(&self, k: usize) -> &[f32] {
        let n = self.dims.cells();
        &self.cond[k * n..(k + 1) * n]
    }
}
