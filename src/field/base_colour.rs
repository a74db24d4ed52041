//! The base colour B(G) of a fitted field (Mokume 5.2, DESIGN section 5): a colour bar over
//! normalised G, a second bar for knots, small per-face offsets for lighting differences
//! between the photos, and the white balance needed to go back to real colour.
//!
//! Colours are stored white-balanced, as the NCA's targets are (DESIGN section 6): each face
//! photo divided by 2 x its mean colour, so a typical face averages 0.5. Real colour is
//! white-balanced colour x 2 x a mean: a face's own mean for that face, the mean over the
//! fitted faces for cuts and volumes.
//!
//! Bars are piecewise linear over t = (G - lo) / (hi - lo) with `g_range = [lo, hi]`, clamped
//! to [0, 1], with nodes evenly spaced over [0, 1]. Where a knot strand dominates, the knot
//! bar takes over, blended over `knot_blend` years of (stem time - knot time) so that the knot
//! boundary is soft rather than a seam.

use serde::{Deserialize, Serialize};

use super::field_sample::FieldSample;
use super::grain_shading::GrainShading;
use super::smin::smoothstep;
use crate::config::Checker;
use crate::error::Result;
use crate::frame::Face;

/// Most bar nodes accepted.
const MAX_BAR_NODES: usize = 4096;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseColour {
    /// G (years, after the ring warp) at the two ends of the bars.
    pub g_range: [f32; 2],
    /// Stem colour bar, white-balanced RGB, nodes evenly spaced over t in [0, 1].
    pub bar: Vec<[f32; 3]>,
    /// Knot colour bar over the same t; empty when the field has no knots.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub knot_bar: Vec<[f32; 3]>,
    /// Years of (stem time - knot time) over which the knot bar blends in.
    #[serde(default = "default_knot_blend")]
    pub knot_blend: f32,
    /// White-balanced RGB added on each face A..F (photo lighting); zero for faces not fitted.
    pub face_offsets: [[f32; 3]; 6],
    /// White-balanced RGB from the bars' ground colour to the photos' mean colour: the mean
    /// residual of the robust (L1) fit over the fitted faces. The bars follow each ring
    /// position's median, which lies above the mean where dark pores make a tail (synthetic
    /// chestnut: 4 % in lightness); the base colour shown on its own as a prediction of the
    /// photos adds it (`ColourSpace::Shown`), the NCA's B does not (its residual paints the
    /// pores on the ground colour). Absent in fits made before it: zero.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub mean_shift: [f32; 3],
    pub white_balance: WhiteBalance,
}

/// The way back from white-balanced to real colour.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhiteBalance {
    /// Mean real RGB (in [0, 1]) of each face photo A..F; faces not fitted hold `mean`.
    pub face_means: [[f32; 3]; 6],
    /// Mean of the fitted faces' means: the white balance of cuts and volumes.
    pub mean: [f32; 3],
    /// How the mean colour changes with the angle of surface and fibres, when the photos
    /// show it (`grain_shading`); absent: every surface has the plain `mean`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grain: Option<GrainShading>,
}

fn is_zero(v: &[f32; 3]) -> bool {
    v.iter().all(|&x| x == 0.0)
}

fn default_knot_blend() -> f32 {
    1.0
}

/// The node interval and fraction of t in [0, 1] on a bar of `n` >= 2 nodes: t falls between
/// nodes i and i + 1 at fraction f (i <= n - 2).
pub fn bar_position(t: f32, n: usize) -> (usize, f32) {
    let x = t.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (x.floor() as usize).min(n - 2);
    (i, x - i as f32)
}

/// Linear interpolation of a bar at t.
pub(crate) fn bar_lookup(bar: &[[f32; 3]], t: f32) -> [f32; 3] {
    let (i, f) = bar_position(t, bar.len());
    std::array::from_fn(|c| bar[i][c] * (1.0 - f) + bar[i + 1][c] * f)
}

impl WhiteBalance {
    /// Real colour of a white-balanced value seen on `face` (`None`: a cut or volume).
    pub(crate) fn to_real(&self, rgb: [f32; 3], face: Option<Face>) -> [f32; 3] {
        let mean = face.map_or(self.mean, |f| self.face_means[f.index()]);
        std::array::from_fn(|c| rgb[c] * 2.0 * mean[c])
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        for (f, m) in self.face_means.iter().enumerate() {
            check_mean(check, &format!("face_means[{f}]"), *m)?;
        }
        check_mean(check, "mean", self.mean)?;
        match &self.grain {
            Some(g) => g.validate(&check.nested("grain")),
            None => Ok(()),
        }
    }
}

fn check_mean(check: &Checker, key: &str, m: [f32; 3]) -> Result<()> {
    if m.iter().all(|v| v.is_finite() && *v >= 1e-4 && *v <= 1.0) {
        Ok(())
    } else {
        Err(check.error(
            key,
            format!("= {m:?}: expected a mean RGB colour with channels in [0.0001, 1]"),
        ))
    }
}

fn check_bar(check: &Checker, key: &str, bar: &[[f32; 3]], allow_empty: bool) -> Result<()> {
    if bar.is_empty() && allow_empty {
        return Ok(());
    }
    if bar.len() < 2 || bar.len() > MAX_BAR_NODES {
        return Err(check.error(
            key,
            format!(
                "has {} nodes; expected 2 to {MAX_BAR_NODES} RGB triples",
                bar.len()
            ),
        ));
    }
    if let Some(i) = bar
        .iter()
        .position(|c| !c.iter().all(|v| v.is_finite() && v.abs() <= 10.0))
    {
        return Err(check.error(
            key,
            format!(
                "[{i}] = {:?}: expected white-balanced RGB values within +-10",
                bar[i]
            ),
        ));
    }
    Ok(())
}

impl BaseColour {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        let [lo, hi] = self.g_range;
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            return Err(check.error(
                "g_range",
                format!("= [{lo}, {hi}]: expected [low, high] years with low < high"),
            ));
        }
        check_bar(check, "bar", &self.bar, false)?;
        check_bar(check, "knot_bar", &self.knot_bar, true)?;
        check.positive(
            "knot_blend",
            self.knot_blend,
            1000.0,
            "a blend width in years",
        )?;
        for (f, o) in self.face_offsets.iter().enumerate() {
            check.vector(
                &format!("face_offsets[{f}]"),
                *o,
                2.0,
                "a white-balanced RGB offset",
            )?;
        }
        check.vector(
            "mean_shift",
            self.mean_shift,
            0.5,
            "a white-balanced RGB shift",
        )?;
        self.white_balance.validate(&check.nested("white_balance"))
    }

    /// t in [0, 1] of a G value (years).
    pub fn normalised(&self, g: f32) -> f32 {
        let [lo, hi] = self.g_range;
        ((g - lo) / (hi - lo)).clamp(0.0, 1.0)
    }

    /// Weight of the knot bar at a field sample (0 on the stem, 1 well inside a knot).
    pub(crate) fn knot_weight(&self, s: &FieldSample) -> f32 {
        if self.knot_bar.is_empty() || !s.knot_time.is_finite() {
            return 0.0;
        }
        smoothstep(-self.knot_blend, self.knot_blend, s.stem - s.knot_time)
    }

    /// White-balanced base colour at a field sample (no face offset).
    pub fn colour(&self, s: &FieldSample) -> [f32; 3] {
        let t = self.normalised(s.g);
        let stem = bar_lookup(&self.bar, t);
        let w = self.knot_weight(s);
        if w <= 0.0 {
            return stem;
        }
        let knot = bar_lookup(&self.knot_bar, t);
        std::array::from_fn(|c| stem[c] * (1.0 - w) + knot[c] * w)
    }

    /// Real colour of a white-balanced base colour as it appears on `face` (offset and that
    /// face's white balance) or in a cut or volume (`None`).
    pub(crate) fn to_real(&self, rgb: [f32; 3], face: Option<Face>) -> [f32; 3] {
        let offset = face.map_or([0.0; 3], |f| self.face_offsets[f.index()]);
        let lit = std::array::from_fn(|c| rgb[c] + offset[c]);
        self.white_balance.to_real(lit, face)
    }

    /// [`Self::to_real`] of the colour shifted to the photos' mean (`mean_shift`).
    pub(crate) fn to_shown(&self, rgb: [f32; 3], face: Option<Face>) -> [f32; 3] {
        self.to_real(std::array::from_fn(|c| rgb[c] + self.mean_shift[c]), face)
    }
}
