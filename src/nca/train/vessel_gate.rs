//! Whether a training gets the grain noise at all: only wood whose photos show vessels.
//!
//! Why: the grain noise (`nca::grain_noise`) is vessel noise, tubes along the fibres that the
//! rule thresholds into pore dashes. Softwoods have no vessels. Trained on hinoki (H11) with
//! the noise, the quality NCA covered held-out faces with pink and violet dashes (H11 A:
//! style 1.58 against the base colour's 0.78); the same config without the channel drew no
//! dashes (style 0.45; BENCHMARKS, "Grain noise on a softwood"). The rule cannot learn to
//! ignore the channel on side grain alone: the noise that makes dots on end grain makes
//! dashes on side grain.

use crate::image2::Image2;
use crate::metrics::vessels::vessel_fraction;
use crate::nca::cond_channel::CondChannel;
use crate::nca::config::{ModelSpec, TrainConfig};

/// What the vessel gate changed in a training config (`None` from [`apply_vessel_gate`]: nothing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateClosed {
    /// The photos' mean vessel fraction, below `model.grain_noise.min_vessel_fraction`.
    pub vessel_fraction: f32,
    /// The guide weight now in force, when `[loss.guided] guide_weight_without_vessels`
    /// replaced `guide_weight`.
    pub guide_weight: Option<f32>,
}

/// The photos' mean vessel fraction (`metrics::vessels`). Measured, mean of six faces:
/// CN03 7.7 %, H11 1.2 %; synthetic samples at 256 px: chestnut 7.5 %, oak 5.4 %, softwood
/// 0.6 % (its dark latewood lines are not vessels).
fn photos_vessel_fraction(photos: &[&Image2]) -> f32 {
    let (sum, n) = photos.iter().fold((0.0f64, 0usize), |(s, n), p| {
        (s + f64::from(vessel_fraction(p)), n + 1)
    });
    if n == 0 { 0.0 } else { (sum / n as f64) as f32 }
}

/// Takes `grain_noise` out of `model`'s conditioning when the photos' vessel fraction is below
/// `model.grain_noise.min_vessel_fraction`; returns that fraction when it did.
pub fn leave_out_grain_noise_without_vessels(
    model: &mut ModelSpec,
    photos: &[&Image2],
) -> Option<f32> {
    if !model.conditioning.contains(&CondChannel::GrainNoise) {
        return None;
    }
    let fraction = photos_vessel_fraction(photos);
    if fraction >= model.grain_noise.min_vessel_fraction {
        return None;
    }
    model.conditioning.retain(|c| *c != CondChannel::GrainNoise);
    Some(fraction)
}

/// The whole gate on a training config: without vessels the grain noise is left out (see
/// [`leave_out_grain_noise_without_vessels`]) and the guided loss takes
/// `guide_weight_without_vessels` when the config sets it.
pub fn apply_vessel_gate(config: &mut TrainConfig, photos: &[&Image2]) -> Option<GateClosed> {
    let vessel_fraction = leave_out_grain_noise_without_vessels(&mut config.model, photos)?;
    let guided = &mut config.loss.guided;
    let guide_weight = guided.guide_weight_without_vessels.inspect(|&w| {
        guided.guide_weight = w;
    });
    Some(GateClosed {
        vessel_fraction,
        guide_weight,
    })
}
