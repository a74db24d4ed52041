//! The style-loss config (`configs/loss/default.toml`): pyramid, filter bank, sliced
//! Wasserstein projections and the weight of each term. Plain serde structs; unknown keys are
//! errors and every value is range-checked with a message naming the key.

use serde::{Deserialize, Serialize};

use crate::config::{Checker, ConfigFile};
use crate::error::Result;

/// The built-in default (the text of `configs/loss/default.toml`).
pub(crate) const DEFAULT_LOSS: &str = include_str!("../../configs/loss/default.toml");

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LossConfig {
    /// Seed of the random filters and projections (fixed per loss instance).
    pub seed: u64,
    /// Pyramid levels: level 0 is the image, each next one a 2x2 average of the previous.
    pub octaves: usize,
    /// A level whose valid feature map has fewer pixels than this is skipped (a small patch
    /// has no coarse levels; its statistics would rest on a handful of pixels).
    pub min_layer_pixels: usize,
    /// Four more axes for the colour term, each halfway between lightness and one opponent
    /// axis (L + rg, L - rg, L + yb, L - yb). The six default axes match the marginals of
    /// lightness and chroma but not how they go together: an NCA matched them with grey-blue
    /// pores on pink wood where the photo's pores are darker *and* browner (CN03: correlation
    /// of lightness and yellow-blue over the pixels -0.46 in the photos, +0.27 in the quick
    /// model's faces). The spread along L + yb differs from that along L - yb by twice
    /// their covariance, so these axes pin the coupling. Default false (six axes).
    #[serde(default)]
    pub joint_colour: bool,
    pub filters: FilterConfig,
    pub swd: SwdConfig,
    pub weights: LossWeights,
}

/// The fixed filter bank applied at every pyramid level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilterConfig {
    /// Square kernel sides (odd). Each size gets `random` random filters and the oriented
    /// filters; all responses of a level are cropped to the largest kernel's valid region and
    /// form one feature layer.
    pub kernel_sizes: Vec<usize>,
    /// Random filters per kernel size (zero-mean, unit norm, over RGB).
    pub random: usize,
    /// Orientations of the oriented (Gaussian-derivative) filters per kernel size; each
    /// orientation gives a first and a second derivative on luminance. 0: none.
    pub orientations: usize,
    /// Nonlinearity after the filters.
    pub nonlinearity: Nonlinearity,
    /// Length-to-width ratio of the oriented filters' Gaussian (1: round, the first
    /// design). Pores cut along the grain are dashes a pixel or two wide and many long; an
    /// elongated second derivative responds to a dash and hardly to a dot, so the loss can
    /// tell the two apart.
    #[serde(default = "default_elongation")]
    pub elongation: f32,
    /// Norm of two more filters per kernel size: a round second derivative of a Gaussian on
    /// each opponent colour axis (red-green, yellow-blue). 0 (default): none. The photos'
    /// chroma varies slowly; random RGB filters respond mostly to lightness, so speckle of
    /// pink and green costs the loss almost nothing. These filters see chroma edges only,
    /// and a norm above 1 weighs them above the unit-norm filters in every projection.
    #[serde(default)]
    pub chroma: f32,
    /// Sigma (px) of a Gaussian the random filters' white noise is smoothed with before it
    /// is made zero-mean (0, the default: white noise). White zero-mean kernels respond
    /// mostly to the finest scale, so pores one pixel wide and flecks between them cost as
    /// little as pores two pixels wide; smoothed kernels respond to the 1-4 px band where a
    /// 2 px pore lives (BENCHMARKS "Are the held-out pores thin because the photos are soft?").
    #[serde(default)]
    pub random_smoothing: f32,
}

fn default_elongation() -> f32 {
    1.0
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Nonlinearity {
    /// max(0, x): half-wave rectified responses.
    Relu,
    /// |x|: energy-like responses, blind to sign.
    Abs,
    /// The linear responses (patch projections).
    None,
}

/// Sliced Wasserstein on the feature layers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwdConfig {
    /// Random projection directions per layer.
    pub projections: usize,
    /// Draw new projections on every call (from the seed and the caller's call counter)
    /// instead of keeping one fixed set. Needs the target features kept in memory.
    pub redraw: bool,
    /// With `redraw`, at most this many target pixels per layer are projected and sorted
    /// per call (a random subset seeded by the call); their quantiles stand for the face.
    pub max_target_pixels: usize,
}

/// Weight of each term (0 switches a term off; its statistics are then not computed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LossWeights {
    /// Gram matrices (uncentred second moments) of each feature layer.
    pub gram: f32,
    /// Feature means of each layer.
    pub mean: f32,
    /// Feature covariances of each layer.
    pub covariance: f32,
    /// Sliced Wasserstein distance of each layer.
    pub swd: f32,
    /// Pixel colour: mean, covariance and per-channel histogram of RGB.
    pub colour: f32,
}

impl LossConfig {
    /// The built-in default (same as `configs/loss/default.toml`).
    pub fn default_config() -> Self {
        Self::built_in(DEFAULT_LOSS, "<built-in configs/loss/default.toml>")
    }

    /// Channels of one feature layer.
    pub fn features_per_layer(&self) -> usize {
        self.filters.kernel_sizes.len() * (self.filters.random + 2 * self.filters.orientations)
    }
}

impl ConfigFile for LossConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        check.count("octaves", self.octaves, 1, 8, "pyramid levels")?;
        check.count(
            "min_layer_pixels",
            self.min_layer_pixels,
            1,
            1 << 20,
            "pixels a layer needs to be used",
        )?;
        self.filters.validate(&check.nested("filters"))?;
        self.swd.validate(&check.nested("swd"))?;
        self.weights.validate(&check.nested("weights"))
    }
}

impl FilterConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        check.list_length(
            "kernel_sizes",
            self.kernel_sizes.len(),
            1,
            4,
            "entries: expected 1 to 4 odd kernel sides, e.g. [5]",
        )?;
        for &k in &self.kernel_sizes {
            if k % 2 == 0 || !(1..=15).contains(&k) {
                return Err(check.error(
                    "kernel_sizes",
                    format!("contains {k}: expected odd kernel sides in [1, 15]"),
                ));
            }
        }
        check.count(
            "random",
            self.random,
            0,
            256,
            "random filters per kernel size",
        )?;
        check.count(
            "orientations",
            self.orientations,
            0,
            16,
            "filter orientations",
        )?;
        self.check_no_unit_kernel(
            check,
            self.orientations > 0,
            "`orientations` > 0: oriented filters",
        )?;
        check.range(
            "elongation",
            self.elongation,
            1.0,
            8.0,
            "length-to-width ratio of the oriented filters",
        )?;
        check.range(
            "chroma",
            self.chroma,
            0.0,
            16.0,
            "norm of the chroma-edge filters (0: none)",
        )?;
        self.check_no_unit_kernel(
            check,
            self.chroma > 0.0,
            "`chroma` > 0: chroma-edge filters",
        )?;
        check.range(
            "random_smoothing",
            self.random_smoothing,
            0.0,
            4.0,
            "sigma (px) of the random filters' smoothing (0: white)",
        )?;
        if self.random + self.orientations == 0 {
            return Err(check.error("random", "= 0 and `orientations` = 0: the bank is empty"));
        }
        Ok(())
    }

    /// A kernel of side 1 has no neighbours to compare: filters that need them (`which`,
    /// in use when `in_use`) refuse it.
    fn check_no_unit_kernel(&self, check: &Checker, in_use: bool, which: &str) -> Result<()> {
        if in_use && self.kernel_sizes.contains(&1) {
            return Err(check.error(
                "kernel_sizes",
                format!("contains 1 while {which} need kernels of 3 or more"),
            ));
        }
        Ok(())
    }
}

impl SwdConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        check.count(
            "projections",
            self.projections,
            1,
            512,
            "projections per layer",
        )?;
        check.count(
            "max_target_pixels",
            self.max_target_pixels,
            16,
            1 << 22,
            "target pixels kept per layer",
        )
    }
}

impl LossWeights {
    fn validate(&self, check: &Checker) -> Result<()> {
        for (key, w) in self.named() {
            check.range(key, w, 0.0, 1e6, "a term weight")?;
        }
        if self.named().iter().all(|(_, w)| *w == 0.0) {
            return Err(check.error("swd", "all weights are 0: the loss would be empty"));
        }
        Ok(())
    }

    /// The weights with their config keys.
    pub fn named(&self) -> [(&'static str, f32); 5] {
        [
            ("gram", self.gram),
            ("mean", self.mean),
            ("covariance", self.covariance),
            ("swd", self.swd),
            ("colour", self.colour),
        ]
    }
}
