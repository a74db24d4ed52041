//! Dense voxel volumes over the cube, with trilinear lookup.
//!
//! Layout (also the on-disk `.npy` layout): `[X, Y, Z, C]`, row-major, so
//! `data[((i * ny + j) * nz + k) * c + ch]` is channel `ch` at voxel (i, j, k), whose centre is
//! (x, y, z) = ((i + 0.5)/nx - 0.5, (j + 0.5)/ny - 0.5, (k + 0.5)/nz - 0.5). A numpy user reads
//! `vol[i, j, k]` as the value at x_i, y_j, z_k. Tensors of the NCA use `[C, X, Y, Z]`
//! (burn's `[C, D, H, W]` with D = x, H = y, W = z).

use glam::Vec3;
use rayon::prelude::*;

use crate::error::{Result, XylemError};
use crate::frame::{HALF, voxel_centre};
use crate::texture::SolidTexture;

#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// Voxels along x, y, z.
    pub dims: [usize; 3],
    pub channels: usize,
    /// `[X, Y, Z, C]`, row-major.
    pub data: Vec<f32>,
}

impl Volume {
    pub fn zeros(dims: [usize; 3], channels: usize) -> Self {
        Self {
            dims,
            channels,
            data: vec![0.0; dims[0] * dims[1] * dims[2] * channels],
        }
    }

    /// Wraps `[X, Y, Z, C]` data, checking its length.
    pub fn from_data(dims: [usize; 3], channels: usize, data: Vec<f32>) -> Result<Self> {
        let expected = dims[0] * dims[1] * dims[2] * channels;
        if data.len() != expected || dims.contains(&0) || channels == 0 {
            return Err(XylemError::input(
                "volume data",
                format!(
                    "{} values for dims {dims:?} x {channels} channels (expected {expected}, all sizes > 0)",
                    data.len()
                ),
            ));
        }
        Ok(Self {
            dims,
            channels,
            data,
        })
    }

    /// Evaluates a solid texture at every voxel centre of an n^3 grid, in parallel.
    pub fn from_texture(texture: &dyn SolidTexture, n: usize) -> Self {
        Self::from_texture_with_progress(texture, n, &|| {})
    }

    /// [`Volume::from_texture`] on an `nx x ny x nz` grid (voxel centres per axis as always).
    pub fn from_texture_dims(texture: &dyn SolidTexture, dims: [usize; 3]) -> Self {
        Self::evaluate(texture, dims, &|| {})
    }

    /// [`Volume::from_texture`], calling `slab_done` after each of the n x-slabs (for
    /// progress bars on long evaluations).
    pub fn from_texture_with_progress(
        texture: &dyn SolidTexture,
        n: usize,
        slab_done: &(dyn Fn() + Sync),
    ) -> Self {
        Self::evaluate(texture, [n, n, n], slab_done)
    }

    fn evaluate(
        texture: &dyn SolidTexture,
        dims: [usize; 3],
        slab_done: &(dyn Fn() + Sync),
    ) -> Self {
        let [nx, ny, nz] = dims;
        let channels = texture.channels();
        let mut data = vec![0.0f32; nx * ny * nz * channels];
        data.par_chunks_mut(ny * nz * channels)
            .enumerate()
            .for_each(|(i, slab)| {
                let x = voxel_centre(i, nx);
                for j in 0..ny {
                    let y = voxel_centre(j, ny);
                    for k in 0..nz {
                        let o = (j * nz + k) * channels;
                        texture.eval(
                            Vec3::new(x, y, voxel_centre(k, nz)),
                            &mut slab[o..o + channels],
                        );
                    }
                }
                slab_done();
            });
        Self {
            dims,
            channels,
            data,
        }
    }

    /// Offset of voxel (i, j, k) in `data`.
    pub fn offset(&self, i: usize, j: usize, k: usize) -> usize {
        ((i * self.dims[1] + j) * self.dims[2] + k) * self.channels
    }

    pub fn voxel(&self, i: usize, j: usize, k: usize) -> &[f32] {
        let o = self.offset(i, j, k);
        &self.data[o..o + self.channels]
    }

    /// The voxel centre of (i, j, k).
    pub fn voxel_point(&self, i: usize, j: usize, k: usize) -> Vec3 {
        Vec3::new(
            voxel_centre(i, self.dims[0]),
            voxel_centre(j, self.dims[1]),
            voxel_centre(k, self.dims[2]),
        )
    }

    /// Continuous voxel coordinate of `p` along `axis` (voxel centres at integers), clamped
    /// to the volume so lookups outside repeat the border voxels.
    fn coord(&self, value: f32, axis: usize) -> (usize, usize, f32) {
        let n = self.dims[axis];
        let f = ((value + HALF) * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
        let i0 = f.floor() as usize;
        let i1 = (i0 + 1).min(n - 1);
        (i0, i1, f - i0 as f32)
    }

    /// Trilinear interpolation of all channels at `p`.
    pub fn trilinear(&self, p: Vec3, out: &mut [f32]) {
        let (x0, x1, fx) = self.coord(p.x, 0);
        let (y0, y1, fy) = self.coord(p.y, 1);
        let (z0, z1, fz) = self.coord(p.z, 2);
        out.iter_mut().for_each(|o| *o = 0.0);
        for (i, wx) in [(x0, 1.0 - fx), (x1, fx)] {
            for (j, wy) in [(y0, 1.0 - fy), (y1, fy)] {
                for (k, wz) in [(z0, 1.0 - fz), (z1, fz)] {
                    let w = wx * wy * wz;
                    if w == 0.0 {
                        continue;
                    }
                    for (o, v) in out.iter_mut().zip(self.voxel(i, j, k)) {
                        *o += w * v;
                    }
                }
            }
        }
    }
}

impl SolidTexture for Volume {
    fn channels(&self) -> usize {
        self.channels
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        self.trilinear(p, out)
    }
}
