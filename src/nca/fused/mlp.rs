//! The MLP of one block of cells, forward and backward, on the block's input matrix.
//!
//! Forward: hidden `[H][n]` = relu(W1 inputs + b1), delta `[C][n]` = W2 hidden; the hidden
//! layer never leaves the core's caches.
//! Backward, given g = dL/d(next state) `[C][n]` (the update is residual, so it is also
//! dL/d delta): h = relu(W1 inputs + b1) is recomputed (cheaper than storing 128 floats per
//! cell and step), then dz = W2^T g where h > 0 else 0 (h > 0 exactly where the
//! pre-activation is), and dW2 += g h^T, db1 += sum dz, dW1 += dz inputs^T (lane partial
//! sums, see `gemm::reduce`), d perceived-state = W1[:, ..5C]^T dz.

use super::dispatch::Kernels;
use super::gemm::{Store, reduce_rows};
use super::lanes::LANES;
use super::layout::{Shapes, gemm_cols, lane_count};
use super::perceive::ForwardScratch;
use super::weights::Packed;

/// The matrices of one block, `[rows][stride]` each, reused from block to block.
pub struct BlockWork {
    /// Cells per block (a multiple of the gemm tile width).
    pub stride: usize,
    /// Inputs `[input_rows][stride]` (rows beyond the inputs stay zero).
    pub inp: Vec<f32>,
    /// Hidden layer after the ReLU `[hidden_rows][stride]`.
    pub hid: Vec<f32>,
    /// Backward: dz, the gradient of the hidden pre-activation `[hidden_rows][stride]`.
    pub dh: Vec<f32>,
    /// Gradient of the next state `[state_rows][stride]` (rows beyond C stay zero).
    pub g: Vec<f32>,
    /// Forward: the state change `[state_rows][stride]`; backward: the perceived-state
    /// gradient `[perceived_rows][stride]`.
    pub out: Vec<f32>,
    pub scratch: ForwardScratch,
}

impl BlockWork {
    pub fn new(shapes: &Shapes, block: usize) -> Self {
        let stride = gemm_cols(block);
        let rows = |r: usize| vec![0.0f32; r * stride];
        Self {
            stride,
            inp: rows(shapes.input_rows),
            hid: rows(shapes.hidden_rows),
            dh: rows(shapes.hidden_rows),
            g: rows(shapes.state_rows),
            out: rows(shapes.state_rows.max(shapes.perceived_rows)),
            scratch: ForwardScratch::default(),
        }
    }
}

/// Per-task sums of weight gradients, kept per lane (`gemm::reduce`).
pub struct GradLanes {
    /// `[hidden_rows][input_rows][LANES]`
    pub w1: Vec<f32>,
    /// `[hidden_rows][LANES]`
    pub b1: Vec<f32>,
    /// W2 transposed: `[hidden_rows][state_rows][LANES]`
    pub w2t: Vec<f32>,
}

impl GradLanes {
    pub fn new(shapes: &Shapes) -> Self {
        let h = shapes.hidden_rows;
        Self {
            w1: vec![0.0; h * shapes.input_rows * LANES],
            b1: vec![0.0; h * LANES],
            w2t: vec![0.0; h * shapes.state_rows * LANES],
        }
    }

    pub fn clear(&mut self) {
        self.w1.fill(0.0);
        self.b1.fill(0.0);
        self.w2t.fill(0.0);
    }
}

/// Forward MLP of a block of `n` cells whose inputs are in `work.inp`: the state change
/// in `work.out` rows 0..C.
#[inline(always)]
pub(crate) fn forward_block<K: Kernels>(
    k: K,
    shapes: &Shapes,
    packed: &Packed,
    work: &mut BlockWork,
    n: usize,
) {
    let (stride, cols) = (work.stride, gemm_cols(n));
    k.gemm_hidden(
        &packed.w1,
        shapes.inputs,
        &work.inp,
        &mut work.hid,
        stride,
        cols,
        Store::BiasRelu(&packed.b1),
    );
    k.gemm_state(
        &packed.w2,
        shapes.hidden,
        &work.hid,
        &mut work.out,
        stride,
        cols,
        Store::Plain,
    );
}

/// Backward MLP of a block of `n` cells: inputs in `work.inp`, dL/d(next state) in `work.g`
/// (zero beyond n). Adds the weight gradients to `lanes`; leaves d perceived-state in
/// `work.out` rows 0..5C.
#[inline(always)]
pub fn backward_block<K: Kernels>(
    k: K,
    shapes: &Shapes,
    packed: &Packed,
    work: &mut BlockWork,
    n: usize,
    lanes: &mut GradLanes,
) {
    let (stride, cols, nvec) = (work.stride, gemm_cols(n), lane_count(n));
    let h_rows = shapes.hidden_rows;
    k.gemm_hidden(
        &packed.w1,
        shapes.inputs,
        &work.inp,
        &mut work.hid,
        stride,
        cols,
        Store::BiasRelu(&packed.b1),
    );
    k.gemm_hidden(
        &packed.w2t,
        shapes.state,
        &work.g,
        &mut work.dh,
        stride,
        cols,
        Store::Masked(&work.hid),
    );
    k.reduce(
        &work.dh,
        h_rows,
        &work.inp,
        shapes.input_rows,
        stride,
        nvec,
        &mut lanes.w1,
    );
    k.reduce(
        &work.hid,
        h_rows,
        &work.g,
        shapes.state_rows,
        stride,
        nvec,
        &mut lanes.w2t,
    );
    reduce_rows(k, &work.dh, h_rows, stride, nvec, &mut lanes.b1);
    k.gemm_state(
        &packed.w1t,
        shapes.hidden,
        &work.dh,
        &mut work.out,
        stride,
        cols,
        Store::Plain,
    );
}
