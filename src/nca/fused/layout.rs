//! Buffer layouts and shapes of the fused kernels.
//!
//! Volumes are plain `f32` buffers `[C, X, Y, Z]` (channel planes, x slowest, z fastest;
//! burn's layout, so tensors convert without reordering). Work is split into x-planes: one
//! task updates all cells of one x (`Y * Z` consecutive values in every channel plane), so
//! tasks write disjoint slices and the partition does not depend on the thread count.
//! Inside a task, cells are taken `block` at a time in storage order (a block may span
//! several z-lines); each block's inputs, hidden layer and outputs are small row-major
//! matrices `[rows][block]` that stay in the core's caches.
//!
//! Row counts of those matrices are padded with zero rows to multiples of the kernel tiles
//! (`Shapes`), so the kernels have no remainder cases.

use super::dispatch::{MAX_NV, Tiles};
use super::lanes::{LANES, round_up};
use crate::nca::perception::{FILTERS, POSITION_CHANNELS};

/// Cells per block in the forward step (inputs 73 x 64 and hidden 128 x 64 floats: 51 KB).
pub const FORWARD_BLOCK: usize = 64;
/// Cells per block in the backward step: the weight-gradient tiles stay in registers over a
/// whole block, so larger blocks amortise their flush into the lane buffers.
pub(crate) const BACKWARD_BLOCK: usize = 256;

/// The sizes of one model on one instruction set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shapes {
    /// State channels C.
    pub state: usize,
    /// Conditioning channels K.
    pub cond: usize,
    /// MLP inputs I = 5 (C + K) + 3.
    pub inputs: usize,
    /// Hidden width H.
    pub hidden: usize,
    /// H padded to the hidden gemm and reduction tiles.
    pub hidden_rows: usize,
    /// C padded to the state gemm and reduction tiles.
    pub state_rows: usize,
    /// I padded to the reduction tile.
    pub input_rows: usize,
    /// 5 C (the perceived state) padded to the state gemm tile.
    pub perceived_rows: usize,
}

impl Shapes {
    pub fn new(state: usize, cond: usize, hidden: usize, tiles: Tiles) -> Self {
        let inputs = FILTERS * (state + cond) + POSITION_CHANNELS;
        let (rx, ry) = tiles.reduce;
        Self {
            state,
            cond,
            inputs,
            hidden,
            hidden_rows: round_up(hidden, lcm(tiles.rm_hidden, rx)),
            state_rows: round_up(state, lcm(tiles.rm_state, ry)),
            input_rows: round_up(inputs, ry),
            perceived_rows: round_up(FILTERS * state, tiles.rm_state),
        }
    }

    /// Row of the first position channel among the inputs.
    pub(crate) fn position_row(&self) -> usize {
        FILTERS * (self.state + self.cond)
    }
}

fn lcm(a: usize, b: usize) -> usize {
    let gcd = |mut a: usize, mut b: usize| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    a / gcd(a, b) * b
}

/// Columns the gemms run over for a block of `n` cells: whole gemm tiles.
pub(crate) fn gemm_cols(n: usize) -> usize {
    round_up(n, MAX_NV * LANES)
}

/// Lane arrays covering `n` cells.
pub(crate) fn lane_count(n: usize) -> usize {
    n.div_ceil(LANES)
}

/// The extent of a volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dims(pub [usize; 3]);

impl Dims {
    pub fn cells(self) -> usize {
        self.0.iter().product()
    }

    /// Cells of one x-plane, `Y * Z`.
    pub fn plane(self) -> usize {
        self.0[1] * self.0[2]
    }

    /// Start of z-line (x, y) in a channel plane.
    pub fn line(self, x: usize, y: usize) -> usize {
        (x * self.0[1] + y) * self.0[2]
    }
}

/// Per x-plane, the slices of every row of a `[rows, X, Y, Z]` buffer that belong to it:
/// `result[x][row]`, each `Y * Z` long. The slices are disjoint, so tasks can own them.
pub(crate) fn planes_mut(buf: &mut [f32], rows: usize, dims: Dims) -> Vec<Vec<&mut [f32]>> {
    let n = dims.cells();
    debug_assert_eq!(buf.len(), rows * n);
    let mut planes: Vec<Vec<&mut [f32]>> =
        (0..dims.0[0]).map(|_| Vec::with_capacity(rows)).collect();
    for row in buf.chunks_exact_mut(n) {
        for (x, part) in row.chunks_exact_mut(dims.plane()).enumerate() {
            planes[x].push(part);
        }
    }
    planes
}
