//! The growth field G(p): the time (years) at which the wood at p was laid down. Annual
//! rings are its iso-surfaces at the ring years.
//!
//! Stem: t_s = years_per_unit x (integral of the rate grid along r), or years_per_unit x r
//! without a grid. Knots join by Larsson's rule for several strands:
//! G = min(t_s, t_b1, ..., t_bn) + sum_i delta_i, where delta_i is knot i's (modified) pairwise
//! smoothing with the stem, faded out inside the other knots so one knot does not distort
//! another's interior.
//!
//! A fitted field may list its ring positions (`growth.rings`); G, the stem time and the knot
//! times are then reported through the ring warp so that rings fall on integer years. Knot
//! parameters (`death`) stay in raw stem time.

use glam::Vec3;

use super::config::FieldConfig;
use super::distortion::random_rates;
use super::field_sample::{FieldSample, Strand};
use super::knot::{Knot, KnotSample};
use super::pith::PithAxis;
use super::rate_grid::RateGrid;
use super::ring_warp::RingWarp;
use super::smin::smoothstep;
use crate::texture::SolidTexture;

#[derive(Clone, Debug)]
pub struct GrowthField {
    pub pith: PithAxis,
    pub years_per_unit: f32,
    /// `None`: undistorted, G = years_per_unit x r exactly.
    pub rates: Option<RateGrid>,
    pub knots: Vec<Knot>,
    /// Fitted ring positions: G, the stem time and knot times are reported through this warp
    /// (`None`: rings at integer raw times).
    pub warp: Option<RingWarp>,
}

impl GrowthField {
    /// Builds the field of a validated config.
    pub fn from_config(cfg: &FieldConfig) -> Self {
        let pith = PithAxis::new(Vec3::from(cfg.pith.origin), Vec3::from(cfg.pith.direction));
        let g = &cfg.growth;
        let raw = match (&g.rates, &g.distortion) {
            (Some(r), _) => Some(r.clone()),
            (None, Some(d)) => Some(random_rates(d, g.grid)),
            (None, None) => None,
        };
        let rates = raw.map(|r| {
            RateGrid::new(
                g.grid,
                r,
                g.min_rate,
                g.height_range.unwrap_or_else(|| pith.cube_height_range()),
                g.radius_range.unwrap_or_else(|| pith.cube_radius_range()),
            )
            .with_azimuth_range(g.azimuth_range)
        });
        let knots = cfg.knots.iter().map(|k| Knot::new(k, pith.dir)).collect();
        Self {
            pith,
            years_per_unit: g.years_per_unit,
            rates,
            knots,
            warp: g.rings.as_ref().map(RingWarp::new),
        }
    }

    /// A raw time seen through the ring warp (unchanged without one).
    pub fn warped(&self, t: f32) -> f32 {
        match &self.warp {
            Some(w) if t.is_finite() => w.apply(t),
            _ => t,
        }
    }

    /// The raw stem time t_s at p (before the ring warp).
    pub(crate) fn stem_time(&self, p: Vec3) -> f32 {
        match &self.rates {
            None => self.years_per_unit * self.pith.radius(p),
            Some(grid) => self.years_per_unit * grid.integral(&self.pith.cylindrical(p)),
        }
    }

    /// G at p.
    pub fn value(&self, p: Vec3) -> f32 {
        if self.knots.is_empty() {
            return self.warped(self.stem_time(p));
        }
        self.sample(p).g
    }

    /// G at p with the dominant strand and knot information.
    pub fn sample(&self, p: Vec3) -> FieldSample {
        let raw = self.raw_sample(p);
        FieldSample {
            g: self.warped(raw.g),
            stem: self.warped(raw.stem),
            knot_time: self.warped(raw.knot_time),
            ..raw
        }
    }

    /// [`GrowthField::sample`] before the ring warp.
    pub(crate) fn raw_sample(&self, p: Vec3) -> FieldSample {
        knot_union(&self.knots, p, self.stem_time(p), self.years_per_unit)
    }
}

/// The stem joined with its knots at `p`, given the raw stem time there: Larsson's rule for
/// several strands (module docs). Public so that the fit can evaluate the union for trial
/// knot parameters without rebuilding the field.
pub fn knot_union(knots: &[Knot], p: Vec3, stem: f32, years_per_unit: f32) -> FieldSample {
    if knots.is_empty() {
        return FieldSample {
            g: stem,
            stem,
            strand: Strand::Stem,
            knot_time: f32::INFINITY,
            in_dead_knot: false,
        };
    }
    // Up to 8 knots are evaluated without a heap allocation (this runs per point).
    const INLINE: usize = 8;
    let sample = |k: &Knot| k.sample(p, stem, years_per_unit);
    if knots.len() <= INLINE {
        let mut buf = [KnotSample::default(); INLINE];
        for (slot, k) in buf.iter_mut().zip(knots) {
            *slot = sample(k);
        }
        combine(stem, &buf[..knots.len()])
    } else {
        let samples: Vec<KnotSample> = knots.iter().map(sample).collect();
        combine(stem, &samples)
    }
}

fn combine(stem: f32, samples: &[KnotSample]) -> FieldSample {
    let (mut min, mut strand) = (stem, Strand::Stem);
    let mut knot_time = f32::INFINITY;
    for (i, s) in samples.iter().enumerate() {
        knot_time = knot_time.min(s.time);
        if s.time < min {
            min = s.time;
            strand = Strand::Knot(i);
        }
    }
    let mut delta_sum = 0.0;
    for (i, s) in samples.iter().enumerate() {
        let other = samples
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, o)| o.time)
            .fold(f32::INFINITY, f32::min);
        let inside_other = if other.is_finite() && stem > 0.0 {
            smoothstep(0.0, 1.0, (stem - other).max(0.0) / stem)
        } else {
            0.0
        };
        delta_sum += s.delta * (1.0 - inside_other);
    }
    let in_dead_knot = matches!(strand, Strand::Knot(i) if samples[i].after_death);
    FieldSample {
        g: (min + delta_sum).max(0.0),
        stem,
        strand,
        knot_time,
        in_dead_knot,
    }
}

/// One channel: G in years.
impl SolidTexture for GrowthField {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[0] = self.value(p);
    }
}
