//! Whether a training gets the grain noise at all: only wood whose photos show vessels.
//!
//! Why: the grain noise (`nca::grain_noise`) is vessel noise, tubes along the fibres that the
//! rule thresholds into pore dashes. Softwoods have no vessels. Trained on hinoki (H11) with
//! the noise, the quality NCA covered held-out faces with pink and violet dashes (H11 A:
//! style 1.58 against the base colour's 0.78); the same config without the channel drew no
//! dashes (style 0.45; BENCHMARKS, "Grain noise on a softwood"). The rule cannot learn to
//! ignore the channel on side grain alone: the noise that makes dots on end grain makes
//! dashes on side grain. A config may instead give such wood fibre lines
//! (`[model.grain_noise.without_vessels]`): the same channel with thin, long cells.

use crate::image2::Image2;
use crate::metrics::vessels::vessel_fraction;
use crate::nca::cond_channel::CondChannel;
use crate::nca::config::{ModelSpec, TrainConfig};

/// What the vessel gate changed in a training config (`None` from [`apply_vessel_gate`]: nothing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateClosed {
    /// The photos' mean vessel fraction, below `min_vessel_fraction`.
    pub vessel_fraction: f32,
    /// The threshold the fraction fell below (`model.grain_noise.min_vessel_fraction` as the
    /// config had it: the fibre cells replace the spec, this threshold with it).
    pub min_vessel_fraction: f32,
    /// The guide weight now in force, when `[loss.guided] guide_weight_without_vessels`
    /// replaced `guide_weight`.
    pub guide_weight: Option<f32>,
    /// The grain noise was kept with the fibre cells of `without_vessels` (else left out).
    pub fibre_lines: bool,
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

/// When the photos' vessel fraction is below `model.grain_noise.min_vessel_fraction`,
/// replaces the grain noise's cells by its fibre cells (`without_vessels`) or, without those,
/// takes `grain_noise` out of `model`'s conditioning; says what it did when the gate closed
/// (the guide weight is [`apply_vessel_gate`]'s part, `None` here).
pub fn gate_grain_noise(model: &mut ModelSpec, photos: &[&Image2]) -> Option<GateClosed> {
    if !model.conditioning.contains(&CondChannel::GrainNoise) {
        return None;
    }
    let vessel_fraction = photos_vessel_fraction(photos);
    let min_vessel_fraction = model.grain_noise.min_vessel_fraction;
    if vessel_fraction >= min_vessel_fraction {
        return None;
    }
    let fibres = model.grain_noise.for_wood_without_vessels();
    let fibre_lines = fibres.is_some();
    match fibres {
        Some(fibres) => model.grain_noise = fibres,
        None => model.conditioning.retain(|c| *c != CondChannel::GrainNoise),
    }
    Some(GateClosed {
        vessel_fraction,
        min_vessel_fraction,
        guide_weight: None,
        fibre_lines,
    })
}

/// The whole gate on a training config: without vessels the grain noise draws fibre lines
/// or is left out (see [`gate_grain_noise`]) and the guided loss takes
/// `guide_weight_without_vessels` when the config sets it.
pub fn apply_vessel_gate(config: &mut TrainConfig, photos: &[&Image2]) -> Option<GateClosed> {
    let closed = gate_grain_noise(&mut config.model, photos)?;
    let guided = &mut config.loss.guided;
    let guide_weight = guided.guide_weight_without_vessels.inspect(|&w| {
        guided.guide_weight = w;
    });
    Some(GateClosed {
        guide_weight,
        ..closed
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nca::grain_noise::FibreCells;

    /// A model that asks for the grain noise and gates it at 3 % vessels.
    fn gated_model(without_vessels: Option<FibreCells>) -> ModelSpec {
        let mut model = ModelSpec::default();
        if !model.conditioning.contains(&CondChannel::GrainNoise) {
            model.conditioning.push(CondChannel::GrainNoise);
        }
        model.grain_noise.min_vessel_fraction = 0.03;
        model.grain_noise.without_vessels = without_vessels;
        model
    }

    #[test]
    fn a_plain_photo_closes_the_gate_and_fibre_cells_replace_the_vessel_cells() {
        // An even grey photo has no vessels at all.
        let grey = Image2::filled(64, 64, 3, 0.6);
        let fibres = FibreCells {
            across_mm: 0.2,
            along_mm: 6.0,
        };
        let mut model = gated_model(Some(fibres));
        let closed = gate_grain_noise(&mut model, &[&grey]).expect("no vessels: gate closes");
        assert_eq!(
            (closed.vessel_fraction, closed.min_vessel_fraction),
            (0.0, 0.03)
        );
        assert!(closed.fibre_lines);
        assert!(model.conditioning.contains(&CondChannel::GrainNoise));
        let spec = &model.grain_noise;
        assert_eq!((spec.across_mm, spec.along_mm), (0.2, 6.0));
        // What train.toml records needs no gate again: nothing left to switch.
        assert_eq!(
            (spec.min_vessel_fraction, spec.without_vessels),
            (0.0, None)
        );

        let mut model = gated_model(None);
        let closed = gate_grain_noise(&mut model, &[&grey]).expect("no vessels: gate closes");
        assert!(!closed.fibre_lines);
        assert!(!model.conditioning.contains(&CondChannel::GrainNoise));
    }

    #[test]
    fn the_gate_stays_open_when_the_threshold_is_zero() {
        let grey = Image2::filled(64, 64, 3, 0.6);
        let mut model = gated_model(None);
        model.grain_noise.min_vessel_fraction = 0.0;
        let before = model.clone();
        assert_eq!(gate_grain_noise(&mut model, &[&grey]), None);
        assert_eq!(model, before);
    }
}
