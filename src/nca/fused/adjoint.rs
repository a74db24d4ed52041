//! The adjoint of one fused step: given g = dL/d(next state), the weight gradients of the
//! step and dL/d(state).
//!
//! next = state + W2 relu(W1 perceive(state, cond, pos) + b1), so
//! dL/d state = g + perceive^T(W1[:, ..5C]^T dz) (the residual path plus the perception's
//! adjoint). Two parallel passes over x-planes:
//! 1. per block: recompute the inputs and the hidden layer, back through the MLP
//!    (`mlp::backward_block`), write the perceived-state gradient `[5C, X, Y, Z]` to a
//!    scratch volume and sum the weight gradients of the plane;
//! 2. per z-line: the perception adjoint reads that volume around each cell
//!    (`perceive_adjoint`), which needs the neighbouring planes of pass 1 to be done.
//!
//! Determinism: each plane's weight gradients are summed in block order inside one task
//! and the planes' sums are added in plane order afterwards, so the result does not depend
//! on the number of threads or on scheduling (tested with 1 and 2 threads).

use rayon::prelude::*;

use super::dispatch::{Kernels, multiversion};
use super::forward::Stepper;
use super::lanes::LANES;
use super::layout::{BACKWARD_BLOCK, gemm_cols, planes_mut};
use super::mlp::{BlockWork, GradLanes, backward_block};
use super::perceive::{lines_at, neighbour_offsets};
use super::perceive_adjoint::{AdjointScratch, adjoint_xy, adjoint_z, border_signs, piece_groups};
use crate::nca::perception::FILTERS;

/// Gradients of the MLP weights, row-major as the weights (`MlpWeights`).
#[derive(Clone, Debug, PartialEq)]
pub struct Gradients {
    /// `[H, I]`
    pub w1: Vec<f32>,
    /// `[H]`
    pub b1: Vec<f32>,
    /// `[C, H]`
    pub w2: Vec<f32>,
}

impl Gradients {
    pub fn zeros(state: usize, hidden: usize, inputs: usize) -> Self {
        Self {
            w1: vec![0.0; hidden * inputs],
            b1: vec![0.0; hidden],
            w2: vec![0.0; state * hidden],
        }
    }

    fn add(&mut self, other: &Gradients) {
        let pairs = [
            (&mut self.w1, &other.w1),
            (&mut self.b1, &other.b1),
            (&mut self.w2, &other.w2),
        ];
        for (a, b) in pairs {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
    }
}

/// Buffers reused by every step of a backward pass.
pub struct AdjointBuffers {
    /// Perceived-state gradient `[5C, X, Y, Z]`.
    dp: Vec<f32>,
}

impl AdjointBuffers {
    pub fn new(st: &Stepper) -> Self {
        Self {
            dp: vec![0.0; FILTERS * st.state_len()],
        }
    }
}

impl Stepper<'_> {
    /// Adds the weight gradients of the step `state -> next` to `grads`, given
    /// `g_next` = dL/d next; writes dL/d state to `g_state` if given (the first step of an
    /// unroll does not need it).
    pub fn step_adjoint(
        &self,
        state: &[f32],
        g_next: &[f32],
        g_state: Option<&mut [f32]>,
        buffers: &mut AdjointBuffers,
        grads: &mut Gradients,
    ) {
        let (n, dims) = (self.state_len(), self.fixed.dims);
        assert!(state.len() == n && g_next.len() == n, "state buffer sizes");
        let planes = planes_mut(&mut buffers.dp, FILTERS * self.shapes.state, dims);
        let partials: Vec<Gradients> = planes
            .into_par_iter()
            .enumerate()
            .map_init(
                || {
                    (
                        BlockWork::new(&self.shapes, BACKWARD_BLOCK),
                        GradLanes::new(&self.shapes),
                    )
                },
                |(work, lanes), (x, mut dp)| {
                    backward_plane(self.isa, self, x, state, g_next, &mut dp, work, lanes)
                },
            )
            .collect();
        for p in &partials {
            grads.add(p);
        }
        if let Some(g_state) = g_state {
            let dp = &buffers.dp;
            let outs = planes_mut(g_state, self.shapes.state, dims);
            outs.into_par_iter().enumerate().for_each_init(
                AdjointScratch::default,
                |t, (x, mut out)| {
                    perception_adjoint_plane(self.isa, self, x, dp, g_next, &mut out, t)
                },
            );
        }
    }
}

multiversion!(
    /// Pass 1 of the adjoint for x-plane `x`: `dp[r]` is row r of plane x of the
    /// perceived-state gradient; returns the plane's weight gradients.
    fn backward_plane(st: &Stepper, x: usize, state: &[f32], g_next: &[f32], dp: &mut [&mut [f32]], work: &mut BlockWork, lanes: &mut GradLanes) -> Gradients => backward_plane_body
);

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn backward_plane_body<K: Kernels>(
    k: K,
    st: &Stepper,
    x: usize,
    state: &[f32],
    g_next: &[f32],
    dp: &mut [&mut [f32]],
    work: &mut BlockWork,
    lanes: &mut GradLanes,
) -> Gradients {
    let shapes = &st.shapes;
    let dims = st.fixed.dims;
    let (plane, cells) = (dims.plane(), dims.cells());
    let stride = work.stride;
    lanes.clear();
    for q0 in (0..plane).step_by(BACKWARD_BLOCK) {
        let n = BACKWARD_BLOCK.min(plane - q0);
        let cols = gemm_cols(n);
        st.fill_block(state, x, (q0, n), work);
        for (c, row) in work
            .g
            .chunks_exact_mut(stride)
            .take(shapes.state)
            .enumerate()
        {
            row[..n].copy_from_slice(&g_next[c * cells + x * plane + q0..][..n]);
            row[n..cols].fill(0.0);
        }
        backward_block(k, shapes, &st.packed, work, n, lanes);
        for (r, out) in dp.iter_mut().enumerate() {
            out[q0..q0 + n].copy_from_slice(&work.out[r * stride..][..n]);
        }
    }
    lane_sums(
        shapes.state,
        shapes.hidden,
        shapes.inputs,
        shapes.input_rows,
        shapes.state_rows,
        lanes,
    )
}

/// The weight gradients from the lane partial sums (summed over lanes in lane order).
fn lane_sums(
    state: usize,
    hidden: usize,
    inputs: usize,
    input_rows: usize,
    state_rows: usize,
    lanes: &GradLanes,
) -> Gradients {
    let sum = |at: usize, v: &[f32]| v[at * LANES..(at + 1) * LANES].iter().sum::<f32>();
    let mut g = Gradients::zeros(state, hidden, inputs);
    for j in 0..hidden {
        for k in 0..inputs {
            g.w1[j * inputs + k] = sum(j * input_rows + k, &lanes.w1);
        }
        g.b1[j] = sum(j, &lanes.b1);
        for c in 0..state {
            g.w2[c * hidden + j] = sum(j * state_rows + c, &lanes.w2t);
        }
    }
    g
}

multiversion!(
    /// Pass 2 of the adjoint for x-plane `x`: `out[c]` = channel c of plane x of dL/d state.
    fn perception_adjoint_plane(st: &Stepper, x: usize, dp: &[f32], g_next: &[f32], out: &mut [&mut [f32]], t: &mut AdjointScratch) => perception_adjoint_body
);

#[inline(always)]
fn perception_adjoint_body<K: Kernels>(
    _k: K,
    st: &Stepper,
    x: usize,
    dp: &[f32],
    g_next: &[f32],
    out: &mut [&mut [f32]],
    t: &mut AdjointScratch,
) {
    let dims = st.fixed.dims;
    let [nx, ny, nz] = dims.0;
    let cells = dims.cells();
    let (sxm, sxp) = border_signs(x, nx);
    for group in piece_groups(ny, nz) {
        for (c, out_c) in out.iter_mut().enumerate() {
            let row = |f: usize| &dp[(FILTERS * c + f) * cells..][..cells];
            let rows = [row(0), row(1), row(2), row(3), row(4)];
            for p in &group {
                let (sym, syp) = border_signs(p.y, ny);
                let offsets = neighbour_offsets(dims, x, p.y);
                let lines = |f: usize| lines_at(rows[f], &offsets, nz);
                let fields = [lines(0), lines(1), lines(2), lines(3), lines(4)];
                adjoint_xy(&fields, [sxm, sxp, sym, syp], p.z0, p.len, nz, t, p.at);
            }
            for p in &group {
                let line = dims.line(x, p.y) + p.z0;
                let identity = &rows[0][line..][..p.len];
                let g = &g_next[c * cells + line..][..p.len];
                let dst = &mut out_c[p.y * nz + p.z0..][..p.len];
                adjoint_z(t, p.at, p.len, identity, g, dst);
            }
        }
    }
}
