//! How a synthetic sample is photographed (issue 14): the wood's colour as a camera sees it
//! on a cut surface. Real end grain photographs darker than side grain (CN03's end faces
//! are about 0.84 of its side faces in every channel; DESIGN "Grain shading"), which the
//! point-wise species model knows nothing of. A synthetic sample made with
//! `end_grain < 1` carries that effect with a known factor in its faces *and* in its hidden
//! truth cuts, so the fit's grain shading and the colour of interior cuts can be checked
//! against it.
//!
//! Model: a surface with unit normal n shows the wood's colour times
//! 1 + (end_grain - 1) w, w = (n . t)^2, t the species' fibre axis
//! (`PithConfig::fibre_axis`): the form `field::GrainShading` fits, so the fit can recover
//! it exactly. Points (volumes, `eval`) keep the plain wood colour.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::config::{Checker, ConfigFile};
use crate::error::Result;
use crate::field::{GrainShaded, GrainShading};
use crate::texture::SolidTexture;

/// The photographing step of `xylem sample` (written to `truth/photograph.toml`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Photograph {
    /// Colour of end grain relative to side grain, per channel (1: no difference).
    pub end_grain: f32,
}

impl Default for Photograph {
    fn default() -> Self {
        Self { end_grain: 1.0 }
    }
}

/// Accepted end-grain factors: darker end grain is what photos show; up to 1.5 allows a
/// lighter one (lighting), beyond which colours would clip.
const END_GRAIN_RANGE: [f32; 2] = [0.25, 1.5];

impl ConfigFile for Photograph {
    fn validate(&self, check: &Checker) -> Result<()> {
        let [lo, hi] = END_GRAIN_RANGE;
        if !(lo..=hi).contains(&self.end_grain) {
            return Err(check.error(
                "end_grain",
                format!("= {}: expected a number in [{lo}, {hi}]", self.end_grain),
            ));
        }
        Ok(())
    }
}

/// A colour texture (RGB first) seen through `photograph`, with fibres along `fibre`:
/// surfaces get the factor of their normal, points stay plain. The photograph is a grain
/// shading with side grain 1 and end grain `end_grain` about a white balance of 1.
pub fn photographed<T: SolidTexture>(
    inner: T,
    photograph: &Photograph,
    fibre: Vec3,
) -> GrainShaded<T> {
    let shading = GrainShading {
        fibre: fibre.normalize_or_zero().into(),
        side: [1.0; 3],
        end: [photograph.end_grain; 3],
        t_statistic: f32::INFINITY,
    };
    GrainShaded::with_shading(inner, shading, [1.0; 3])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{Face, Plane};
    use crate::slice::slice_plane;
    use crate::volume::Volume;

    #[test]
    fn end_grain_gets_the_factor_side_grain_none_and_points_stay_plain() {
        let grey = Volume::from_data([4, 4, 4], 3, vec![0.5; 4 * 4 * 4 * 3]).unwrap();
        let seen = photographed(&grey, &Photograph { end_grain: 0.8 }, Vec3::Y);
        assert_eq!(seen.eval_vec(Vec3::ZERO), vec![0.5; 3]);
        let mean = |plane: &Plane| {
            let img = slice_plane(&seen, plane, 4, 4);
            img.data.iter().sum::<f32>() / img.data.len() as f32
        };
        assert!((mean(&Plane::face(Face::B)) - 0.4).abs() < 1e-6);
        assert!((mean(&Plane::face(Face::A)) - 0.5).abs() < 1e-6);
        // A plane at 60 degrees to the fibres' cross-section: w = cos^2(60) = 1/4.
        let tilted = Plane {
            origin: Vec3::new(-0.5, -0.5, -0.5),
            u: Vec3::X,
            v: Vec3::new(0.0, 0.75f32.sqrt(), 0.5),
        };
        let want = 0.5 * (1.0 - 0.2 * 0.25);
        assert!((mean(&tilted) - want).abs() < 1e-5, "{}", mean(&tilted));
    }

    #[test]
    fn an_end_grain_factor_out_of_range_is_refused_with_its_key() {
        let err = Photograph::parse("end_grain = 0.1", std::path::Path::new("p.toml"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("p.toml") && err.contains("end_grain"), "{err}");
    }
}
