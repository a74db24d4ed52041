//! Ray noise: a second fixed random input of the NCA, flat plates that run out across the
//! rings.
//!
//! Why: rays are ribbons of cells running radially, thin around the stem and a few
//! millimetres tall along the grain. Oak's broad rays are what a cut of oak shows besides its
//! pores: thin lines across the rings on end grain, spindles on tangential faces, broad flecks
//! on radial faces. The grain noise (`grain_noise.rs`) varies fastest across the fibres in
//! both directions, so thresholding it gives tubes, never plates, and the rule has nothing
//! from which to grow a line that crosses ten rings (the synthetic oak with quality.toml:
//! no rays on any face or cut). This channel is value noise whose cells are thin
//! tangentially, long radially and tall along the fibres, its radial coordinate the growth
//! field itself (as the grain noise's `follow_rings`), so a high threshold of it is a plate
//! that crosses the rings where they lie. Being an input, it cannot drift during unrolls.
//! Off in every shipped config: on the synthetic oak the rule drew only faint short streaks
//! from it (BENCHMARKS "Ray noise on the synthetic oak").
//!
//! The plates are laid in one frame for the cube (the mean ring surface, as the grain noise's):
//! right where the pith is far from the cube, as on most cut blocks; with the pith inside the
//! cube (rings without a mean direction) the plates keep one arbitrary orientation.

use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::grain_noise::{GrainNoise, NoiseCells};
use crate::config::Checker;
use crate::error::Result;
use crate::rng::mix64;
use crate::texture::SolidTexture;

/// Cell sizes of the ray noise (`[model.ray_noise]`), used when the conditioning lists
/// `ray_noise`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RayNoiseSpec {
    /// Lattice spacing around the stem in millimetres (about a ray's width).
    pub tangential_mm: f32,
    /// Lattice spacing across the rings in millimetres (about half a ray's radial length).
    pub radial_mm: f32,
    /// Lattice spacing along the fibres in millimetres (about half a ray's height).
    pub along_mm: f32,
}

impl Default for RayNoiseSpec {
    fn default() -> Self {
        // Oak's broad rays (configs/species/oak.toml): 0.45 mm wide, 24 mm long radially,
        // 8 mm tall; a value-noise blob above a high threshold spans about one cell.
        Self {
            tangential_mm: 0.45,
            radial_mm: 12.0,
            along_mm: 4.0,
        }
    }
}

impl RayNoiseSpec {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "tangential_mm",
            self.tangential_mm,
            0.01,
            100.0,
            "millimetres",
        )?;
        check.range("radial_mm", self.radial_mm, 0.01, 1000.0, "millimetres")?;
        check.range("along_mm", self.along_mm, 0.01, 1000.0, "millimetres")
    }

    /// The noise of realisation `seed` around the fibre `axis`, its radial coordinate G
    /// (`growth`), the cells multiplied by `cell_scale` (`grain_noise::cell_scale`).
    pub fn noise(
        &self,
        axis: Vec3,
        growth: Arc<dyn SolidTexture>,
        seed: u64,
        cell_scale: f32,
    ) -> GrainNoise {
        let cells = NoiseCells::from_mm(
            self.tangential_mm,
            self.radial_mm,
            self.along_mm,
            cell_scale,
        );
        GrainNoise::in_rings(cells, cells, axis, growth, mix64(seed ^ RAY_STREAM))
    }
}

/// Stream that separates the ray noise's key from the grain noise's and every other use of
/// the same seed.
const RAY_STREAM: u64 = 0x5241_595F_4E4F_4953;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::CM_PER_UNIT;
    use crate::nca::grain_noise::tests::mean_change;

    /// Rings as parallel planes normal to x, 10 per cube unit.
    struct PlaneRings;

    impl SolidTexture for PlaneRings {
        fn channels(&self) -> usize {
            1
        }
        fn eval(&self, p: Vec3, out: &mut [f32]) {
            out[0] = 10.0 * p.x;
        }
    }

    /// Mean absolute change of the noise over a step of `mm` along `dir`.
    fn change_over_mm(noise: &GrainNoise, dir: Vec3, mm: f32) -> f32 {
        mean_change(noise, dir * mm / (CM_PER_UNIT * 10.0))
    }

    /// Fibres along y, rings normal to x: the plates are thin along z (around the stem) and
    /// long along x (across the rings) and y.
    #[test]
    fn ray_noise_is_plates_across_the_rings() {
        let noise = RayNoiseSpec::default().noise(Vec3::Y, Arc::new(PlaneRings), 3, 1.0);
        let tangential = change_over_mm(&noise, Vec3::Z, 0.45);
        let radial = change_over_mm(&noise, Vec3::X, 0.45);
        let along = change_over_mm(&noise, Vec3::Y, 0.45);
        eprintln!("change over 0.45 mm: tangential {tangential}, radial {radial}, along {along}");
        assert!(
            tangential > 5.0 * radial,
            "tangential {tangential}, radial {radial}"
        );
        assert!(
            tangential > 3.0 * along,
            "tangential {tangential}, along {along}"
        );
        assert!(along > radial, "along {along}, radial {radial}");
    }

    /// The same seed gives the grain noise and the ray noise different realisations.
    #[test]
    fn ray_noise_is_not_the_grain_noise() {
        use super::super::grain_noise::GrainNoiseSpec;
        let rings: Arc<dyn SolidTexture> = Arc::new(PlaneRings);
        let spec = RayNoiseSpec {
            tangential_mm: 0.3,
            radial_mm: 0.3,
            along_mm: 1.5,
        };
        let rays = spec.noise(Vec3::Y, rings.clone(), 4, 1.0);
        let grain = GrainNoise::following_rings(&GrainNoiseSpec::default(), Vec3::Y, rings, 4, 1.0);
        let p = Vec3::new(0.12, -0.07, 0.2);
        let differ = (0..50)
            .map(|i| p + Vec3::Z * (i as f32 * 0.011))
            .filter(|&q| rays.value(q) != grain.value(q))
            .count();
        assert!(differ > 40, "{differ} of 50 differ");
    }
}
