//! 1D colour maps (64 x 3, as in Mokume appendix A.2.3): a colour as a function of a
//! normalised coordinate in [0, 1], used along G for the heart-to-sapwood change of earlywood
//! and latewood and along the knot time for knots.
//!
//! In TOML a map is given by a few control points `[t, r, g, b]` (t strictly increasing in
//! [0, 1], colours display-referred sRGB in [0, 1]) that are interpolated linearly into the 64
//! entries; a fitting stage can write all 64 entries as stops at t = i / 63.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::config::Checker;
use crate::error::Result;

/// Entries of the internal table.
pub(crate) const MAP_LEN: usize = 64;

/// A colour map as written in configs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColourMapConfig {
    /// Control points `[t, r, g, b]`; one stop means a constant colour.
    pub stops: Vec<[f32; 4]>,
}

impl ColourMapConfig {
    /// A constant colour.
    pub fn constant(rgb: [f32; 3]) -> Self {
        Self {
            stops: vec![[0.0, rgb[0], rgb[1], rgb[2]]],
        }
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.list_length(
            "stops",
            self.stops.len(),
            1,
            256,
            "control points; expected 1 to 256 points [t, r, g, b]",
        )?;
        let mut previous = f32::NEG_INFINITY;
        for (i, stop) in self.stops.iter().enumerate() {
            let [t, r, g, b] = *stop;
            let ok_t = t.is_finite() && (0.0..=1.0).contains(&t) && t > previous;
            let ok_rgb = [r, g, b]
                .iter()
                .all(|c| c.is_finite() && (0.0..=1.0).contains(c));
            if !ok_t || !ok_rgb {
                return Err(check.error(
                    &format!("stops[{i}]"),
                    format!(
                        "= {stop:?}: expected [t, r, g, b] with t in [0, 1] strictly increasing \
                         and r, g, b display-referred values in [0, 1]"
                    ),
                ));
            }
            previous = t;
        }
        Ok(())
    }
}

/// A 64-entry colour table with linear lookup.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ColourMap {
    pub entries: [Vec3; MAP_LEN],
}

impl ColourMap {
    /// Interpolates the control points of a validated config into the table (constant
    /// beyond the first and last stop).
    pub(crate) fn from_config(cfg: &ColourMapConfig) -> Self {
        let stops = &cfg.stops;
        let entries = std::array::from_fn(|i| {
            let t = i as f32 / (MAP_LEN - 1) as f32;
            let colour = |s: &[f32; 4]| Vec3::new(s[1], s[2], s[3]);
            let next = stops.iter().position(|s| s[0] >= t);
            match next {
                Some(0) => colour(&stops[0]),
                None => colour(&stops[stops.len() - 1]),
                Some(n) => {
                    let (a, b) = (&stops[n - 1], &stops[n]);
                    colour(a).lerp(colour(b), (t - a[0]) / (b[0] - a[0]))
                }
            }
        });
        Self { entries }
    }

    /// The colour at t in [0, 1] (clamped), linear between entries.
    #[inline]
    pub(crate) fn sample(&self, t: f32) -> Vec3 {
        let x = t.clamp(0.0, 1.0) * (MAP_LEN - 1) as f32;
        let i = (x as usize).min(MAP_LEN - 2);
        self.entries[i].lerp(self.entries[i + 1], x - i as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn stops_interpolate_into_the_table() {
        let cfg = ColourMapConfig {
            stops: vec![
                [0.0, 0.0, 0.0, 0.0],
                [0.5, 1.0, 0.5, 0.0],
                [1.0, 1.0, 1.0, 1.0],
            ],
        };
        cfg.validate(&Checker::new(Path::new("t.toml"))).unwrap();
        let map = ColourMap::from_config(&cfg);
        assert_eq!(map.entries[0], Vec3::ZERO);
        assert_eq!(map.entries[63], Vec3::ONE);
        let mid = map.sample(0.25);
        assert!((mid - Vec3::new(0.5, 0.25, 0.0)).length() < 0.02, "{mid}");
        assert_eq!(map.sample(-3.0), Vec3::ZERO);
        let constant = ColourMap::from_config(&ColourMapConfig::constant([0.2, 0.3, 0.4]));
        assert_eq!(constant.sample(0.7), Vec3::new(0.2, 0.3, 0.4));
    }

    #[test]
    fn bad_stops_name_the_key() {
        let check = Checker::new(Path::new("s.toml")).nested("rings.earlywood");
        let bad = ColourMapConfig {
            stops: vec![[0.5, 0.1, 0.1, 0.1], [0.2, 0.1, 0.1, 0.1]],
        };
        let err = bad.validate(&check).unwrap_err().to_string();
        assert!(err.contains("rings.earlywood.stops[1]"), "{err}");
        let bright = ColourMapConfig::constant([0.2, 1.5, 0.1]);
        assert!(bright.validate(&check).is_err());
    }
}
