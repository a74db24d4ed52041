//! The NCA's fixed perception: kernels exactly as DESIGN section 6, replicate padding, and the
//! two implementations (shifted slices, grouped conv3d) agreeing with a plain loop.
// Kernel offsets a, b, c index the kernels and, mirrored, the outputs: plain indices read
// as the formulas they check.
#![allow(clippy::needless_range_loop)]

mod common;
use common::max_abs_diff;

use burn::tensor::{Device, Tensor};
use xylem::nca::perception::{PerceptionImpl, kernels};
use xylem::nca::tensors::{tensor_from, to_vec};
use xylem::rng::Rng;

fn device() -> Device {
    Device::flex()
}

/// DESIGN section 6, written out: identity; Sobel = [1,2,1] x [1,2,1] x [-1,0,1] / 4 with the
/// difference along the filter's axis; Laplacian layers / 8.
fn design_kernels() -> Vec<[[[f32; 3]; 3]; 3]> {
    let s = [1.0, 2.0, 1.0];
    let d = [-1.0, 0.0, 1.0];
    let mut out = vec![[[[0.0; 3]; 3]; 3]; 5];
    out[0][1][1][1] = 1.0;
    for a in 0..3 {
        for b in 0..3 {
            for c in 0..3 {
                out[1][a][b][c] = d[a] * s[b] * s[c] / 4.0;
                out[2][a][b][c] = s[a] * d[b] * s[c] / 4.0;
                out[3][a][b][c] = s[a] * s[b] * d[c] / 4.0;
            }
        }
    }
    let outer = [[2.0, 3.0, 2.0], [3.0, 6.0, 3.0], [2.0, 3.0, 2.0]];
    let middle = [[3.0, 6.0, 3.0], [6.0, -88.0, 6.0], [3.0, 6.0, 3.0]];
    for b in 0..3 {
        for c in 0..3 {
            out[4][0][b][c] = outer[b][c] / 8.0;
            out[4][1][b][c] = middle[b][c] / 8.0;
            out[4][2][b][c] = outer[b][c] / 8.0;
        }
    }
    out
}

#[test]
fn kernel_table_equals_design() {
    let k = kernels();
    for (f, expected) in design_kernels().iter().enumerate() {
        assert_eq!(&k[f], expected, "filter {f}");
    }
    // The Laplacian sums to zero; each Sobel sums to zero and has unit-ish weight 4 per side.
    let sum: f32 = k[4].iter().flatten().flatten().sum();
    assert!(sum.abs() < 1e-6);
}

/// An impulse in the middle of a 5^3 volume: output voxel (2 - (a-1), ...) of filter f reads
/// kernel entry [a][b][c] (cross-correlation).
#[test]
fn impulse_response_is_the_kernels_for_both_implementations() {
    let n = 5;
    let mut data = vec![0.0f32; n * n * n];
    data[(2 * n + 2) * n + 2] = 1.0;
    let x: Tensor<4> = tensor_from(data, [1, n, n, n], &device());
    let design = design_kernels();
    for imp in [PerceptionImpl::Shifted, PerceptionImpl::Conv] {
        let out = to_vec(imp.perceive(x.clone())).unwrap();
        assert_eq!(out.len(), 5 * n * n * n);
        for (f, kernel) in design.iter().enumerate() {
            for a in 0..3 {
                for b in 0..3 {
                    for c in 0..3 {
                        let (i, j, k) = (3 - a, 3 - b, 3 - c);
                        let got = out[((f * n + i) * n + j) * n + k];
                        assert!(
                            (got - kernel[a][b][c]).abs() < 1e-6,
                            "{imp:?} filter {f} at {a}{b}{c}: {got} vs {}",
                            kernel[a][b][c]
                        );
                    }
                }
            }
        }
    }
}

/// Plain loops with clamped (replicate) indices, the definition of the perception.
fn reference(input: &[f32], c: usize, dims: [usize; 3]) -> Vec<f32> {
    let k = kernels();
    let [nx, ny, nz] = dims;
    let at = |ch: usize, i: isize, j: isize, l: isize| {
        let i = i.clamp(0, nx as isize - 1) as usize;
        let j = j.clamp(0, ny as isize - 1) as usize;
        let l = l.clamp(0, nz as isize - 1) as usize;
        input[((ch * nx + i) * ny + j) * nz + l]
    };
    let mut out = vec![0.0f32; c * 5 * nx * ny * nz];
    for ch in 0..c {
        for f in 0..5 {
            for i in 0..nx {
                for j in 0..ny {
                    for l in 0..nz {
                        let mut acc = 0.0;
                        for a in 0..3 {
                            for b in 0..3 {
                                for cc in 0..3 {
                                    acc += k[f][a][b][cc]
                                        * at(
                                            ch,
                                            i as isize + a as isize - 1,
                                            j as isize + b as isize - 1,
                                            l as isize + cc as isize - 1,
                                        );
                                }
                            }
                        }
                        out[(((ch * 5 + f) * nx + i) * ny + j) * nz + l] = acc;
                    }
                }
            }
        }
    }
    out
}

#[test]
fn both_implementations_match_plain_loops_with_replicate_padding() {
    let (c, dims) = (3, [4, 5, 6]);
    let mut rng = Rng::new(3);
    let input: Vec<f32> = (0..c * dims.iter().product::<usize>())
        .map(|_| rng.range(-1.0, 1.0))
        .collect();
    let expected = reference(&input, c, dims);
    let x: Tensor<4> = tensor_from(input, [c, dims[0], dims[1], dims[2]], &device());
    for imp in [PerceptionImpl::Shifted, PerceptionImpl::Conv] {
        let got = to_vec(imp.perceive(x.clone())).unwrap();
        let worst = max_abs_diff(&got, &expected);
        assert!(worst < 1e-4, "{imp:?}: max difference {worst}");
    }
}

#[test]
fn constant_field_has_zero_gradients_and_laplacian_at_the_border_too() {
    let x: Tensor<4> = Tensor::ones([1, 3, 3, 3], &device()).mul_scalar(0.7);
    let out = to_vec(PerceptionImpl::Shifted.perceive(x)).unwrap();
    for (idx, v) in out.iter().enumerate() {
        let f = idx / 27;
        let expected = if f == 0 { 0.7 } else { 0.0 };
        assert!((v - expected).abs() < 1e-5, "filter {f}: {v}");
    }
}
