//! The fit config (`configs/fit/default.toml`). Every section and key has a default, so an
//! empty file is the default fit; unknown keys are errors and every value is range-checked
//! with a message naming the key. The resolved config is written next to the fit's outputs.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::localiser_config::LocaliserConfig;
use crate::config::{Checker, ConfigFile};
use crate::error::Result;
use crate::field::GrowthConfig;

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FitConfig {
    pub contours: ContourConfig,
    pub pith: PithFitConfig,
    pub distortion: DistortionFitConfig,
    pub rings: RingPeakConfig,
    pub knots: KnotFitConfig,
    pub colour: ColourFitConfig,
    /// The ring localiser, for faces without ring images (`crate::rings`).
    pub localiser: LocaliserConfig,
    /// The inverse procedural fit (`fit::procedural_fit`).
    pub procedural: ProceduralFitConfig,
}

/// The inverse procedural fit: which presets are tried, at what size, how long the search is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ProceduralFitConfig {
    /// Species presets tried (the lowest style loss wins); empty: no procedural fit, and
    /// `xylem run` shows its `--species` preset on the fitted field instead. `burl` is left
    /// out by default: a figure rather than a species, and 30x slower to render.
    pub presets: Vec<String>,
    /// Face side (pixels) at which candidates are searched; photos larger are box-filtered.
    pub search_size: usize,
    /// Rounds of the appearance parameters' pattern search (0: phase and colour only).
    pub rounds: usize,
}

impl Default for ProceduralFitConfig {
    fn default() -> Self {
        Self {
            presets: ["oak", "chestnut", "maple", "walnut", "softwood"]
                .map(String::from)
                .to_vec(),
            search_size: 128,
            rounds: 3,
        }
    }
}

impl ProceduralFitConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        for (i, name) in self.presets.iter().enumerate() {
            if crate::presets::species_preset(name).is_none() {
                return Err(check.error(
                    &format!("presets[{i}]"),
                    format!(
                        "= {:?}: not a species preset (one of {})",
                        name,
                        crate::presets::species_preset_names().join(", ")
                    ),
                ));
            }
        }
        check.count(
            "search_size",
            self.search_size,
            16,
            1024,
            "a face side in pixels",
        )?;
        check.count("rounds", self.rounds, 0, 10, "search rounds")
    }
}

/// Contour extraction from the ring localisation images (Mokume 5.1.2, DESIGN section 5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContourConfig {
    /// Pixels at or above this grey value (0..1) belong to a ring (200/255 in the reference);
    /// contours are the edges of these bands.
    pub threshold: f32,
    /// Pixels this close to the image border are dropped (U-Net output is poor there).
    pub border: usize,
    /// Edge components with fewer pixels are dropped (the reference drops 32 or fewer).
    pub min_pixels: usize,
    /// At most this many contour points enter the losses (evenly thinned within each contour).
    pub max_points: usize,
}

/// Step 1: the pith axis of the undistorted field G = r.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PithFitConfig {
    /// Largest tilt of a candidate axis from the y axis (degrees).
    pub max_tilt_deg: f32,
    /// Spacing of candidate directions (degrees).
    pub direction_step_deg: f32,
    /// Distances of candidate axes from the cube centre (cube units; 10 = 40 cm).
    pub distances: Vec<f32>,
    /// Candidate axis positions around the cube centre at each distance.
    pub offset_azimuths: usize,
    /// Contour points used to score the candidates (evenly thinned).
    pub search_points: usize,
    /// Best distinct candidates refined by gradient descent (each then gets a step-2 trial).
    pub refine: usize,
    /// Adam iterations per refined candidate.
    pub iterations: usize,
    /// Adam step for the axis position (cube units, scaled by the candidate's distance).
    pub lr_origin: f32,
    /// Adam step for the axis direction.
    pub lr_direction: f32,
}

/// Step 2: the rate grid R and the grey map M (and knots).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DistortionFitConfig {
    /// Rate grid resolution [n_h, n_a, n_r] (the paper's 8 x 16 x 16).
    pub grid: [usize; 3],
    /// Adam iterations of the final fit.
    pub iterations: usize,
    /// Adam iterations of the short trial fit from each refined pith candidate; the candidate
    /// with the lowest step-2 loss is kept (0: keep the best step-1 candidate).
    pub trial_iterations: usize,
    /// Adam step for the rates, as the ring shift one step may cause (cube units): each log
    /// rate's step is this over its lever (how far G moves per unit of relative rate, in
    /// cube units), so the first radial node, which also sets the growth between the pith
    /// and the cube, moves as carefully as the others.
    pub lr_rates: f32,
    /// Adam step for the grey map.
    pub lr_map: f32,
    /// Weight of the iso-contour loss (lambda1).
    pub lambda_iso: f32,
    /// Weight of the L1 loss between M(G) and the ring images (lambda2).
    pub lambda_image: f32,
    /// Weight of the smoothness penalty on neighbouring log rates.
    pub lambda_smooth: f32,
    /// Weight of the penalty on the log rates themselves (pulls towards round rings where
    /// the faces say nothing).
    pub lambda_magnitude: f32,
    /// Nodes of the grey map M per year of G (the map spans the faces' range of G); fine
    /// enough to resolve a ring, which is about a tenth of a year wide in sharp images.
    pub map_nodes_per_year: f32,
    /// Every `image_stride`-th pixel (in rows and columns) enters the image loss.
    pub image_stride: usize,
    /// Smallest relative growth rate (rings never cross).
    pub min_rate: f32,
    /// The knot-parameter gradient is estimated from every n-th point (1: all, exact). Its
    /// finite differences cost 14 field evaluations per point and knot while a knot has
    /// only 7 parameters, and the points are dense, so a quarter of them points the same way;
    /// rates and grey map always see every point.
    pub knot_gradient_stride: usize,
}

/// Ring iso-values from the peaks of M.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RingPeakConfig {
    /// Runs of M above min + threshold x (max - min) are rings.
    pub threshold: f32,
    /// A gap wider than this many median spacings gets evenly spaced rings inserted.
    pub gap_factor: f32,
}

/// Knots initialised from the markers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct KnotFitConfig {
    /// Knot radius at the marks (cube units; 0.12 = 5 mm) when the photos do not show it
    /// (`knot_init::photo_knot_radius`). The knot's growth speed (knot radius / stem radius)
    /// is this radius over the marks' distance from the pith.
    pub radius: f32,
    /// Largest knot radius looked for in the photos (cube units).
    pub max_radius: f32,
    /// Weight of the penalty holding each knot's strand near its marks (per cube unit
    /// squared; 100: a 1 mm miss costs 0.06).
    pub lambda_anchor: f32,
    /// Fit the growth speed too (the ring images hardly constrain a knot's size, see
    /// `knot_init`); origin and direction are fitted when `fit` is set.
    pub fit_speed: bool,
    /// Contour points closer than this to a marked knot axis (cube units) are left out of
    /// step 1, whose undistorted field cannot explain them.
    pub exclusion: f32,
    /// Adam step for the knot origin and direction (cube units).
    pub lr: f32,
    /// Fit the knot axis and speed in step 2 (false: keep the marked axis).
    pub fit: bool,
}

/// The base colour bars.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ColourFitConfig {
    /// Nodes of the colour bar over normalised G.
    pub bar_nodes: usize,
    /// Adam iterations after the binned-median start.
    pub iterations: usize,
    pub lr: f32,
    /// Weight of the smoothness penalty on neighbouring bar nodes.
    pub lambda_smooth: f32,
    /// Weight of the L2 penalty that keeps the per-face offsets small.
    pub lambda_offset: f32,
    /// Every `pixel_stride`-th pixel (in rows and columns) enters the colour loss.
    pub pixel_stride: usize,
    /// Years of (stem - knot time) over which the knot bar blends in.
    pub knot_blend: f32,
}

impl Default for ContourConfig {
    fn default() -> Self {
        Self {
            threshold: 200.0 / 255.0,
            border: 5,
            min_pixels: 33,
            max_points: 30_000,
        }
    }
}

impl Default for PithFitConfig {
    fn default() -> Self {
        Self {
            max_tilt_deg: 60.0,
            direction_step_deg: 7.5,
            distances: vec![0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.5, 7.0, 10.0],
            offset_azimuths: 16,
            search_points: 2000,
            refine: 4,
            iterations: 150,
            lr_origin: 0.02,
            lr_direction: 0.01,
        }
    }
}

impl Default for DistortionFitConfig {
    fn default() -> Self {
        Self {
            grid: [8, 16, 16],
            iterations: 300,
            trial_iterations: 60,
            lr_rates: 0.001,
            lr_map: 0.02,
            lambda_iso: 10.0,
            lambda_image: 1.0,
            lambda_smooth: 5.0,
            lambda_magnitude: 0.0,
            map_nodes_per_year: 24.0,
            image_stride: 4,
            min_rate: 0.05,
            knot_gradient_stride: 4,
        }
    }
}

impl Default for RingPeakConfig {
    fn default() -> Self {
        Self {
            threshold: 0.35,
            gap_factor: 1.6,
        }
    }
}

impl Default for KnotFitConfig {
    fn default() -> Self {
        Self {
            radius: 0.12,
            max_radius: 0.45,
            fit_speed: false,
            lambda_anchor: 100.0,
            exclusion: 0.1,
            lr: 0.005,
            fit: true,
        }
    }
}

impl Default for ColourFitConfig {
    fn default() -> Self {
        Self {
            bar_nodes: 128,
            iterations: 150,
            lr: 0.005,
            lambda_smooth: 0.5,
            lambda_offset: 0.1,
            pixel_stride: 2,
            knot_blend: 1.0,
        }
    }
}

/// A loss weight: finite, in [0, 1e6].
fn weight(check: &Checker, key: &str, value: f32) -> Result<()> {
    check.range(key, value, 0.0, 1e6, "a loss weight")
}

impl FitConfig {
    /// The config at `path`, or the built-in defaults when no file is given.
    pub fn load_or_default(path: Option<&Path>) -> Result<Self> {
        path.map_or_else(|| Ok(Self::default()), Self::load)
    }
}

impl ConfigFile for FitConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        self.contours.validate(&check.nested("contours"))?;
        self.pith.validate(&check.nested("pith"))?;
        self.distortion.validate(&check.nested("distortion"))?;
        self.rings.validate(&check.nested("rings"))?;
        self.knots.validate(&check.nested("knots"))?;
        self.colour.validate(&check.nested("colour"))?;
        self.localiser.validate(&check.nested("localiser"))?;
        self.procedural.validate(&check.nested("procedural"))
    }
}

impl ContourConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "threshold",
            self.threshold,
            0.01,
            1.0,
            "a grey level in (0, 1]",
        )?;
        check.count("border", self.border, 0, 64, "pixels trimmed at the border")?;
        check.count(
            "min_pixels",
            self.min_pixels,
            1,
            100_000,
            "the smallest contour size in pixels",
        )?;
        check.count(
            "max_points",
            self.max_points,
            100,
            10_000_000,
            "the number of contour points used",
        )
    }
}

impl PithFitConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "max_tilt_deg",
            self.max_tilt_deg,
            0.0,
            89.0,
            "degrees from the y axis",
        )?;
        check.range(
            "direction_step_deg",
            self.direction_step_deg,
            0.5,
            45.0,
            "degrees",
        )?;
        check.list_length(
            "distances",
            self.distances.len(),
            1,
            64,
            "values; expected 1 to 64 distances",
        )?;
        for (i, d) in self.distances.iter().enumerate() {
            check.range(
                &format!("distances[{i}]"),
                *d,
                0.0,
                50.0,
                "a distance in cube units",
            )?;
        }
        check.count(
            "offset_azimuths",
            self.offset_azimuths,
            1,
            256,
            "positions around the cube centre",
        )?;
        check.count(
            "search_points",
            self.search_points,
            50,
            1_000_000,
            "contour points",
        )?;
        check.count("refine", self.refine, 1, 64, "candidates to refine")?;
        check.count("iterations", self.iterations, 0, 100_000, "Adam iterations")?;
        check.range("lr_origin", self.lr_origin, 0.0, 1.0, "an Adam step")?;
        check.range("lr_direction", self.lr_direction, 0.0, 1.0, "an Adam step")
    }
}

impl DistortionFitConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        let [nh, na, nr] = self.grid;
        check.count("grid[0]", nh, 1, 64, "the number of heights n_h")?;
        check.count("grid[1]", na, 4, 128, "the number of azimuths n_a")?;
        check.count("grid[2]", nr, 2, 128, "the number of radii n_r")?;
        check.count("iterations", self.iterations, 0, 100_000, "Adam iterations")?;
        check.count(
            "trial_iterations",
            self.trial_iterations,
            0,
            100_000,
            "Adam iterations per trial",
        )?;
        check.range(
            "lr_rates",
            self.lr_rates,
            0.0,
            0.1,
            "a ring shift per Adam step in cube units",
        )?;
        check.range("lr_map", self.lr_map, 0.0, 1.0, "an Adam step")?;
        weight(check, "lambda_iso", self.lambda_iso)?;
        weight(check, "lambda_image", self.lambda_image)?;
        weight(check, "lambda_smooth", self.lambda_smooth)?;
        weight(check, "lambda_magnitude", self.lambda_magnitude)?;
        check.range(
            "map_nodes_per_year",
            self.map_nodes_per_year,
            1.0,
            200.0,
            "grey-map nodes per year",
        )?;
        check.count("image_stride", self.image_stride, 1, 64, "a pixel stride")?;
        GrowthConfig::check_min_rate(check, self.min_rate)?;
        check.count(
            "knot_gradient_stride",
            self.knot_gradient_stride,
            1,
            64,
            "a point stride",
        )
    }
}

impl RingPeakConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "threshold",
            self.threshold,
            0.01,
            0.99,
            "a fraction of the grey map's range",
        )?;
        check.range(
            "gap_factor",
            self.gap_factor,
            1.1,
            100.0,
            "a multiple of the median ring spacing",
        )
    }
}

impl KnotFitConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range(
            "radius",
            self.radius,
            0.005,
            1.0,
            "the initial knot radius in cube units",
        )?;
        check.range(
            "max_radius",
            self.max_radius,
            0.01,
            1.0,
            "the largest knot radius in cube units",
        )?;
        weight(check, "lambda_anchor", self.lambda_anchor)?;
        check.range(
            "exclusion",
            self.exclusion,
            0.0,
            1.0,
            "a distance in cube units",
        )?;
        check.range("lr", self.lr, 0.0, 1.0, "an Adam step")
    }
}

impl ColourFitConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.count("bar_nodes", self.bar_nodes, 2, 4096, "colour bar nodes")?;
        check.count("iterations", self.iterations, 0, 100_000, "Adam iterations")?;
        check.range("lr", self.lr, 0.0, 1.0, "an Adam step")?;
        weight(check, "lambda_smooth", self.lambda_smooth)?;
        weight(check, "lambda_offset", self.lambda_offset)?;
        check.count("pixel_stride", self.pixel_stride, 1, 64, "a pixel stride")?;
        check.positive("knot_blend", self.knot_blend, 1000.0, "years")
    }
}
