//! Moving data between plain `Vec<f32>`/[`Volume`]s and burn tensors.
//!
//! Volumes are `[X, Y, Z, C]` (the foundation's layout); NCA tensors are `[C, X, Y, Z]`. The
//! conversions copy through `TensorData`, which is exact, so the same numbers reach flex and
//! ndarray.

use burn::tensor::{Device, Tensor, TensorData};

use crate::error::{Result, XylemError};
use crate::volume::Volume;

/// A tensor of `shape` from row-major data.
pub fn tensor_from<const D: usize>(
    data: Vec<f32>,
    shape: [usize; D],
    device: &Device,
) -> Tensor<D> {
    Tensor::from_data(TensorData::new(data, shape), device)
}

/// The values of a tensor, row-major.
pub fn to_vec<const D: usize>(t: Tensor<D>) -> Result<Vec<f32>> {
    t.into_data()
        .convert::<f32>()
        .try_to_vec::<f32>()
        .map_err(|e| XylemError::numeric("tensor readback", format!("{e:?}")))
}

/// A single-value tensor as a number.
pub fn scalar(t: Tensor<1>) -> f32 {
    t.into_scalar::<f32>()
}

/// `[C, X, Y, Z]` tensor -> `[X, Y, Z, C]` volume.
pub(crate) fn tensor_to_volume(t: Tensor<4>) -> Result<Volume> {
    let [c, x, y, z] = t.dims();
    let planar = to_vec(t)?;
    let n = x * y * z;
    let mut data = vec![0.0f32; planar.len()];
    for (voxel, values) in data.chunks_exact_mut(c).enumerate() {
        for (ch, value) in values.iter_mut().enumerate() {
            *value = planar[ch * n + voxel];
        }
    }
    Volume::from_data([x, y, z], c, data)
}
