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
use super::gemm::{Block, Rows, Store, reduce_rows};
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
    /// The product shape of a block of `n` cells.
    fn block(&self, n: usize) -> Block {
        Block {
            stride: self.stride,
            cols: gemm_cols(n),
        }
    }

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

/// The hidden layer `work.hid` = relu(W1 inputs + b1) of the block's first `block.cols`
/// cells: the start of both passes (the backward pass recomputes it).
#[inline(always)]
fn hidden_layer<K: Kernels>(k: K, packed: &Packed, work: &mut BlockWork, block: Block) {
    k.gemm_hidden(
        packed.w1(),
        &work.inp,
        &mut work.hid,
        block,
        Store::BiasRelu(&packed.b1),
    );
}

/// Forward MLP of a block of `n` cells whose inputs are in `work.inp`: the state change
/// in `work.out` rows 0..C.
#[inline(always)]
pub(crate) fn forward_block<K: Kernels>(k: K, packed: &Packed, work: &mut BlockWork, n: usize) {
    let block = work.block(n);
    hidden_layer(k, packed, work, block);
    k.gemm_state(packed.w2(), &work.hid, &mut work.out, block, Store::Plain);
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
    let block = work.block(n);
    let span = (work.stride, lane_count(n));
    let h_rows = shapes.hidden_rows;
    hidden_layer(k, packed, work, block);
    k.gemm_hidden(
        packed.w2t(),
        &work.g,
        &mut work.dh,
        block,
        Store::Masked(&work.hid),
    );
    let (dz, hid) = (Rows::new(&work.dh, h_rows), Rows::new(&work.hid, h_rows));
    let inputs = Rows::new(&work.inp, shapes.input_rows);
    let next = Rows::new(&work.g, shapes.state_rows);
    k.reduce(dz, inputs, span, &mut lanes.w1);
    k.reduce(hid, next, span, &mut lanes.w2t);
    reduce_rows(k, &work.dh, h_rows, work.stride, span.1, &mut lanes.b1);
    k.gemm_state(packed.w1t(), &work.dh, &mut work.out, block, Store::Plain);
}
