//! The MLP weights as plain arrays, and packed for the kernels of one instruction set.

use super::dispatch::Tiles;
use super::gemm::{Tiled, pack};
use super::layout::Shapes;
use crate::error::{Result, XylemError};
use crate::nca::model::Nca;
use crate::nca::perception::FILTERS;
use crate::nca::tensors::to_vec;

/// Row-major copies of the model's parameters (burn's layout).
#[derive(Clone, Debug, PartialEq)]
pub struct MlpWeights {
    /// State channels C.
    pub state: usize,
    /// Hidden width H.
    pub hidden: usize,
    /// Inputs I.
    pub inputs: usize,
    /// `[H, I]`
    pub w1: Vec<f32>,
    /// `[H]`
    pub b1: Vec<f32>,
    /// `[C, H]`
    pub w2: Vec<f32>,
}

impl MlpWeights {
    /// The parameters of a burn model (on any device, with or without autodiff).
    pub(crate) fn from_model(model: &Nca) -> Result<Self> {
        let [hidden, inputs] = model.w1.dims();
        let [state, h2] = model.w2.dims();
        let w = Self {
            state,
            hidden,
            inputs,
            w1: to_vec(model.w1.val())?,
            b1: to_vec(model.b1.val())?,
            w2: to_vec(model.w2.val())?,
        };
        if h2 != hidden || w.b1.len() != hidden {
            return Err(XylemError::input(
                "fused NCA weights",
                format!(
                    "w1 {:?}, b1 [{}], w2 {:?} do not form one MLP",
                    model.w1.dims(),
                    w.b1.len(),
                    model.w2.dims()
                ),
            ));
        }
        Ok(w)
    }

    /// Conditioning channels implied by the input count, if it fits `5 (C + K) + 3`.
    pub fn cond_channels(&self) -> Option<usize> {
        let perceived = self.inputs.checked_sub(3)?;
        (perceived % FILTERS == 0)
            .then(|| (perceived / FILTERS).checked_sub(self.state))
            .flatten()
    }
}

/// The weights packed into the tiles of one instruction set (`gemm::pack`).
#[derive(Clone, Debug)]
pub struct Packed {
    /// W1 `[H, I]` for the hidden layer.
    w1: Vec<f32>,
    /// b1 padded to `hidden_rows`.
    pub b1: Vec<f32>,
    /// W2 `[C, H]` for the state update.
    w2: Vec<f32>,
    /// W2^T `[H, C]` for the hidden-layer gradient.
    w2t: Vec<f32>,
    /// The perceived-state columns of W1, transposed, `[5 C, H]`, for the perception gradient.
    w1t: Vec<f32>,
    /// C, H and I: the matrices' column counts.
    state: usize,
    hidden: usize,
    inputs: usize,
}

impl Packed {
    pub fn new(w: &MlpWeights, shapes: &Shapes, tiles: Tiles) -> Self {
        let (c, h, i) = (w.state, w.hidden, w.inputs);
        let mut b1 = w.b1.clone();
        b1.resize(shapes.hidden_rows, 0.0);
        Self {
            w1: pack(&w.w1, (h, i), (i, 1), tiles.rm_hidden, shapes.hidden_rows),
            b1,
            w2: pack(&w.w2, (c, h), (h, 1), tiles.rm_state, shapes.state_rows),
            w2t: pack(&w.w2, (h, c), (1, h), tiles.rm_hidden, shapes.hidden_rows),
            w1t: pack(
                &w.w1,
                (FILTERS * c, h),
                (1, i),
                tiles.rm_state,
                shapes.perceived_rows,
            ),
            state: c,
            hidden: h,
            inputs: i,
        }
    }

    pub fn w1(&self) -> Tiled<'_> {
        Tiled::new(&self.w1, self.inputs)
    }

    pub fn w2(&self) -> Tiled<'_> {
        Tiled::new(&self.w2, self.hidden)
    }

    pub fn w2t(&self) -> Tiled<'_> {
        Tiled::new(&self.w2t, self.state)
    }

    pub fn w1t(&self) -> Tiled<'_> {
        Tiled::new(&self.w1t, self.hidden)
    }
}
