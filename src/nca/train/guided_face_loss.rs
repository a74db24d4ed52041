//! The guided local loss of `crate::loss::guided` as the NCA's [`FaceLoss`]
//! (`[loss] face = "guided"`, the default of the shipped configs): each face patch of a crop
//! against the photo's window around the same place, with the ring phase of the fitted field
//! as a guide, so the pores land in the rings where the photo has them.

use burn::tensor::{Device, Tensor};

use super::iteration::TrainData;
use super::loss::{FaceLoss, no_target_loss};
use crate::error::{Result, XylemError};
use crate::loss::{GuidedLoss, GuidedPatch, GuidedTarget};
use crate::nca::config::TrainConfig;
use crate::nca::faces::FacePatch;

pub(crate) struct GuidedFaceLoss {
    loss: GuidedLoss,
    targets: Vec<GuidedTarget>,
    /// Index into `targets` of each face (file order), `None` for faces without a photo.
    pair: [Option<usize>; 6],
}

impl GuidedFaceLoss {
    pub(crate) fn new(cfg: &TrainConfig, data: &TrainData, device: &Device) -> Result<Self> {
        let loss = GuidedLoss::new(&cfg.loss.style, &cfg.loss.guided, device);
        let side = cfg.volume.crop_side();
        if !loss.usable(side, side) {
            return Err(XylemError::input(
                "training config [volume] crop",
                format!(
                    "= {side}: face patches of {side}x{side} are too small for the guided loss's \
                     filters ([loss.style] filters and min_layer_pixels); use a larger crop"
                ),
            ));
        }
        let mut pair = [None; 6];
        let mut targets = Vec::new();
        for (f, (image, guide)) in data.targets.iter().zip(&data.guides).enumerate() {
            if let (Some(image), Some(guide)) = (image, guide) {
                pair[f] = Some(targets.len());
                targets.push(loss.target(image, guide)?);
            }
        }
        Ok(Self {
            loss,
            targets,
            pair,
        })
    }
}

impl FaceLoss for GuidedFaceLoss {
    fn loss(&self, patches: &[FacePatch], iteration: usize) -> Tensor<1> {
        let guided: Vec<GuidedPatch> = patches
            .iter()
            .filter_map(|p| {
                Some(GuidedPatch {
                    image: p.image.clone(),
                    target: self.pair[p.face.index()]?,
                    origin: p.origin,
                    guide: p.guide.clone(),
                })
            })
            .collect();
        if guided.is_empty() {
            return no_target_loss(patches);
        }
        self.loss
            .terms(&guided, &self.targets, iteration as u64)
            .expect("patch sizes and places are checked in GuidedFaceLoss::new and by the crops")
            .total
    }
}
