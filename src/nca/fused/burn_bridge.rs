//! The seam between the fused kernels and burn in training: burn keeps the parameters, the
//! optimiser and the face loss; the unroll and its backward pass run in the fused kernels.
//!
//! The final state of the fused unroll becomes a burn leaf tensor that requires grad; the
//! loss on it is differentiated by burn's autodiff (cheap: a few face patches), its
//! gradient goes back through the fused adjoint, and the weight gradients come back as a
//! `GradientsParams` keyed by the model's own parameter ids, exactly what
//! `checkpoint::unroll_gradients` (the all-burn reference) returns.

use burn::optim::GradientsParams;
use burn::tensor::{Device, Tensor};

use super::forward::Stepper;
use super::inputs::FixedInputs;
use super::isa::Isa;
use super::train_step::unroll_gradients as fused_unroll_gradients;
use super::weights::MlpWeights;
use crate::error::Result;
use crate::nca::checkpoint::{Objective, UnrollGradients};
use crate::nca::model::Nca;
use crate::nca::tensors::{tensor_from, to_vec};

/// Gradients of `objective(final state)` with respect to the parameters of `model` (on an
/// autodiff device) through `steps` steps from `start` (no autodiff), with segments of
/// `segment` steps. `plain` is the device without autodiff the results are returned on.
#[allow(clippy::too_many_arguments)]
pub fn unroll_gradients(
    model: &Nca,
    plain: &Device,
    isa: Isa,
    start: Tensor<4>,
    fixed: &FixedInputs,
    steps: usize,
    segment: usize,
    objective: impl FnOnce(Tensor<4>) -> Objective,
) -> Result<UnrollGradients> {
    let weights = MlpWeights::from_model(model)?;
    let stepper = Stepper::new(isa, &weights, fixed)?;
    let dims = start.dims();
    let outcome = fused_unroll_gradients(&stepper, to_vec(start)?, steps, segment, |last| {
        final_state_gradient(last, dims, plain, objective)
    })?;
    let (loss, terms) = outcome.loss;
    let (h, i, c) = (weights.hidden, weights.inputs, weights.state);
    let mut grads = GradientsParams::new();
    grads.register(model.w1.id, tensor_from(outcome.grads.w1, [h, i], plain));
    grads.register(model.b1.id, tensor_from(outcome.grads.b1, [h], plain));
    grads.register(model.w2.id, tensor_from(outcome.grads.w2, [c, h], plain));
    Ok(UnrollGradients {
        loss,
        terms,
        grads,
        final_state: tensor_from(outcome.final_state, dims, plain),
    })
}

/// The loss of a final state and its gradient, through burn's autodiff; zero gradient if
/// the loss does not depend on the state.
#[allow(clippy::type_complexity)]
fn final_state_gradient(
    last: &[f32],
    dims: [usize; 4],
    plain: &Device,
    objective: impl FnOnce(Tensor<4>) -> Objective,
) -> Result<(Vec<f32>, (f32, Vec<(&'static str, f32)>))> {
    let leaf = Tensor::from_inner(tensor_from(last.to_vec(), dims, plain)).require_grad();
    let obj = objective(leaf.clone());
    let loss = obj.total.clone().inner().into_scalar::<f32>();
    let mut grads = obj.total.backward();
    let g = match leaf.grad_remove(&mut grads) {
        Some(g) => to_vec(g)?,
        None => vec![0.0; last.len()],
    };
    Ok((g, (loss, obj.terms)))
}
