//! The update network: a 1x1x1 MLP applied at every voxel, and one NCA step.
//!
//! inputs (73) -> hidden (128, bias, ReLU) -> state delta (12, no bias), added to the state at
//! every voxel at every step (no stochastic update mask; DESIGN section 6). The first layer is
//! Xavier-normal with gain 0.2, the second starts at zero so the untrained NCA is the identity
//! and training begins from "B alone". The second layer has no bias, as in the NCA literature
//! (a bias would push every voxel the same way at every step). Weights are drawn from the
//! config seed with [`crate::rng::Rng`], so flex and ndarray start from the same numbers.
//!
//! The inputs are laid out as `[perceive(state) (5 x 12) | perceive(cond) (5 x K) | pos (3)]`;
//! the last two do not change during an unroll and are computed once ([`StepInputs`]).

use burn::module::{Module, Param, ParamId};
use burn::tensor::activation::relu;
use burn::tensor::{Device, Tensor};

use super::config::ModelSpec;
use super::perception::{PerceptionImpl, pad_replicate};
use super::tensors::tensor_from;
use crate::rng::Rng;

/// Xavier-normal gain of the first layer (DESIGN: small, so early updates are gentle).
const FIRST_LAYER_GAIN: f32 = 0.2;

/// The trainable part of the NCA.
#[derive(Module, Debug)]
pub struct Nca {
    /// `[hidden, inputs]`
    pub w1: Param<Tensor<2>>,
    /// `[hidden]`
    pub b1: Param<Tensor<1>>,
    /// `[state, hidden]`
    pub w2: Param<Tensor<2>>,
}

/// The inputs that stay fixed during an unroll: perceived conditioning and positions,
/// `[5 K + 3, X, Y, Z]`, plus the perception implementation.
#[derive(Clone, Debug)]
pub struct StepInputs {
    pub constant: Tensor<4>,
    pub perception: PerceptionImpl,
}

impl StepInputs {
    /// Perceives the conditioning `[K, X, Y, Z]` (K may be 0) and appends the positions
    /// `[3, X, Y, Z]`.
    pub fn new(cond: Option<Tensor<4>>, positions: Tensor<4>, perception: PerceptionImpl) -> Self {
        let constant = match cond {
            Some(c) => Tensor::cat(vec![perception.perceive(c), positions], 0),
            None => positions,
        };
        Self {
            constant,
            perception,
        }
    }

    /// The x-slab [start, start + len) of the fixed inputs.
    pub fn slab(&self, start: usize, len: usize) -> Tensor<4> {
        self.constant.clone().narrow(1, start, len)
    }
}

impl Nca {
    /// A fresh model: first layer Xavier-normal (gain 0.2) from `seed`, biases and second
    /// layer zero.
    pub fn init(spec: &ModelSpec, seed: u64, device: &Device) -> Self {
        let (h, i, c) = (spec.hidden, spec.inputs(), spec.state_channels);
        let std = FIRST_LAYER_GAIN * (2.0 / (h + i) as f32).sqrt();
        let mut rng = Rng::substream(seed, 0x4E43_415F_494E_4954); // "NCA_INIT"
        let w1: Vec<f32> = (0..h * i).map(|_| std * rng.normal()).collect();
        Self {
            w1: fixed_id(Param::from_tensor(tensor_from(w1, [h, i], device)), 1),
            b1: fixed_id(Param::from_tensor(Tensor::zeros([h], device)), 2),
            w2: fixed_id(Param::from_tensor(Tensor::zeros([c, h], device)), 3),
        }
    }

    /// The state change of one step for a slab: `padded` is the replicate-padded state
    /// `[C, X+2, Y+2, Z+2]`, `constant` the fixed inputs `[5 K + 3, X, Y, Z]`; returns
    /// `[C, X, Y, Z]`.
    pub fn delta(
        &self,
        padded: Tensor<4>,
        constant: Tensor<4>,
        perception: PerceptionImpl,
    ) -> Tensor<4> {
        let [_, x, y, z] = constant.dims();
        let features = Tensor::cat(vec![perception.perceive_padded(padded), constant], 0);
        let inputs = features.dims()[0];
        let v = x * y * z;
        let features = features.reshape([inputs, v]); // [I, V]
        let hidden = self.w1.val().matmul(features) + self.b1.val().reshape([self.hidden(), 1]); // [H, V]
        let delta = self.w2.val().matmul(relu(hidden)); // [C, V]
        let c = delta.dims()[0];
        delta.reshape([c, x, y, z])
    }

    /// One step over the whole state `[C, X, Y, Z]` at once.
    pub fn step(&self, state: Tensor<4>, inputs: &StepInputs) -> Tensor<4> {
        let delta = self.delta(
            pad_replicate(state.clone()),
            inputs.constant.clone(),
            inputs.perception,
        );
        state + delta
    }

    pub fn hidden(&self) -> usize {
        self.w1.dims()[0]
    }

    /// Checks that loaded weights have the shapes `spec` asks for.
    pub fn matches(&self, spec: &ModelSpec) -> bool {
        self.w1.dims() == [spec.hidden, spec.inputs()]
            && self.b1.dims() == [spec.hidden]
            && self.w2.dims() == [spec.state_channels, spec.hidden]
    }
}

/// The parameter with a fixed id: burn draws ids at random and writes them into model.bpk,
/// so two identical trainings wrote different files (and weight hashes); ids only need to be
/// unique within the model.
fn fixed_id<const D: usize>(mut param: Param<Tensor<D>>, id: u64) -> Param<Tensor<D>> {
    param.id = ParamId::from(id);
    param
}
