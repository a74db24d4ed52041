//! Grain shading (issue 14): the photographed colour of wood depends on how the surface cuts
//! the fibres. End grain (surface across the fibres) looks darker than side grain because
//! cut vessels and fibre lumens trap light; CN03's end-grain photos average 155-164 in red
//! against 176-193 for its side-grain photos.
//!
//! Model: the mean colour seen on a surface with unit normal n is
//! m(n) = side + (end - side) w, w = (n . t)^2, t the fibre direction
//! (`PithConfig::fibre_axis`): w is 0 on side grain, 1 on end grain, 1/3 on average over all
//! orientations. A solid texture whose colours are at the white balance of the whole sample
//! (the base colour's `Real(None)` and `Shown(None)`, the NCA's volume) is seen on that
//! surface multiplied per channel by m(n) / mean ([`GrainShading::factor`]). The fibre
//! direction is one vector for the cube: the deflection around knots is not modelled.
//!
//! The model is fitted from the faces' mean colours (`fit::grain_shading_fit`) and kept only
//! when the photos show it; otherwise the white balance has none and every surface gets the
//! plain mean, as before.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::config::Checker;
use crate::error::Result;

/// The fitted grain shading of a sample (stored in the fit's white balance).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrainShading {
    /// Unit fibre direction t (cube frame) the weights were computed with.
    pub fibre: [f32; 3],
    /// Mean real RGB of side grain (w = 0).
    pub side: [f32; 3],
    /// Mean real RGB of end grain (w = 1).
    pub end: [f32; 3],
    /// The evidence: slope of the faces' mean lightness over w divided by its standard error.
    pub t_statistic: f32,
}

/// Smallest mean colour a surface can get (the white balance's floor).
const MIN_MEAN: f32 = 1e-4;

impl GrainShading {
    /// End-grain weight w = (n . t)^2 of a surface with normal `normal` (need not be unit).
    pub fn weight(&self, normal: Vec3) -> f32 {
        let t = Vec3::from(self.fibre).normalize_or_zero();
        let n = normal.normalize_or_zero();
        let c = n.dot(t);
        c * c
    }

    /// Mean real RGB seen on a surface with normal `normal`.
    pub(crate) fn mean_colour(&self, normal: Vec3) -> [f32; 3] {
        let w = self.weight(normal);
        std::array::from_fn(|c| (self.side[c] + (self.end[c] - self.side[c]) * w).max(MIN_MEAN))
    }

    /// Per-channel factor from colour at the sample's white balance `mean` (the mean of the
    /// fitted faces' colours) to colour seen on a surface with normal `normal`.
    pub fn factor(&self, normal: Vec3, mean: [f32; 3]) -> [f32; 3] {
        let seen = self.mean_colour(normal);
        std::array::from_fn(|c| seen[c] / mean[c].max(MIN_MEAN))
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        let t = Vec3::from(self.fibre);
        if !t.is_finite() || (t.length() - 1.0).abs() > 1e-3 {
            return Err(check.error(
                "fibre",
                format!("= {:?}: expected a unit vector", self.fibre),
            ));
        }
        for (key, m) in [("side", self.side), ("end", self.end)] {
            if !m
                .iter()
                .all(|v| v.is_finite() && *v >= MIN_MEAN && *v <= 1.0)
            {
                return Err(check.error(
                    key,
                    format!("= {m:?}: expected a mean RGB colour with channels in [0.0001, 1]"),
                ));
            }
        }
        if !self.t_statistic.is_finite() {
            return Err(check.error("t_statistic", "must be a finite number"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shading() -> GrainShading {
        GrainShading {
            fibre: [0.0, 1.0, 0.0],
            side: [0.8, 0.6, 0.5],
            end: [0.6, 0.5, 0.45],
            t_statistic: -4.0,
        }
    }

    #[test]
    fn side_grain_gets_the_side_colour_and_end_grain_the_end_colour() {
        let s = shading();
        assert_eq!(s.mean_colour(Vec3::Z), s.side);
        assert_eq!(s.mean_colour(Vec3::NEG_Y), s.end);
        // 60 degrees from the fibres: w = cos^2(60) = 1/4.
        let n = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
        for (c, m) in s.mean_colour(n).into_iter().enumerate() {
            let want = s.side[c] + 0.25 * (s.end[c] - s.side[c]);
            assert!((m - want).abs() < 1e-6, "channel {c}: {m} vs {want}");
        }
    }

    #[test]
    fn factor_brings_the_sample_mean_to_the_surface_mean() {
        let s = shading();
        let mean = [0.7, 0.55, 0.48];
        let f = s.factor(Vec3::Y, mean);
        for c in 0..3 {
            assert!((mean[c] * f[c] - s.end[c]).abs() < 1e-6);
        }
    }
}
