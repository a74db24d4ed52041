//! Gradients of a loss on the final state of an unroll with respect to the MLP weights,
//! with segment checkpointing, all in fused kernels.
//!
//! 1. Forward: the state at the start of every segment is kept; the last segment keeps all
//!    its states (they are needed first, so they are never recomputed).
//! 2. The caller's loss gives dL/d(final state).
//! 3. Backward, segment by segment from the last: the segment's states are recomputed from
//!    its saved start (except the last), then `Stepper::step_adjoint` walks its steps back,
//!    adding the weight gradients and carrying dL/d state.
//!
//! A state is `C` floats per cell (the hidden layer is recomputed inside the adjoint), so
//! memory is (segments + the longest segment) states: `segment = 0` (one segment) keeps
//! every state and recomputes nothing, which at 64^3 x 15 steps is 190 MB.

use super::adjoint::{AdjointBuffers, Gradients};
use super::forward::Stepper;
use crate::error::{Result, XylemError};
use crate::nca::checkpoint::segment_lengths;

/// What a checkpointed unroll returns.
pub struct UnrollOutcome<T> {
    pub final_state: Vec<f32>,
    pub grads: Gradients,
    /// What the loss returned besides the gradient.
    pub loss: T,
}

/// Unrolls `steps` steps from `start` and backpropagates `loss(final state)`, which returns
/// dL/d(final state) (same length as the state) and anything else to pass through.
pub fn unroll_gradients<T>(
    st: &Stepper,
    start: Vec<f32>,
    steps: usize,
    segment: usize,
    loss: impl FnOnce(&[f32]) -> Result<(Vec<f32>, T)>,
) -> Result<UnrollOutcome<T>> {
    let n = st.state_len();
    if steps == 0 {
        return Err(XylemError::input(
            "fused NCA unroll",
            "no steps to differentiate through",
        ));
    }
    if start.len() != n {
        return Err(XylemError::input(
            "fused NCA unroll",
            format!("start state has {} values, expected {n}", start.len()),
        ));
    }
    let lens = segment_lengths(steps, segment);
    let (starts, mut last) = forward(st, start, &lens);
    let final_state = last.pop().expect("a segment's states");
    let (mut g, extra) = loss(&final_state)?;
    if g.len() != n {
        return Err(XylemError::numeric(
            "fused NCA backward",
            format!(
                "the loss gave {} gradient values for {n} state values",
                g.len()
            ),
        ));
    }
    let shapes = &st.shapes;
    let mut grads = Gradients::zeros(shapes.state, shapes.hidden, shapes.inputs);
    let mut buffers = AdjointBuffers::new(st);
    let mut g_prev = vec![0.0f32; n];
    for (k, &len) in lens.iter().enumerate().rev() {
        let states = if k + 1 == lens.len() {
            std::mem::take(&mut last)
        } else {
            segment_states(st, starts[k].clone(), len)
        };
        for (t, s) in states.iter().enumerate().rev() {
            let first = k == 0 && t == 0;
            let g_state = (!first).then_some(g_prev.as_mut_slice());
            st.step_adjoint(s, &g, g_state, &mut buffers, &mut grads);
            std::mem::swap(&mut g, &mut g_prev);
        }
    }
    Ok(UnrollOutcome {
        final_state,
        grads,
        loss: extra,
    })
}

/// The forward pass: the start state of every segment but the last, and all states of the
/// last segment including the final one.
fn forward(st: &Stepper, start: Vec<f32>, lens: &[usize]) -> (Vec<Vec<f32>>, Vec<Vec<f32>>) {
    let mut starts = Vec::with_capacity(lens.len());
    let mut state = start;
    for &len in &lens[..lens.len() - 1] {
        starts.push(state.clone());
        state = st.unroll(state, len, |_| {});
    }
    let mut last = segment_states(st, state, lens[lens.len() - 1]);
    let end = {
        let mut next = vec![0.0f32; st.state_len()];
        st.step(last.last().expect("a state"), &mut next);
        next
    };
    last.push(end);
    (starts, last)
}

/// The `len` states s_0 .. s_{len-1} of a segment starting at `start` (s_0 = start).
fn segment_states(st: &Stepper, start: Vec<f32>, len: usize) -> Vec<Vec<f32>> {
    let mut states = Vec::with_capacity(len + 1);
    states.push(start);
    for _ in 1..len {
        let mut next = vec![0.0f32; st.state_len()];
        st.step(states.last().expect("a state"), &mut next);
        states.push(next);
    }
    states
}
