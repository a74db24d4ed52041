//! Grain-aligned noise: a fixed random input of the NCA, stretched along the fibres.
//!
//! Why: the NCA's only source of randomness used to be its seed state, white noise, and a
//! rule of 3x3x3 perception grown for 8-16 steps turned it into round dots everywhere (the
//! NCA study: pore anisotropy 0.30 on the synthetic cut2, truth 0.72). Vessels are long tubes
//! along the fibres, so on side grain they show as dashes and on end grain as dots. This
//! channel gives every voxel a value of smooth value noise whose cells are `along_mm` long
//! along the fibre axis and `across_mm` wide across it: thresholding it (at a level the rule
//! may tie to the ring phase) gives tubes, which every cut shows with the right shape. Being
//! an input, not part of the state, it cannot drift during long unrolls.
//!
//! The fibre axis is one direction for the cube: the one `xylem fit` measured on the photos'
//! pores and fibre streaks (`fit::fibre_direction`), else the fitted pith direction. The
//! deflection around knots is left to the rule, which also sees B and G. The noise is a function of the
//! global position and a key, so a training crop sees the same part of the pattern as the
//! whole volume would, and the key (the config's seed in training, the synthesis seed in
//! synthesis) makes each synthesis a new realisation of the same statistics.

use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::config::Checker;
use crate::error::Result;
use crate::frame::CM_PER_UNIT;
use crate::procedural::noise::value3;
use crate::rng::mix64;
use crate::texture::{SolidTexture, first_channel};

/// Cell sizes of the grain noise (`[model.grain_noise]`), used when the conditioning lists
/// `grain_noise`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GrainNoiseSpec {
    /// Lattice spacing across the fibres in millimetres (about a pore's width).
    pub across_mm: f32,
    /// Lattice spacing along the fibres in millimetres (about a pore dash's length).
    pub along_mm: f32,
    /// Lattice spacing across the rings in millimetres, when it differs from `across_mm`
    /// (needs `follow_rings`, the only case where "across the rings" is a direction of the
    /// noise). Why: on a radial face a ring-porous wood's earlywood vessels merge into one
    /// bold line per ring; round cells 0.3 mm wide put two or three thin tubes across the
    /// earlywood band, drawn as several fine dashed lines (BENCHMARKS "Longer and wider
    /// grain-noise cells"). `None` (the default): `across_mm`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radial_mm: Option<f32>,
    /// Training leaves the channel out when fewer of the training photos' pixels than this
    /// lie in vessels (`metrics::vessels`): wood without vessels (softwoods) gets no vessel
    /// noise to draw (`nca::train::vessel_gate`). 0 (the default) keeps it always;
    /// `quality.toml` sets 0.03, measured on hinoki at that scale (BENCHMARKS, "Grain noise
    /// on a softwood"); the quick config on hinoki drew no dashes with the noise and keeps it.
    pub min_vessel_fraction: f32,
    /// Lay the tubes in the ring surfaces: the noise's coordinate across the rings is the
    /// growth field G itself (converted to length by G's mean gradient), so a tube follows
    /// its ring wherever the ring bends, as fibres do; the other two coordinates are the
    /// fibre axis projected into the cube's mean ring surface and the direction across it
    /// within that surface. `false` (the first version): straight tubes along one axis,
    /// which cross the rings wherever they lean away from it (CN03 held-out E: slanted
    /// streaks over upright rings). Falls back to straight tubes when the cube's rings have
    /// no mean direction (pith inside the cube).
    pub follow_rings: bool,
    /// The cells the noise takes instead when the vessel gate closes (`[model.grain_noise.
    /// without_vessels]`): thin fibre lines, not vessel dashes, on wood whose photos show
    /// no vessels. `None` (the default): the gate leaves the channel out.
    pub without_vessels: Option<FibreCells>,
}

/// Cells of the grain noise on wood without vessels: fibre lines (`[model.grain_noise.
/// without_vessels]`). Why: hinoki's side faces carry fine lines along the fibres, which a
/// model without the channel does not draw (H11 A held out: anisotropy .30 against the
/// photo's .46; with these cells .53 and .45 over two seeds). Off in the shipped configs:
/// with 0.2 x 6 mm cells the synthetic softwood's 90-step volume ran away (blobs at the
/// colour bounds) and H11 D and F held out lost bars; with 0.2 x 3 mm cells the softwood
/// stayed clean but H11 C and E held out lost their ring orientation bar (24 bars of 36
/// against 25 without the channel; BENCHMARKS "Fibre noise on wood without vessels").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FibreCells {
    /// Lattice spacing across the fibres in millimetres (a line's width).
    pub across_mm: f32,
    /// Lattice spacing along the fibres in millimetres (a line's length).
    pub along_mm: f32,
}

impl Default for GrainNoiseSpec {
    fn default() -> Self {
        // Chestnut's earlywood vessels photographed at 0.16 mm per pixel: dashes 1-3 px wide
        // and 6-12 px long on side grain.
        Self {
            across_mm: 0.3,
            along_mm: 1.5,
            radial_mm: None,
            min_vessel_fraction: 0.0,
            follow_rings: false,
            without_vessels: None,
        }
    }
}

impl GrainNoiseSpec {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range("across_mm", self.across_mm, 0.01, 100.0, "millimetres")?;
        check.range("along_mm", self.along_mm, 0.01, 100.0, "millimetres")?;
        if let Some(radial) = self.radial_mm {
            check.range("radial_mm", radial, 0.01, 100.0, "millimetres")?;
            if !self.follow_rings {
                return Err(check.error(
                    "radial_mm",
                    "is set but follow_rings = false gives the noise no direction across the \
                     rings: expected follow_rings = true or no radial_mm",
                ));
            }
        }
        let share = self.min_vessel_fraction;
        check.range("min_vessel_fraction", share, 0.0, 1.0, "a share")?;
        if let Some(fibres) = &self.without_vessels {
            // The gate never closes at threshold 0: the table would be read and ignored.
            if share <= 0.0 {
                return Err(check.error(
                    "without_vessels",
                    "is set but min_vessel_fraction = 0 never closes the vessel gate: \
                     expected min_vessel_fraction > 0 (e.g. 0.03) or no without_vessels table",
                ));
            }
            let check = check.nested("without_vessels");
            check.range("across_mm", fibres.across_mm, 0.01, 100.0, "millimetres")?;
            check.range("along_mm", fibres.along_mm, 0.01, 100.0, "millimetres")?;
        }
        Ok(())
    }

    /// The spec for wood without vessels: the fibre cells when `without_vessels` sets
    /// them (and nothing left to gate), else `None`.
    pub fn for_wood_without_vessels(&self) -> Option<GrainNoiseSpec> {
        let fibres = self.without_vessels?;
        Some(GrainNoiseSpec {
            across_mm: fibres.across_mm,
            along_mm: fibres.along_mm,
            radial_mm: None,
            min_vessel_fraction: 0.0,
            follow_rings: self.follow_rings,
            without_vessels: None,
        })
    }
}

/// The factor on the cell sizes when a model trained on a `training_grid`^3 grid fills a
/// `grid`^3 volume. The rule learnt its texture per voxel (DESIGN: a synthesis at another size
/// keeps the texture's size in voxels), so the noise keeps its cells' size in voxels too:
/// twice the grid, half the cells in millimetres. Training itself uses 1.
pub fn cell_scale(training_grid: usize, grid: usize) -> f32 {
    training_grid as f32 / grid.max(1) as f32
}

/// Stream that separates the noise's key from every other use of the same seed.
const GRAIN_STREAM: u64 = 0x6752_4149_4E5F_4E5A;

/// Value noise in [-1, 1], stretched along `axis` (1 channel).
#[derive(Clone)]
pub struct GrainNoise {
    /// Rows: the two directions across the fibres and the fibre axis, each divided by its
    /// lattice spacing in cube units, so `frame * p` is the lattice coordinate. With
    /// `rings`, row 1 is unused: G takes its place.
    frame: [Vec3; 3],
    key: u64,
    /// G and the factor from G to lattice cells across the rings (`follow_rings`).
    rings: Option<(Arc<dyn SolidTexture>, f32)>,
}

/// Side of the grid on which G's mean gradient is measured.
const GRADIENT_GRID: usize = 8;
/// The mean gradient direction must be at least this share of the mean gradient length,
/// else the rings have no mean direction in the cube and the tubes stay straight.
const MIN_GRADIENT_COHERENCE: f32 = 0.5;

/// Lattice spacings of a fibre-aligned noise in cube units: around the stem within the ring
/// surface, across the rings (radial) and along the fibres.
#[derive(Clone, Copy, Debug)]
pub struct NoiseCells {
    pub tangential: f32,
    pub radial: f32,
    pub along: f32,
}

impl NoiseCells {
    /// Spacings given in millimetres, multiplied by `cell_scale` (see [`cell_scale`]).
    pub fn from_mm(tangential: f32, radial: f32, along: f32, cell_scale: f32) -> Self {
        let unit = |mm: f32| cell_scale * mm / (CM_PER_UNIT * 10.0);
        Self {
            tangential: unit(tangential),
            radial: unit(radial),
            along: unit(along),
        }
    }
}

impl GrainNoiseSpec {
    /// The vessel tubes' cells in the rings: round across the fibres unless `radial_mm`
    /// widens them across the rings.
    fn cells(&self, cell_scale: f32) -> NoiseCells {
        let radial = self.radial_mm.unwrap_or(self.across_mm);
        NoiseCells::from_mm(self.across_mm, radial, self.along_mm, cell_scale)
    }

    /// The cells of straight tubes, always round: straight noise has no direction across
    /// the rings for `radial_mm` to widen.
    fn straight_cells(&self, cell_scale: f32) -> NoiseCells {
        NoiseCells::from_mm(self.across_mm, self.across_mm, self.along_mm, cell_scale)
    }
}

impl GrainNoise {
    /// Noise with cells of `spec` along the unit `axis` (cube frame), realisation `seed`,
    /// the cells multiplied by `cell_scale` (see [`cell_scale`]).
    pub fn new(spec: &GrainNoiseSpec, axis: Vec3, seed: u64, cell_scale: f32) -> Self {
        Self::straight(
            spec.straight_cells(cell_scale),
            axis,
            mix64(seed ^ GRAIN_STREAM),
        )
    }

    /// As [`GrainNoise::new`], with the tubes laid in the iso-surfaces of `growth` (see
    /// [`GrainNoiseSpec::follow_rings`]); straight tubes when G has no mean direction.
    pub fn following_rings(
        spec: &GrainNoiseSpec,
        axis: Vec3,
        growth: Arc<dyn SolidTexture>,
        seed: u64,
        cell_scale: f32,
    ) -> Self {
        let key = mix64(seed ^ GRAIN_STREAM);
        let straight = spec.straight_cells(cell_scale);
        Self::in_rings(spec.cells(cell_scale), straight, axis, growth, key)
    }

    /// Noise of lattice `cells` around the unit `axis`, keyed by `key`; across the axis an
    /// arbitrary orthonormal pair takes the tangential and the radial spacing.
    pub(crate) fn straight(cells: NoiseCells, axis: Vec3, key: u64) -> Self {
        let t = axis.normalize_or(Vec3::Y);
        let e1 = t.any_orthonormal_vector();
        let e2 = t.cross(e1);
        Self {
            frame: [e1 / cells.tangential, e2 / cells.radial, t / cells.along],
            key,
            rings: None,
        }
    }

    /// Noise of lattice `cells` whose radial coordinate is G itself and whose other two lie
    /// in the cube's mean ring surface (see [`GrainNoiseSpec::follow_rings`]); as
    /// [`Self::straight`] with `straight_cells` when G has no mean direction or the fibres
    /// cross the rings (straight noise has no direction across the rings: its "radial"
    /// spacing lies along an arbitrary direction across the axis).
    pub(crate) fn in_rings(
        cells: NoiseCells,
        straight_cells: NoiseCells,
        axis: Vec3,
        growth: Arc<dyn SolidTexture>,
        key: u64,
    ) -> Self {
        let mut noise = Self::straight(straight_cells, axis, key);
        let Some((normal, g_per_unit)) = mean_gradient(growth.as_ref()) else {
            return noise;
        };
        let t = axis.normalize_or(Vec3::Y);
        let in_surface = (t - normal * t.dot(normal)).normalize_or_zero();
        if in_surface == Vec3::ZERO {
            return noise; // fibres along the ring normal: no surface direction to follow
        }
        let across_in_surface = in_surface.cross(normal);
        noise.frame = [
            across_in_surface / cells.tangential,
            Vec3::ZERO,
            in_surface / cells.along,
        ];
        noise.rings = Some((growth, 1.0 / (g_per_unit * cells.radial)));
        noise
    }

    /// The noise at a point of the cube.
    pub fn value(&self, p: Vec3) -> f32 {
        let across_rings = match &self.rings {
            Some((growth, cells_per_year)) => first_channel(growth.as_ref(), p) * cells_per_year,
            None => self.frame[1].dot(p),
        };
        let q = Vec3::new(self.frame[0].dot(p), across_rings, self.frame[2].dot(p));
        value3(self.key, q)
    }
}

/// The unit mean gradient of `growth` over the cube and the mean gradient length (G per cube
/// unit), by central differences on an 8^3 grid; `None` when the gradients do not share a
/// direction (see [`MIN_GRADIENT_COHERENCE`]) or G is flat.
fn mean_gradient(growth: &dyn SolidTexture) -> Option<(Vec3, f32)> {
    let h = 0.5 / GRADIENT_GRID as f32;
    let g = |p: Vec3| first_channel(growth, p);
    let at = |i: usize| (i as f32 + 0.5) / GRADIENT_GRID as f32 - 0.5;
    let (mut sum, mut length, mut n) = (Vec3::ZERO, 0.0f32, 0.0f32);
    for i in 0..GRADIENT_GRID {
        for j in 0..GRADIENT_GRID {
            for k in 0..GRADIENT_GRID {
                let p = Vec3::new(at(i), at(j), at(k));
                let d = |e: Vec3| (g(p + e * h) - g(p - e * h)) / (2.0 * h);
                let grad = Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z));
                if grad.is_finite() {
                    sum += grad;
                    length += grad.length();
                    n += 1.0;
                }
            }
        }
    }
    if n == 0.0 || length <= 0.0 {
        return None;
    }
    let coherent = sum.length() >= MIN_GRADIENT_COHERENCE * length;
    coherent.then(|| (sum.normalize(), length / n))
}

impl SolidTexture for GrainNoise {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[0] = self.value(p);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Mean absolute change of the noise over a `step` from 2000 random points.
    pub(crate) fn mean_change(noise: &GrainNoise, step: Vec3) -> f32 {
        let mut rng = crate::rng::Rng::new(3);
        let n = 2000;
        let mut sum = 0.0;
        for _ in 0..n {
            let p = Vec3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            );
            sum += (noise.value(p + step) - noise.value(p)).abs();
        }
        sum / n as f32
    }

    #[test]
    fn noise_varies_slower_along_the_axis_than_across() {
        let axis = Vec3::new(0.3, 1.0, 0.1).normalize();
        let noise = GrainNoise::new(&GrainNoiseSpec::default(), axis, 7, 1.0);
        let step = 0.3 / (CM_PER_UNIT * 10.0); // one cell across
        let across = mean_change(&noise, axis.any_orthonormal_vector() * step);
        let along = mean_change(&noise, axis * step);
        assert!(across > 3.0 * along, "across {across}, along {along}");
    }

    /// The noise on a face at 256 px, thresholded into dark pores on pale wood (RGB).
    fn pores_on(noise: &GrainNoise, face: crate::frame::Face) -> crate::image2::Image2 {
        let mut img = crate::slice::slice_face(noise, face, 256).with_channels(3);
        for v in img.data.iter_mut() {
            *v = if *v > 0.4 { 0.3 } else { 0.8 };
        }
        img
    }

    /// What the channel is for: its tubes along the axis read as dashes on side grain and as
    /// dots on end grain, measured with the metric of issue 12.
    #[test]
    fn thresholded_noise_is_dashes_on_side_grain_and_dots_on_end_grain() {
        use crate::frame::Face;
        use crate::metrics::anisotropy::pore_anisotropy;
        let noise = GrainNoise::new(&GrainNoiseSpec::default(), Vec3::Y, 5, 1.0);
        let side = pore_anisotropy(&pores_on(&noise, Face::A));
        let end = pore_anisotropy(&pores_on(&noise, Face::B));
        eprintln!("aniso: side grain {side}, end grain {end}");
        assert!(
            side > 0.6 && end < 0.35,
            "side grain {side}, end grain {end}"
        );
    }

    /// A volume twice the training grid sees the pattern at half the size in cube units, so
    /// the same in voxels: the value at p equals the value at 2 p of the training noise.
    #[test]
    fn a_larger_grid_keeps_the_cells_size_in_voxels() {
        let spec = GrainNoiseSpec::default();
        let trained = GrainNoise::new(&spec, Vec3::Y, 3, cell_scale(128, 128));
        let doubled = GrainNoise::new(&spec, Vec3::Y, 3, cell_scale(128, 256));
        for p in [Vec3::new(0.1, 0.2, -0.15), Vec3::new(-0.2, 0.05, 0.1)] {
            let (a, b) = (doubled.value(p), trained.value(2.0 * p));
            assert!((a - b).abs() < 1e-4, "{a} vs {b}");
        }
    }

    #[test]
    fn seeds_give_different_realisations_and_the_same_seed_the_same() {
        let spec = GrainNoiseSpec::default();
        let a = GrainNoise::new(&spec, Vec3::Y, 1, 1.0);
        let b = GrainNoise::new(&spec, Vec3::Y, 2, 1.0);
        let p = Vec3::new(0.11, -0.2, 0.3);
        assert_eq!(a.value(p), GrainNoise::new(&spec, Vec3::Y, 1, 1.0).value(p));
        let differ = (0..50)
            .map(|i| p + Vec3::X * (i as f32 * 0.013))
            .filter(|&q| a.value(q) != b.value(q))
            .count();
        assert!(differ > 40);
    }

    /// Rings as parallel planes of normal `normal`, `rings_per_unit` of them per cube unit.
    struct PlaneRings {
        normal: Vec3,
        rings_per_unit: f32,
    }

    impl SolidTexture for PlaneRings {
        fn channels(&self) -> usize {
            1
        }
        fn eval(&self, p: Vec3, out: &mut [f32]) {
            out[0] = self.rings_per_unit * self.normal.dot(p);
        }
    }

    /// The fibre axis crosses tilted rings by 17 degrees; following the rings, the tubes run
    /// in the ring planes: the noise changes little along the axis projected into them and
    /// the straight noise does not.
    #[test]
    fn tubes_that_follow_the_rings_lie_in_the_ring_surfaces() {
        let normal = Vec3::new(0.3, 0.0, 1.0).normalize();
        let rings: Arc<dyn SolidTexture> = Arc::new(PlaneRings {
            normal,
            rings_per_unit: 12.0,
        });
        let axis = Vec3::Y;
        let tilted = (axis + 0.3 * Vec3::Z).normalize(); // 17 degrees out of the ring plane
        let spec = GrainNoiseSpec::default();
        let following = GrainNoise::following_rings(&spec, tilted, rings, 4, 1.0);
        let straight = GrainNoise::new(&spec, tilted, 4, 1.0);
        let in_plane = (tilted - normal * tilted.dot(normal)).normalize();
        let cell = 0.3 / (CM_PER_UNIT * 10.0);
        let along = |n: &GrainNoise, dir: Vec3| mean_change(n, dir * cell);
        let across = mean_change(&following, normal * cell);
        let following_along = along(&following, in_plane);
        let straight_along = along(&straight, in_plane);
        eprintln!("across {across}, along: following {following_along}, straight {straight_along}");
        assert!(
            across > 2.0 * following_along,
            "across {across}, along {following_along}"
        );
        assert!(
            straight_along > 1.5 * following_along,
            "straight {straight_along}, following {following_along}"
        );
    }

    /// `radial_mm` widens the cells across the rings alone: the noise changes less over
    /// a step across the rings and about as much over a step around the stem.
    #[test]
    fn radial_cells_widen_the_tubes_across_the_rings_only() {
        let normal = Vec3::Z;
        let rings: Arc<dyn SolidTexture> = Arc::new(PlaneRings {
            normal,
            rings_per_unit: 12.0,
        });
        let round = GrainNoiseSpec {
            follow_rings: true,
            ..GrainNoiseSpec::default()
        };
        let wide = GrainNoiseSpec {
            radial_mm: Some(3.0 * round.across_mm),
            ..round.clone()
        };
        let noise = |spec: &GrainNoiseSpec| {
            GrainNoise::following_rings(spec, Vec3::Y, rings.clone(), 6, 1.0)
        };
        let (round, wide) = (noise(&round), noise(&wide));
        let step = 0.3 / (CM_PER_UNIT * 10.0);
        let radial = |n: &GrainNoise| mean_change(n, normal * step);
        let around = |n: &GrainNoise| mean_change(n, Vec3::X * step);
        eprintln!(
            "radial: round {}, wide {}; around: round {}, wide {}",
            radial(&round),
            radial(&wide),
            around(&round),
            around(&wide)
        );
        assert!(radial(&round) > 2.0 * radial(&wide));
        // other lattice points, the same statistics around the stem
        assert!((around(&round) / around(&wide) - 1.0).abs() < 0.1);
    }

    #[test]
    fn radial_cells_are_refused_without_rings_to_follow() {
        let spec = GrainNoiseSpec {
            radial_mm: Some(0.8),
            ..GrainNoiseSpec::default()
        };
        let check = Checker::new(std::path::Path::new("nca.toml")).nested("model.grain_noise");
        let message = spec.validate(&check).unwrap_err().to_string();
        assert!(
            message.contains("nca.toml") && message.contains("model.grain_noise.radial_mm"),
            "{message}"
        );
    }

    /// Rings around a pith inside the cube have no mean direction: straight tubes.
    #[test]
    fn rings_around_an_inner_pith_keep_straight_tubes() {
        struct Around;
        impl SolidTexture for Around {
            fn channels(&self) -> usize {
                1
            }
            fn eval(&self, p: Vec3, out: &mut [f32]) {
                out[0] = 10.0 * (p.x * p.x + p.z * p.z).sqrt();
            }
        }
        let spec = GrainNoiseSpec::default();
        let following = GrainNoise::following_rings(&spec, Vec3::Y, Arc::new(Around), 2, 1.0);
        let straight = GrainNoise::new(&spec, Vec3::Y, 2, 1.0);
        let p = Vec3::new(0.1, -0.2, 0.3);
        assert_eq!(following.value(p), straight.value(p));
        // nor does `radial_mm` widen the straight tubes along an arbitrary direction
        let wide = GrainNoiseSpec {
            radial_mm: Some(0.9),
            follow_rings: true,
            ..spec
        };
        let wide = GrainNoise::following_rings(&wide, Vec3::Y, Arc::new(Around), 2, 1.0);
        assert_eq!(wide.value(p), straight.value(p));
    }
}
