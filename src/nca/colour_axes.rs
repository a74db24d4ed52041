//! The colours the state may paint: the principal axes of the photos' fine texture
//! (`model.colour_axes`, issue 12's pink-violet mottle).
//!
//! Why: the photos' fine texture (each target minus its Gaussian blur of 0.5 mm) varies
//! almost along one colour axis, dark brown to light tan. On CN03 that axis carries 97.8 %
//! of the variance, the second 2.0 % and the third, a magenta-green axis, 0.3 %; the NCA's
//! faces put 0.9-1.3 % of theirs on that third axis (H11: 2-5 %, photos 0.5-1.1 %), and on
//! the sheets it is the pink-violet mottle between the pores. With `colour_axes = k` the
//! state's RGB residual is projected onto the first k axes before it is added to B, so the
//! rule cannot paint a colour the photos' texture does not have; the fitted B still
//! carries every colour the cube has at ring scale. `k = 3` is the identity (no projection),
//! the authors' readout.

use burn::tensor::{Device, Tensor};
use glam::DMat3;

use super::tensors::tensor_from;
use crate::image_filter::gaussian_blur;
use crate::image2::Image2;
use crate::symmetric_eigen::symmetric_eigen;

/// Sigma of the blur whose residual is the fine texture, in mm of the cube (4 cm a side):
/// about a pore wide, so pores and fibre streaks are in, ring-scale colour is out.
const FINE_TEXTURE_SIGMA_MM: f32 = 0.5;
/// Side of the cube in mm (the targets are `size` x `size` over one face).
const CUBE_MM: f32 = 40.0;

/// The principal axes of the targets' fine-texture colour: variances in descending order and
/// the unit axes as columns, in the targets' (white-balanced) colour space.
pub(crate) fn fine_texture_axes(targets: &[Option<Image2>]) -> ([f64; 3], DMat3) {
    let mut moments = [[0.0f64; 3]; 3];
    let mut count = 0usize;
    for target in targets.iter().flatten() {
        let sigma = FINE_TEXTURE_SIGMA_MM * target.width as f32 / CUBE_MM;
        let low: Vec<Image2> = (0..3)
            .map(|c| gaussian_blur(&target.channel(c), sigma))
            .collect();
        for (v, px) in target.data.chunks_exact(target.channels).enumerate() {
            let fine: [f64; 3] = std::array::from_fn(|c| f64::from(px[c] - low[c].data[v]));
            for (row, a) in moments.iter_mut().zip(fine) {
                for (m, b) in row.iter_mut().zip(fine) {
                    *m += a * b;
                }
            }
            count += 1;
        }
    }
    let n = count.max(1) as f64;
    let covariance = DMat3::from_cols_array_2d(&moments.map(|row| row.map(|m| m / n)));
    let (values, vectors) = symmetric_eigen(&covariance); // ascending
    (
        [values[2], values[1], values[0]],
        DMat3::from_cols(vectors.col(2), vectors.col(1), vectors.col(0)),
    )
}

/// The 3x3 projection (row-major) onto the first `count` fine-texture axes of `targets`, or
/// `None` for `count >= 3` (every colour allowed).
pub fn colour_projection(targets: &[Option<Image2>], count: usize) -> Option<[[f32; 3]; 3]> {
    if count >= 3 {
        return None;
    }
    let (_, axes) = fine_texture_axes(targets);
    let mut p = DMat3::ZERO;
    for j in 0..count {
        let u = axes.col(j);
        p += DMat3::from_cols(u * u.x, u * u.y, u * u.z);
    }
    Some(std::array::from_fn(|r| {
        std::array::from_fn(|c| p.col(c)[r] as f32)
    }))
}

/// `p` applied to every voxel of an RGB tensor `[3, X, Y, Z]` (differentiable).
pub(crate) fn project_tensor(rgb: Tensor<4>, p: &[[f32; 3]; 3], device: &Device) -> Tensor<4> {
    let dims = rgb.dims();
    let voxels = dims[1] * dims[2] * dims[3];
    let matrix = tensor_from(p.concat(), [3, 3], device); // [3, 3]
    matrix
        .matmul(rgb.reshape([3, voxels])) // [3, N]
        .reshape(dims)
}

/// `p` applied to one RGB value.
pub fn project(p: &[[f32; 3]; 3], rgb: [f32; 3]) -> [f32; 3] {
    p.map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nca::tensors::to_vec;

    /// A target whose fine texture moves only along `axis` (stripes of one pixel), on a
    /// ring-scale ramp along another colour.
    fn striped(size: usize, axis: [f32; 3]) -> Image2 {
        let mut img = Image2::filled(size, size, 3, 0.0);
        for r in 0..size {
            for c in 0..size {
                let stripe = if c % 3 == 0 { 0.1 } else { -0.05 };
                let ramp = r as f32 / size as f32 * 0.2;
                let px = img.pixel_mut(r, c);
                for k in 0..3 {
                    px[k] = 0.5 + stripe * axis[k] + ramp * [0.0, 0.0, 1.0][k];
                }
            }
        }
        img
    }

    #[test]
    fn the_first_axis_is_the_fine_texture_colour_and_not_the_ramp() {
        let axis = [0.6, 0.64, 0.48]; // unit
        let targets = [Some(striped(64, axis)), None];
        let (values, axes) = fine_texture_axes(&targets);
        assert!(values[0] > 100.0 * values[1].max(1e-12), "{values:?}");
        let dot: f64 = (0..3).map(|k| axes.col(0)[k] * f64::from(axis[k])).sum();
        assert!(dot.abs() > 0.999, "{:?}", axes.col(0));
    }

    #[test]
    fn the_projection_keeps_its_axes_and_removes_the_rest() {
        let axis = [0.6, 0.64, 0.48];
        let targets = [Some(striped(64, axis))];
        assert_eq!(colour_projection(&targets, 3), None);
        let p = colour_projection(&targets, 1).expect("one axis");
        let along = project(&p, axis);
        for k in 0..3 {
            assert!((along[k] - axis[k]).abs() < 1e-3, "{along:?}");
        }
        // Orthogonal to the axis: removed.
        let across = project(&p, [0.64, -0.6, 0.0]);
        assert!(across.iter().all(|v| v.abs() < 1e-3), "{across:?}");
        // The tensor form agrees with the per-voxel form.
        let device = Device::default();
        let rgb = tensor_from(vec![0.3, -0.2, 0.1, 0.5, 0.0, -0.4], [3, 2, 1, 1], &device);
        let out = to_vec(project_tensor(rgb, &p, &device)).expect("f32 tensor");
        for v in 0..2 {
            let voxel = [[0.3, -0.2], [0.1, 0.5], [0.0, -0.4]].map(|c: [f32; 2]| c[v]);
            let want = project(&p, voxel);
            for k in 0..3 {
                assert!((out[k * 2 + v] - want[k]).abs() < 1e-6, "{out:?} {want:?}");
            }
        }
    }
}
