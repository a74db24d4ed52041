//! The pool of states (Mordvintsev et al. 2020): an iteration continues from a stored state
//! of an earlier iteration, so the NCA learns to keep its texture over long unrolls rather
//! than only to reach it after a few steps. Every `fresh_every` iterations the drawn slot gets
//! a fresh seed instead, so the NCA also keeps learning to grow from noise.
//!
//! With crops, each slot remembers the region (place in the grid) its state belongs to. A pool of size 0
//! starts every iteration from a fresh seed (the trial of DESIGN section 6 did that).

use burn::tensor::{Device, Tensor};

use crate::error::{Result, XylemError};
use crate::nca::region::Region;
use crate::nca::tensors::{tensor_from, to_vec};

/// One stored state and its region.
#[derive(Clone, Debug)]
pub struct Slot {
    pub region: Region,
    /// `[C, X, Y, Z]`, no autodiff.
    pub state: Tensor<4>,
}

/// A slot as plain data: region, state shape `[C, X, Y, Z]`, values.
pub(crate) type PlainSlot = (Region, [usize; 4], Vec<f32>);

#[derive(Clone, Debug, Default)]
pub struct Pool {
    slots: Vec<Option<Slot>>,
}

/// Where an iteration starts.
#[derive(Clone, Debug)]
pub enum Start {
    /// A fresh seed in a region drawn by the caller; written back to `slot` if any.
    Fresh { slot: Option<usize> },
    /// Continue from a stored state (boxed: a slot with its region is much larger than
    /// the fresh variant).
    Continue { slot: usize, from: Box<Slot> },
}

impl Pool {
    pub fn new(size: usize) -> Self {
        Self {
            slots: vec![None; size],
        }
    }

    pub fn len(&self) -> usize {
        self.slots.len()
    }

    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// The start of an iteration: slot `draw` (a uniform draw in [0, len)), fresh if the slot
    /// is empty or `fresh` is set.
    pub fn start(&self, draw: usize, fresh: bool) -> Start {
        if self.slots.is_empty() {
            return Start::Fresh { slot: None };
        }
        match &self.slots[draw] {
            Some(s) if !fresh => Start::Continue {
                slot: draw,
                from: Box::new(s.clone()),
            },
            _ => Start::Fresh { slot: Some(draw) },
        }
    }

    /// Stores the result of an iteration.
    pub fn put(&mut self, slot: usize, region: Region, state: Tensor<4>) {
        self.slots[slot] = Some(Slot { region, state });
    }

    /// Empties a slot: its next draw starts from a fresh seed.
    pub fn clear(&mut self, slot: usize) {
        self.slots[slot] = None;
    }

    /// Regions of the filled slots.
    pub fn regions(&self) -> impl Iterator<Item = &Region> {
        self.slots.iter().flatten().map(|s| &s.region)
    }

    /// The pool as plain data: per slot its region (or `None`) and its values.
    pub fn to_data(&self) -> Result<Vec<Option<PlainSlot>>> {
        self.slots
            .iter()
            .map(|s| {
                s.as_ref()
                    .map(|s| Ok((s.region, s.state.dims(), to_vec(s.state.clone())?)))
                    .transpose()
            })
            .collect()
    }

    /// Rebuilds a pool from [`Pool::to_data`].
    pub fn from_data(data: Vec<Option<PlainSlot>>, device: &Device) -> Result<Self> {
        let slots = data
            .into_iter()
            .map(|s| {
                s.map(|(region, dims, values)| {
                    if values.len() != dims.iter().product::<usize>() {
                        return Err(XylemError::numeric(
                            "pool",
                            format!("{} values for a state of shape {dims:?}", values.len()),
                        ));
                    }
                    Ok(Slot {
                        region,
                        state: tensor_from(values, dims, device),
                    })
                })
                .transpose()
            })
            .collect::<Result<_>>()?;
        Ok(Self { slots })
    }
}
