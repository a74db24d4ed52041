//! Gradients through an unroll with segment checkpointing (BURN-NOTES "Memory for backprop").
//!
//! Backpropagating through a whole unroll keeps every step's activations on the tape (~45 MB
//! per step at 32^3, ~360 MB at 64^3). Instead:
//! 1. run the unroll without autodiff, keeping only the state at the start of each segment of
//!    `segment` steps;
//! 2. walk the segments backwards: re-run a segment from its saved state on the autodiff
//!    device with the state marked `require_grad`; its objective is the loss (last segment)
//!    or `sum(state_out * incoming_gradient)` (earlier segments), whose gradient with respect
//!    to the parameters and the input state is exactly the chain rule's contribution of that
//!    segment; accumulate the parameter gradients and carry the input-state gradient back.
//!
//! Memory is one segment's tape plus the saved states; time is one extra forward unroll.
//! There is no randomness in a step (every voxel updates every step), so the re-run segment
//! reproduces the saved forward exactly and the gradients equal full backprop (tested).

use burn::module::Module;
use burn::optim::{GradientsAccumulator, GradientsParams};
use burn::tensor::Tensor;

use super::model::{Nca, StepInputs};

/// The loss of a final state: the scalar to differentiate and named values to log.
pub struct Objective {
    /// `[1]`, on the autodiff device.
    pub total: Tensor<1>,
    /// Loss terms for the log (already read back).
    pub terms: Vec<(&'static str, f32)>,
}

/// The result of one forward + backward pass.
pub struct UnrollGradients {
    pub loss: f32,
    pub terms: Vec<(&'static str, f32)>,
    /// Parameter gradients (of the autodiff `model` passed in).
    pub grads: GradientsParams,
    /// The final state, without autodiff.
    pub final_state: Tensor<4>,
}

/// Steps of each segment of an unroll of `steps` (`segment` 0: one segment).
pub(crate) fn segment_lengths(steps: usize, segment: usize) -> Vec<usize> {
    if segment == 0 || segment >= steps {
        return vec![steps];
    }
    let mut lens = vec![segment; steps / segment];
    if !steps.is_multiple_of(segment) {
        lens.push(steps % segment);
    }
    lens
}

/// Gradients of `objective(final state)` with respect to the parameters of `model` (which
/// lives on an autodiff device), through `steps` steps from `start` (no autodiff).
/// `inputs` holds constants without autodiff; they enter the tape as constants.
pub fn unroll_gradients(
    model: &Nca,
    start: Tensor<4>,
    inputs: &StepInputs,
    steps: usize,
    segment: usize,
    mut objective: impl FnMut(Tensor<4>) -> Objective,
) -> UnrollGradients {
    let lens = segment_lengths(steps, segment);
    let starts = segment_starts(model, start, inputs, &lens);
    let mut accumulator = GradientsAccumulator::<Nca>::new();
    let mut carried: Option<Tensor<4>> = None;
    let mut result = None;
    for (k, (state_in, &len)) in starts.into_iter().zip(&lens).enumerate().rev() {
        let state_in = Tensor::from_inner(state_in).require_grad();
        let mut state = state_in.clone();
        for _ in 0..len {
            state = model.step(state, inputs);
        }
        let total = match carried.take() {
            None => {
                let obj = objective(state.clone());
                let loss = obj.total.clone().inner().into_scalar::<f32>();
                result = Some((loss, obj.terms, state.clone().inner()));
                obj.total
            }
            // d/dθ sum(out * g) = g^T d out/dθ: this segment's share of the chain rule.
            Some(g) => (state * g).sum(),
        };
        let mut grads = total.backward();
        if k > 0 {
            carried = state_in.grad_remove(&mut grads);
        }
        accumulator.accumulate(model, GradientsParams::from_grads(grads, model));
    }
    let (loss, terms, final_state) = result.expect("an unroll has at least one segment");
    UnrollGradients {
        loss,
        terms,
        grads: accumulator.grads(),
        final_state,
    }
}

/// The forward pass without autodiff: the state at the start of every segment.
fn segment_starts(
    model: &Nca,
    start: Tensor<4>,
    inputs: &StepInputs,
    lens: &[usize],
) -> Vec<Tensor<4>> {
    let plain = model.valid();
    let mut starts = Vec::with_capacity(lens.len());
    let mut state = start.inner();
    for (k, &len) in lens.iter().enumerate() {
        starts.push(state.clone());
        if k + 1 < lens.len() {
            for _ in 0..len {
                state = plain.step(state, inputs);
            }
        }
    }
    starts
}
