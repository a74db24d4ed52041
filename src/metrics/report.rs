//! All comparison metrics of a candidate image against a reference, as one struct with the
//! names `xylem compare` prints and `metrics.csv` uses as columns.
//!
//! Images of different sizes: the candidate is resized (box filter) to the reference's size
//! when their aspect ratios agree to 1 %; otherwise the comparison is refused, because
//! stretching would change the grain direction and the ring spacing being measured.

use burn::tensor::Device;

use super::anisotropy::pore_anisotropy;
use super::lab::{colour_differences, image_to_lab};
use super::orientation::orientation_agreement;
use super::patch_swd::{PatchChannels, PatchSwdSettings, patch_swd};
use super::ring::{RingSettings, ring_ncc};
use super::speckle::speckle;
use crate::error::{Result, XylemError};
use crate::image2::Image2;
use crate::loss::{LossConfig, StyleLoss, StyleTargets, image_to_tensor};

/// Metric names in output order (JSON keys, CSV columns).
pub const METRIC_NAMES: [&str; 12] = [
    "ring_ncc",
    "orient",
    "swd",
    "swd_L",
    "swd_chroma",
    "dE_mean",
    "dE_std",
    "style",
    "aniso",
    "aniso_ref",
    "speckle",
    "speckle_ref",
];

/// The metrics of one comparison. Perfect values: `ring_ncc` 1, `orient` 1, `aniso` equal to
/// `aniso_ref`, `speckle` equal to `speckle_ref`, all others 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Ring alignment: best correlation of band-passed luminance over small shifts, [-1, 1].
    pub ring_ncc: f32,
    /// Grain-direction agreement: weighted mean cos(2 delta theta), [-1, 1].
    pub orient: f32,
    /// Patch texture distance in Lab (Delta E / 100), two scales.
    pub swd: f32,
    /// The same on lightness patches only.
    pub swd_l: f32,
    /// The same on (a, b) patches only.
    pub swd_chroma: f32,
    /// Distance between the mean Lab colours (Delta E).
    pub de_mean: f32,
    /// Distance between the Lab standard deviations (Delta E).
    pub de_std: f32,
    /// The style loss of the candidate against the reference's statistics.
    pub style: f32,
    /// Pore-scale anisotropy of the candidate, [0, 1] (not a distance: compare with
    /// `aniso_ref`).
    pub aniso: f32,
    /// Pore-scale anisotropy of the reference.
    pub aniso_ref: f32,
    /// Pixel-scale speckle of the candidate (white noise 1, checkerboard 2; not a distance:
    /// compare with `speckle_ref`).
    pub speckle: f32,
    /// Pixel-scale speckle of the reference.
    pub speckle_ref: f32,
}

impl Metrics {
    /// The values in [`METRIC_NAMES`] order.
    pub fn values(&self) -> [f32; 12] {
        [
            self.ring_ncc,
            self.orient,
            self.swd,
            self.swd_l,
            self.swd_chroma,
            self.de_mean,
            self.de_std,
            self.style,
            self.aniso,
            self.aniso_ref,
            self.speckle,
            self.speckle_ref,
        ]
    }

    /// One JSON object on one line (non-finite values as `null`).
    pub fn to_json(&self) -> String {
        let fields: Vec<String> = METRIC_NAMES
            .iter()
            .zip(self.values())
            .map(|(name, v)| {
                if v.is_finite() {
                    format!("\"{name}\": {v}")
                } else {
                    format!("\"{name}\": null")
                }
            })
            .collect();
        format!("{{{}}}", fields.join(", "))
    }

    /// The values as CSV fields in [`METRIC_NAMES`] order.
    pub(crate) fn csv_fields(&self) -> Vec<String> {
        self.values().iter().map(|v| v.to_string()).collect()
    }
}

/// What the metrics are computed with; build once and reuse for many comparisons.
pub struct Comparer {
    style: StyleLoss,
    device: Device,
    ring: RingSettings,
    patches: PatchSwdSettings,
}

impl Comparer {
    /// Default settings, the style loss of `loss` on `device` (no autodiff needed). The
    /// metric uses the fixed projections and every target pixel (`swd.redraw` off), so it is
    /// exact and the same on every call: an image against itself scores 0.
    pub fn new(loss: &LossConfig, device: &Device) -> Self {
        let mut loss = loss.clone();
        loss.swd.redraw = false;
        Self {
            style: StyleLoss::new(&loss, device),
            device: device.clone().without_autodiff(),
            ring: RingSettings::default(),
            patches: PatchSwdSettings::default(),
        }
    }

    /// All metrics of `candidate` against `reference` (RGB or grey, display-referred).
    pub fn compare(&self, reference: &Image2, candidate: &Image2) -> Result<Metrics> {
        let candidate = match_size(reference, candidate)?;
        let reference = reference.with_channels(3);
        let (lab_r, lab_c) = (image_to_lab(&reference), image_to_lab(&candidate));
        let swd = |ch| patch_swd(&lab_r, &lab_c, ch, &self.patches);
        let (de_mean, de_std) = colour_differences(&lab_r, &lab_c);
        Ok(Metrics {
            ring_ncc: ring_ncc(&reference, &candidate, &self.ring),
            orient: orientation_agreement(&reference, &candidate),
            swd: swd(PatchChannels::All),
            swd_l: swd(PatchChannels::Lightness),
            swd_chroma: swd(PatchChannels::Chroma),
            de_mean,
            de_std,
            style: self.style(&self.style_reference(&reference)?, &candidate)?,
            aniso: pore_anisotropy(&candidate),
            aniso_ref: pore_anisotropy(&reference),
            speckle: speckle(&candidate),
            speckle_ref: speckle(&reference),
        })
    }

    /// The style statistics of `reference`, computed once for many [`Self::style`] calls
    /// (a search scoring many candidates against the same photo).
    pub fn style_reference(&self, reference: &Image2) -> Result<StyleReference> {
        let image = reference.with_channels(3);
        let targets = self.style.targets(std::slice::from_ref(&image))?;
        Ok(StyleReference { image, targets })
    }

    /// The style loss of `candidate` against a prepared reference alone (the `style` of
    /// [`Self::compare`]).
    pub fn style(&self, reference: &StyleReference, candidate: &Image2) -> Result<f32> {
        let candidate = match_size(&reference.image, candidate)?;
        self.style_loss(&reference.targets, &candidate)
    }

    fn style_loss(&self, targets: &StyleTargets, candidate: &Image2) -> Result<f32> {
        let generated = image_to_tensor(candidate, &self.device);
        Ok(self
            .style
            .loss(&[generated], targets, &[0])?
            .into_scalar::<f32>())
    }
}

/// A reference image with its style statistics ([`Comparer::style_reference`]).
pub struct StyleReference {
    image: Image2,
    targets: StyleTargets,
}

/// All metrics with the default settings and loss on the flex device.
pub fn compare(reference: &Image2, candidate: &Image2) -> Result<Metrics> {
    Comparer::new(&LossConfig::default_config(), &Device::flex()).compare(reference, candidate)
}

/// The candidate as RGB at the reference's size (see the module note).
fn match_size(reference: &Image2, candidate: &Image2) -> Result<Image2> {
    let candidate = candidate.with_channels(3);
    if (candidate.width, candidate.height) == (reference.width, reference.height) {
        return Ok(candidate);
    }
    let ra = reference.width as f64 / reference.height as f64;
    let ca = candidate.width as f64 / candidate.height as f64;
    if (ra / ca - 1.0).abs() > 0.01 {
        return Err(XylemError::input(
            "compare",
            format!(
                "the reference is {}x{} and the candidate {}x{}: expected the same aspect ratio (the candidate is resized to the reference's size, never stretched)",
                reference.width, reference.height, candidate.width, candidate.height
            ),
        ));
    }
    Ok(candidate.resized(reference.width, reference.height))
}
