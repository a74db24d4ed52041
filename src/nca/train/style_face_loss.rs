//! The style loss of `crate::loss` as the NCA's [`FaceLoss`], and the choice between it and
//! the moment baseline (`loss.face` in the training config).
//!
//! Target statistics are computed once from the white-balanced face photos at the training
//! grid side; each generated patch (a corner crop's part of a face, or a whole face) is
//! compared with the statistics of its whole face. The sliced-Wasserstein projections are
//! redrawn per iteration (seeded by the loss seed and the iteration) when the loss config
//! asks for it.

use burn::tensor::{Device, Tensor};

use super::guided_face_loss::GuidedFaceLoss;
use super::iteration::TrainData;
use super::loss::{FaceLoss, MomentLoss, no_target_loss};
use crate::error::{Result, XylemError};
use crate::image2::Image2;
use crate::loss::{StyleLoss, StyleTargets};
use crate::nca::config::{FaceLossKind, TrainConfig};
use crate::nca::faces::FacePatch;

/// The face loss a training config asks for, with targets `[Option<Image2>; 6]` in file
/// order (`None`: face not trained on). Fails, naming the config key, when the loss cannot
/// use the patches this config produces (crop smaller than the loss's filters).
pub fn face_loss(
    cfg: &TrainConfig,
    data: &TrainData,
    device: &Device,
) -> Result<Box<dyn FaceLoss>> {
    let targets = &data.targets;
    Ok(match cfg.loss.face {
        FaceLossKind::Moments => Box::new(MomentLoss::new(targets, device)),
        FaceLossKind::Style => Box::new(StyleFaceLoss::new(cfg, targets, device)?),
        FaceLossKind::Guided => Box::new(GuidedFaceLoss::new(cfg, data, device)?),
    })
}

/// [`StyleLoss`] against the whole faces' statistics.
pub struct StyleFaceLoss {
    loss: StyleLoss,
    targets: StyleTargets,
    /// Index into `targets` of each face (file order), `None` for faces without a photo.
    pair: [Option<usize>; 6],
}

impl StyleFaceLoss {
    pub fn new(cfg: &TrainConfig, targets: &[Option<Image2>; 6], device: &Device) -> Result<Self> {
        let loss = StyleLoss::new(&cfg.loss.style, device);
        let side = cfg.volume.crop_side();
        if !loss.usable(side, side) {
            return Err(XylemError::input(
                "training config [volume] crop",
                format!(
                    "= {side}: face patches of {side}x{side} are too small for the style loss \
                     (filters of {} px, at least {} valid feature pixels: [loss.style] \
                     min_layer_pixels); use a larger crop or smaller [loss.style] filters",
                    loss.min_side(),
                    cfg.loss.style.min_layer_pixels
                ),
            ));
        }
        let mut pair = [None; 6];
        let mut images = Vec::new();
        for (f, target) in targets.iter().enumerate() {
            if let Some(img) = target {
                pair[f] = Some(images.len());
                images.push(img.clone());
            }
        }
        let targets = loss.targets(&images)?;
        Ok(Self {
            loss,
            targets,
            pair,
        })
    }
}

impl FaceLoss for StyleFaceLoss {
    fn loss(&self, patches: &[FacePatch], iteration: usize) -> Tensor<1> {
        let (images, pairs): (Vec<Tensor<3>>, Vec<usize>) = patches
            .iter()
            .filter_map(|p| Some((p.image.clone(), self.pair[p.face.index()]?)))
            .unzip();
        if images.is_empty() {
            return no_target_loss(patches);
        }
        self.loss
            .loss_at(&images, &self.targets, &pairs, iteration as u64)
            .expect("patch sides and pairs are checked in StyleFaceLoss::new")
    }
}
