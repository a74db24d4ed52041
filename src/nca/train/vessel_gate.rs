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
use crate::nca::config::ModelSpec;

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
