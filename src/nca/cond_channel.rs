//! The kinds of conditioning input a model perceives (`model.conditioning` in the config),
//! with their channel counts; what each one carries is computed in `conditioning.rs`.

use serde::{Deserialize, Serialize};

/// One kind of conditioning input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CondChannel {
    /// Lightness of white-balanced B, minus 0.5 (1 channel).
    GreyB,
    /// White-balanced B minus 0.5 (3 channels).
    RgbB,
    /// G normalised to [0, 1] over the cube, minus 0.5 (1 channel).
    G,
    /// 0.5 cos(2 pi G), 0.5 sin(2 pi G) (2 channels).
    RingPhase,
    /// Half of the grain-aligned noise (`grain_noise.rs`, 1 channel): tubes along the fibres.
    GrainNoise,
    /// Half of the ray noise (`ray_noise.rs`, 1 channel): plates across the rings.
    RayNoise,
}

impl CondChannel {
    /// Number of tensor channels.
    pub fn width(self) -> usize {
        match self {
            CondChannel::GreyB
            | CondChannel::G
            | CondChannel::GrainNoise
            | CondChannel::RayNoise => 1,
            CondChannel::RgbB => 3,
            CondChannel::RingPhase => 2,
        }
    }
}
