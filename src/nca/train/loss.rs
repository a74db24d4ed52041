//! The seam between the NCA and the face losses.
//!
//! [`FaceLoss`] is what training calls: generated face patches (white-balanced RGB
//! `[3, h, w]`, each knowing its face and where it sits in that face) in, a scalar tensor out.
//! [`super::style_face_loss::StyleFaceLoss`] (the default, `loss.face = "style"`) is the
//! VGG-free style loss of `crate::loss` with target statistics precomputed from the whole
//! face photos (a crop is compared with the whole face's statistics).
//!
//! [`MomentLoss`] (`loss.face = "moments"`) is a cheap baseline kept for fast tests and as an
//! ablation: per face, the mean and covariance of five features (R, G, B and the horizontal
//! and vertical differences of lightness) at two scales (full and 2x2-averaged), compared by
//! mean squared difference with the same statistics of the whole target face. It matches
//! colour, contrast and gradient orientation statistics; it cannot describe pores or ring
//! structure.

use burn::tensor::{Device, Tensor};

use crate::frame::Face;
use crate::image2::Image2;
use crate::loss::image_to_tensor;
use crate::nca::faces::FacePatch;

/// A loss on generated face patches.
pub trait FaceLoss {
    /// The loss of `patches` (each `[3, h, w]`, white-balanced RGB) against the targets of
    /// their faces, as a `[1]` tensor on the patches' device. Patches of faces without a
    /// target contribute nothing. `iteration` seeds losses that draw random projections
    /// per call, so a resumed run draws what the uninterrupted one would have.
    fn loss(&self, patches: &[FacePatch], iteration: usize) -> Tensor<1>;
}

/// The loss of a crop that touches only faces left out: zero, with no gradient, on the
/// patches' device.
pub(crate) fn no_target_loss(patches: &[FacePatch]) -> Tensor<1> {
    let device = patches
        .first()
        .map(|p| p.image.device())
        .unwrap_or_default();
    Tensor::zeros([1], &device)
}

/// Features per pixel of [`MomentLoss`].
const FEATURES: usize = 5;
/// Scales (1 = full resolution, 2 = 2x2 averages).
const SCALES: [usize; 2] = [1, 2];

/// Mean `[5]` and covariance `[5, 5]` of the features of one image at one scale.
struct Moments {
    mean: Tensor<1>,
    cov: Tensor<2>,
}

/// Stand-in style loss: feature means and covariances against the whole target faces.
pub struct MomentLoss {
    /// Per face (file order) and scale, the target moments (no autodiff).
    targets: [Option<Vec<Moments>>; 6],
}

impl MomentLoss {
    /// Precomputes the target statistics of the white-balanced face images (`None` for faces
    /// not used in training).
    pub fn new(targets: &[Option<Image2>; 6], device: &Device) -> Self {
        let stats = |img: &Image2| {
            let t = image_to_tensor(img, device);
            SCALES
                .iter()
                .map(|&s| moments(pool(t.clone(), s)))
                .collect()
        };
        Self {
            targets: std::array::from_fn(|f| targets[f].as_ref().map(stats)),
        }
    }

    fn target(&self, face: Face) -> Option<&Vec<Moments>> {
        self.targets[face.index()].as_ref()
    }
}

impl FaceLoss for MomentLoss {
    fn loss(&self, patches: &[FacePatch], _iteration: usize) -> Tensor<1> {
        let mut terms = Vec::new();
        for patch in patches {
            let Some(target) = self.target(patch.face) else {
                continue;
            };
            for (&scale, t) in SCALES.iter().zip(target) {
                let g = moments(pool(patch.image.clone(), scale));
                let dm = (g.mean - t.mean.clone()).square().mean();
                let dc = (g.cov - t.cov.clone()).square().mean();
                terms.push(dm + dc);
            }
        }
        let count = terms.len().max(1) as f32;
        match terms.into_iter().reduce(|a, b| a + b) {
            Some(sum) => sum.div_scalar(count),
            None => {
                let device = patches
                    .first()
                    .map(|p| p.image.device())
                    .unwrap_or_default();
                Tensor::zeros([1], &device)
            }
        }
    }
}

/// Average pooling by `s` x `s` (odd remainders are dropped): `[3, H, W]` -> `[3, H/s, W/s]`.
fn pool(img: Tensor<3>, s: usize) -> Tensor<3> {
    if s == 1 {
        return img;
    }
    let [c, h, w] = img.dims();
    let (h2, w2) = (h / s, w / s);
    img.narrow(1, 0, h2 * s)
        .narrow(2, 0, w2 * s)
        .reshape([c, h2, s, w2, s])
        .mean_dim(4)
        .mean_dim(2)
        .reshape([c, h2, w2])
}

/// Moments of the five features of `[3, H, W]`.
fn moments(img: Tensor<3>) -> Moments {
    let [_, h, w] = img.dims();
    let light = img.clone().mean_dim(0); // [1, H, W]
    let gx = light.clone().narrow(2, 1, w - 1) - light.clone().narrow(2, 0, w - 1); // [1, H, W-1]
    let gy = light.clone().narrow(1, 1, h - 1) - light.narrow(1, 0, h - 1); // [1, H-1, W]
    let features = Tensor::cat(
        vec![
            img.narrow(1, 0, h - 1).narrow(2, 0, w - 1),
            gx.narrow(1, 0, h - 1),
            gy.narrow(2, 0, w - 1),
        ],
        0,
    ); // [5, H-1, W-1]
    let p = (h - 1) * (w - 1);
    let f = features.reshape([FEATURES, p]);
    let mean = f.clone().mean_dim(1); // [5, 1]
    let centred = f - mean.clone();
    let cov = centred
        .clone()
        .matmul(centred.transpose())
        .div_scalar(p as f32); // [5, 5]
    Moments {
        mean: mean.reshape([FEATURES]),
        cov,
    }
}
