//! One fused NCA step over a whole volume, and an unroll of many steps over two state
//! buffers (ping-pong).
//!
//! `Stepper::step` splits the volume into x-planes (rayon tasks); each task walks its plane
//! in blocks of `FORWARD_BLOCK` cells: perception of the state and conditioning into the
//! block's input matrix, the MLP, and `next = state + delta` for the block's cells. Every
//! cell's result depends only on the inputs, never on the thread that computed it.

use rayon::prelude::*;

use super::dispatch::{Kernels, multiversion};
use super::inputs::FixedInputs;
use super::isa::Isa;
use super::layout::{FORWARD_BLOCK, Shapes, gemm_cols, planes_mut};
use super::mlp::{BlockWork, forward_block};
use super::perceive::fill_inputs;
use super::weights::{MlpWeights, Packed};
use crate::error::{Result, XylemError};

/// A model ready to step over one region on one instruction set.
pub struct Stepper<'a> {
    pub isa: Isa,
    pub shapes: Shapes,
    pub packed: Packed,
    pub fixed: &'a FixedInputs,
}

impl<'a> Stepper<'a> {
    pub fn new(isa: Isa, weights: &MlpWeights, fixed: &'a FixedInputs) -> Result<Self> {
        let shapes = Shapes::new(
            weights.state,
            fixed.cond_channels,
            weights.hidden,
            isa.tiles(),
        );
        let sizes_ok = weights.w1.len() == weights.hidden * weights.inputs
            && weights.w2.len() == weights.state * weights.hidden
            && weights.b1.len() == weights.hidden;
        if weights.inputs != shapes.inputs || !sizes_ok {
            return Err(XylemError::input(
                "fused NCA",
                format!(
                    "the model has {} inputs for {} state channels; the region gives {} conditioning channels, which needs {}",
                    weights.inputs, weights.state, fixed.cond_channels, shapes.inputs
                ),
            ));
        }
        Ok(Self {
            isa,
            shapes,
            packed: Packed::new(weights, &shapes, isa.tiles()),
            fixed,
        })
    }

    /// Values of a state buffer: `C * X * Y * Z`.
    pub(crate) fn state_len(&self) -> usize {
        self.shapes.state * self.fixed.dims.cells()
    }

    /// `next = state + delta(state)`, both `[C, X, Y, Z]`.
    pub fn step(&self, state: &[f32], next: &mut [f32]) {
        assert_eq!(state.len(), self.state_len(), "state buffer size");
        let planes = planes_mut(next, self.shapes.state, self.fixed.dims);
        planes.into_par_iter().enumerate().for_each_init(
            || BlockWork::new(&self.shapes, FORWARD_BLOCK),
            |work, (x, mut outs)| forward_plane(self.isa, self, x, state, &mut outs, work),
        );
    }

    /// The input matrix (perception and conditioning) of the `n` cells from `q0` of plane
    /// `x` into `work.inp`, zero beyond `n`.
    pub(crate) fn fill_block(
        &self,
        state: &[f32],
        x: usize,
        cells: (usize, usize),
        work: &mut BlockWork,
    ) {
        let cols = gemm_cols(cells.1);
        let (inp, scratch) = (&mut work.inp, &mut work.scratch);
        fill_inputs(
            &self.shapes,
            self.fixed,
            state,
            x,
            cells,
            inp,
            (work.stride, cols),
            scratch,
        );
    }

    /// `steps` steps from `state`, calling `progress` after each; two buffers in all.
    pub fn unroll(
        &self,
        mut state: Vec<f32>,
        steps: usize,
        mut progress: impl FnMut(usize),
    ) -> Vec<f32> {
        let mut next = vec![0.0f32; state.len()];
        for s in 0..steps {
            self.step(&state, &mut next);
            std::mem::swap(&mut state, &mut next);
            progress(s + 1);
        }
        state
    }
}

multiversion!(
    /// One x-plane of a step: `outs[c]` is channel c of plane x of the next state.
    fn forward_plane(st: &Stepper, x: usize, state: &[f32], outs: &mut [&mut [f32]], work: &mut BlockWork) => forward_plane_body
);

#[inline(always)]
fn forward_plane_body<K: Kernels>(
    k: K,
    st: &Stepper,
    x: usize,
    state: &[f32],
    outs: &mut [&mut [f32]],
    work: &mut BlockWork,
) {
    let dims = st.fixed.dims;
    let (plane, cells) = (dims.plane(), dims.cells());
    let stride = work.stride;
    for q0 in (0..plane).step_by(FORWARD_BLOCK) {
        let n = FORWARD_BLOCK.min(plane - q0);

        st.fill_block(state, x, (q0, n), work);
        forward_block(k, &st.packed, work, n);
        for (c, out) in outs.iter_mut().enumerate() {
            let old = &state[c * cells + x * plane + q0..][..n];
            let delta = &work.out[c * stride..][..n];
            for ((o, &s), &d) in out[q0..q0 + n].iter_mut().zip(old).zip(delta) {
                *o = s + d;
            }
        }
    }
}
