//! The two register-tiled matrix kernels every layer of the fused step is made of.
//!
//! Block matrices are row-major with the cells of a block along the rows:
//! `[rows][stride]`, `stride` = the block's cell capacity (a multiple of `2 * LANES`).
//!
//! - [`gemm`]: `C = A B (+ bias)`, A a small weight matrix packed by [`pack`] (tiles of `RM`
//!   rows, each stored k-major: `[M / RM][K][RM]`), B and C block matrices. A tile of `RM`
//!   rows x `NV` lane arrays of C stays in registers while k runs; every step of k loads
//!   `NV` lane arrays of B and broadcasts `RM` weights. Used for both layers forward and
//!   for the transposed layers backward.
//! - [`reduce`]: `G += X Y^T` summed over cells (weight gradients). A tile of `RM` x `RK`
//!   lane arrays of partial sums stays in registers over all cells of the block and is then
//!   added to a per-task buffer of lane partial sums `[M][K][LANES]`, which is summed across
//!   lanes once per task. No horizontal sums in the hot loop.
//!
//! Row counts are padded (zero rows) to multiples of the tiles, so there are no remainder
//! tiles: see `layout::Shapes`.

use super::lanes::{LANES, lane, lane_mut};
use super::simd::Simd;

/// Packs the row-major `m x k` matrix `a` (element (i, j) at `a[i * row_stride + j *
/// col_stride]`) into tiles of `rm` rows, zero rows up to `padded_rows`:
/// `[padded_rows / rm][k][rm]`.
pub fn pack(
    a: &[f32],
    (m, k): (usize, usize),
    (row_stride, col_stride): (usize, usize),
    rm: usize,
    padded_rows: usize,
) -> Vec<f32> {
    debug_assert_eq!(padded_rows % rm, 0);
    let mut out = vec![0.0f32; padded_rows * k];
    for (t, tile) in out.chunks_exact_mut(k * rm).enumerate() {
        for (j, col) in tile.chunks_exact_mut(rm).enumerate() {
            for (r, v) in col.iter_mut().enumerate() {
                let i = t * rm + r;
                if i < m {
                    *v = a[i * row_stride + j * col_stride];
                }
            }
        }
    }
    out
}

/// How a [`gemm`] result is stored.
#[derive(Clone, Copy)]
pub enum Store<'a> {
    /// `C = A B`.
    Plain,
    /// `C = A B + bias` (one value per row).
    Bias(&'a [f32]),
    /// `C = max(A B + bias, 0)`.
    BiasRelu(&'a [f32]),
    /// `C = A B` where the matrix `mask` (same layout as C) is > 0, else 0: the ReLU's
    /// backward pass, with the hidden layer after the ReLU as the mask.
    Masked(&'a [f32]),
}

/// A weight matrix packed by [`pack`]: `k` columns, tiles of the kernel's `RM` rows.
#[derive(Clone, Copy)]
pub struct Tiled<'a> {
    pub tiles: &'a [f32],
    pub k: usize,
}

impl<'a> Tiled<'a> {
    pub fn new(tiles: &'a [f32], k: usize) -> Self {
        Self { tiles, k }
    }
}

/// The shape shared by the block matrices of one product: `[rows][stride]`, of which the
/// first `cols` columns are computed.
#[derive(Clone, Copy)]
pub struct Block {
    pub stride: usize,
    pub cols: usize,
}

/// The first `rows` rows of a block matrix `[rows][stride]`.
#[derive(Clone, Copy)]
pub struct Rows<'a> {
    pub data: &'a [f32],
    pub rows: usize,
}

impl<'a> Rows<'a> {
    pub fn new(data: &'a [f32], rows: usize) -> Self {
        Self { data, rows }
    }
}

/// `C[0..rows][0..cols] = A B` (+ store variant), A packed with `RM` rows per tile, B
/// `[k][stride]`, C `[rows][stride]`, `cols` a multiple of `NV * LANES`.
#[inline(always)]
pub fn gemm<S: Simd, const RM: usize, const NV: usize>(
    s: S,
    a: Tiled,
    b: &[f32],
    c: &mut [f32],
    Block { stride, cols }: Block,
    store: Store,
) {
    let Tiled { tiles: a, k } = a;
    debug_assert_eq!(cols % (NV * LANES), 0);
    for (t, (a_tile, c_rows)) in a
        .chunks_exact(k * RM)
        .zip(c.chunks_exact_mut(RM * stride))
        .enumerate()
    {
        // Plain loops rather than `array::from_fn`: a closure that is not inlined would call
        // the intrinsics out of the `#[target_feature]` function (measured: 18% of a step).
        let mut bias = [s.zero(); RM];
        if let Store::Bias(b) | Store::BiasRelu(b) = store {
            for (r, v) in bias.iter_mut().enumerate() {
                *v = s.splat(b[t * RM + r]);
            }
        }
        for col in (0..cols).step_by(NV * LANES) {
            let mut acc = [[s.zero(); NV]; RM];
            for (r, row) in acc.iter_mut().enumerate() {
                *row = [bias[r]; NV];
            }
            for (kk, w) in a_tile.chunks_exact(RM).enumerate() {
                let row = &b[kk * stride + col..kk * stride + col + NV * LANES];
                let mut x = [s.zero(); NV];
                for (v, xv) in x.iter_mut().enumerate() {
                    *xv = s.load(lane(row, v * LANES));
                }
                for r in 0..RM {
                    let wr = s.splat(w[r]);
                    for v in 0..NV {
                        acc[r][v] = s.madd(wr, x[v], acc[r][v]);
                    }
                }
            }
            for (r, out) in c_rows.chunks_exact_mut(stride).enumerate() {
                // Indexed: iterating `acc` by reference here halved the speed (the
                // accumulators left the registers).
                #[allow(clippy::needless_range_loop)]
                for v in 0..NV {
                    let at = col + v * LANES;
                    let value = match store {
                        Store::BiasRelu(_) => s.relu(acc[r][v]),
                        Store::Masked(mask) => {
                            let m = s.load(lane(mask, (t * RM + r) * stride + at));
                            s.select_positive(m, acc[r][v])
                        }
                        Store::Plain | Store::Bias(_) => acc[r][v],
                    };
                    s.store(value, lane_mut(out, at));
                }
            }
        }
    }
}

/// `lanes[i][j][l] += sum over lane arrays v of x[i][v LANES + l] y[j][v LANES + l]` for the
/// first `x.rows` rows of x (`[x_rows][stride]`) and `y.rows` of y, over `nvec` lane arrays;
/// `lanes` is `[x_rows][y_rows][LANES]`. `x_rows % RM == 0`, `y_rows % RK == 0`.
#[inline(always)]
pub fn reduce<S: Simd, const RM: usize, const RK: usize>(
    s: S,
    x: Rows,
    y: Rows,
    (stride, nvec): (usize, usize),
    lanes: &mut [f32],
) {
    let Rows {
        data: x,
        rows: x_rows,
    } = x;
    let Rows {
        data: y,
        rows: y_rows,
    } = y;
    debug_assert!(x_rows.is_multiple_of(RM) && y_rows.is_multiple_of(RK));
    for mt in 0..x_rows / RM {
        let xs: [&[f32]; RM] =
            std::array::from_fn(|r| &x[(mt * RM + r) * stride..][..nvec * LANES]);
        for kt in 0..y_rows / RK {
            let ys: [&[f32]; RK] =
                std::array::from_fn(|q| &y[(kt * RK + q) * stride..][..nvec * LANES]);
            let mut acc = [[s.zero(); RK]; RM];
            for v in 0..nvec {
                let mut yv = [s.zero(); RK];
                for (q, y) in yv.iter_mut().enumerate() {
                    *y = s.load(lane(ys[q], v * LANES));
                }
                for r in 0..RM {
                    let xv = s.load(lane(xs[r], v * LANES));
                    for q in 0..RK {
                        acc[r][q] = s.madd(xv, yv[q], acc[r][q]);
                    }
                }
            }
            for (r, acc_r) in acc.iter().enumerate() {
                for (q, &a) in acc_r.iter().enumerate() {
                    let dst = lane_mut(lanes, ((mt * RM + r) * y_rows + kt * RK + q) * LANES);
                    let sum = s.add(s.load(dst), a);
                    s.store(sum, dst);
                }
            }
        }
    }
}

/// `lanes[i][l] += sum over lane arrays v of x[i][v LANES + l]` for `rows` rows.
#[inline(always)]
pub(crate) fn reduce_rows<S: Simd>(
    s: S,
    x: &[f32],
    rows: usize,
    stride: usize,
    nvec: usize,
    lanes: &mut [f32],
) {
    for (i, row) in x.chunks_exact(stride).take(rows).enumerate() {
        let mut acc = s.zero();
        for v in 0..nvec {
            acc = s.add(acc, s.load(lane(row, v * LANES)));
        }
        let dst = lane_mut(lanes, i * LANES);
        let sum = s.add(s.load(dst), acc);
        s.store(sum, dst);
    }
}
