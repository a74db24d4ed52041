//! Settings of the guided local loss ([`super::guided::GuidedLoss`]): `[loss.guided]` in an
//! NCA training config. The features themselves (pyramid, filters, projections per layer,
//! the swd and colour weights) come from the style-loss config beside it.

use serde::{Deserialize, Serialize};

use crate::config::Checker;
use crate::error::Result;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GuidedConfig {
    /// Pixels of the photo around a generated patch that its statistics are compared with
    /// (the window is the patch grown by this much on every side, clipped to the face).
    pub margin: usize,
    /// Weight of the guide channels (ring phase) in the joint distribution, relative to the
    /// spread of an average feature; 0 compares plain local statistics.
    pub guide_weight: f32,
    /// The guide's weight instead of `guide_weight` when the training's photos show no
    /// vessels (the vessel gate, `nca::train::vessel_gate`, took the grain noise out). Why
    /// two weights: the guide is what places pores at the earlywood phases, and a strong one
    /// draws the photos' pore bands on ring-porous wood; wood without vessels has no pores
    /// to place, and there a strong guide only pulls the rule toward ring-locked states
    /// (DESIGN "NCA study", variant gw4v). Unset: `guide_weight` for every wood.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guide_weight_without_vessels: Option<f32>,
    /// Weight of the pixel-scale energy term (`super::fine_energy`): the patch's
    /// neighbour-difference and checkerboard energies against the window's. 0 (default)
    /// leaves it out and computes nothing for it.
    pub fine_weight: f32,
    /// Weight of the ring-profile term (`super::ring_profile`): the patch's mean colour in
    /// each of 8 ring-phase bins against the window's. 0 (default) leaves it out and computes
    /// nothing for it.
    pub profile_weight: f32,
    /// Which colour axes the ring-profile term compares (`all`, the default, or
    /// `lightness`).
    pub profile_axes: ProfileAxes,
}

/// The colour axes of the ring-profile term.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProfileAxes {
    /// The colour term's axes (R, G, B, luminance, two opponent axes), each scaled by the
    /// window's spread along it.
    #[default]
    All,
    /// Luminance alone. Why offer it: each axis is scaled by the window's own spread, and
    /// wood varies little along the opponent axes, so there a small per-phase chroma
    /// difference costs as much as a large lightness one; a rule whose residual moves along
    /// one colour axis (`[model] colour_axes = 1`) may be unable to follow such a chroma
    /// profile and trade texture for it (measured: BENCHMARKS "The ring-profile term on
    /// lightness alone").
    Lightness,
}

impl Default for GuidedConfig {
    fn default() -> Self {
        Self {
            margin: 8,
            guide_weight: 2.0,
            guide_weight_without_vessels: None,
            fine_weight: 0.0,
            profile_weight: 0.0,
            profile_axes: ProfileAxes::All,
        }
    }
}

impl GuidedConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.count("margin", self.margin, 0, 4096, "pixels around a patch")?;
        check.range(
            "guide_weight",
            self.guide_weight,
            0.0,
            100.0,
            "weight of the guide channels",
        )?;
        if let Some(weight) = self.guide_weight_without_vessels {
            check.range(
                "guide_weight_without_vessels",
                weight,
                0.0,
                100.0,
                "weight of the guide channels for wood without vessels",
            )?;
        }
        check.range(
            "fine_weight",
            self.fine_weight,
            0.0,
            100.0,
            "weight of the pixel-scale energy term",
        )?;
        check.range(
            "profile_weight",
            self.profile_weight,
            0.0,
            100.0,
            "weight of the ring-profile term",
        )?;
        if self.profile_axes != ProfileAxes::All && self.profile_weight == 0.0 {
            return Err(check.error(
                "profile_axes",
                "chooses the ring-profile term's axes, which is off (profile_weight = 0); \
                 set profile_weight > 0 or leave profile_axes out",
            ));
        }
        Ok(())
    }
}
