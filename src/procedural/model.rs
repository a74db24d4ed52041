//! The procedural wood model: a solid texture (RGB, display-referred, in [0, 1]) on top of
//! the growth field.
//!
//! For a point p: figure displacement (if any) gives the idealised point q; with burl, each
//! curl level pushes q further. At the lookup point the growth field gives G, the dominant
//! strand and the knot times; the year table turns G into the ring time T (ring boundaries at
//! integer T); the ring phase picks the earlywood/latewood blend of the two colour maps; the
//! knot colour takes over inside knots; the pigment exponent collects per-year variation,
//! 3D noise, fibres and knot darkening (Beer's law); pores and rays are mixed in last, with
//! their own colours, outside knots. [`WoodSample`] exposes every intermediate quantity, so
//! tests and later stages can measure them.
//!
//! The fibre direction for rendering is not part of the three RGB channels (it costs a
//! Jacobian); [`super::direction::WithFibreDirection`] adds it as channels 3-5.

use glam::Vec3;

use super::burl::Burl;
use super::config::MAX_RAY_LAYERS as MAX_RAYS;
use super::config::SpeciesConfig;
use super::fibres::Fibres;
use super::figure::Figure;
use super::knot_colour::KnotColour;
use super::noise::fract;
use super::pigment::{PigmentNoise, absorb};
use super::pores::Pores;
use super::rays::Rays;
use super::rings::Rings;
use super::tree::TreePoint;
use super::years::YearTable;
use crate::field::smin::smoothstep;
use crate::field::{Cylindrical, FieldSample, GrowthField};
use crate::rng::Rng;
use crate::texture::SolidTexture;

/// Sub-streams of the species seed, one per random component.
mod stream {
    pub(crate) const YEARS: u64 = 1;
    pub(crate) const PIGMENT: u64 = 2;
    pub(crate) const FIBRES: u64 = 3;
    pub(crate) const PORES: u64 = 4;
    pub(crate) const FIGURE: u64 = 5;
    pub(crate) const BURL: u64 = 6;
    pub(crate) const RAYS: u64 = 16;
}

fn stream_seed(seed: u64, stream: u64) -> u64 {
    Rng::substream(seed, stream).next_u64()
}

#[derive(Clone, Debug)]
pub struct ProceduralWood {
    pub field: GrowthField,
    years: YearTable,
    rings: Rings,
    pigment: Option<PigmentNoise>,
    fibres: Option<Fibres>,
    pores: Option<Pores>,
    rays: Vec<Rays>,
    /// Present when the field has knots.
    knots: Option<KnotColour>,
    figure: Option<Figure>,
    burl: Option<Burl>,
    /// `rings.phase_offset`: years added to G before the ring phase.
    phase_offset: f32,
}

/// Everything the model computes at one lookup point.
#[derive(Clone, Copy, Debug)]
pub struct WoodSample {
    pub field: FieldSample,
    pub tree: TreePoint,
    /// Ring time T (years): integer values are ring boundaries.
    pub time: f32,
    /// Fractional part of T.
    pub phase: f32,
    /// Latewood weight in [0, 1].
    pub latewood: f32,
    /// Knot membership in [0, 1].
    pub knot: f32,
    /// Pore weight in [0, 1] (0 inside knots).
    pub pore: f32,
    /// Ray weight of each layer in [0, 1] (unused layers 0).
    pub rays: [f32; MAX_RAYS],
    /// Fibre value in [-1, 1] (0 without fibres).
    pub fibre: f32,
    /// Log pigment exponent from per-year variation and 3D noise.
    pub pigment: f32,
}

impl WoodSample {
    /// The strongest ray weight over all layers.
    pub fn ray(&self) -> f32 {
        self.rays.iter().copied().fold(0.0, f32::max)
    }
}

impl ProceduralWood {
    /// Builds the model of a validated species config.
    pub fn new(cfg: &SpeciesConfig) -> Self {
        let field = GrowthField::from_config(&cfg.field_config());
        let seed = cfg.seed;
        let rings = &cfg.rings;
        Self {
            years: YearTable::new(
                stream_seed(seed, stream::YEARS),
                rings.width_variation,
                rings.width_correlation,
                rings.colour_variation,
            ),
            rings: Rings::new(rings),
            phase_offset: rings.phase_offset,
            pigment: cfg
                .pigment
                .as_ref()
                .map(|p| PigmentNoise::new(p, stream_seed(seed, stream::PIGMENT))),
            fibres: cfg
                .fibres
                .as_ref()
                .map(|f| Fibres::new(f, stream_seed(seed, stream::FIBRES))),
            pores: cfg
                .pores
                .as_ref()
                .map(|p| Pores::new(p, stream_seed(seed, stream::PORES))),
            rays: cfg
                .rays
                .iter()
                .enumerate()
                .map(|(i, r)| Rays::new(r, stream_seed(seed, stream::RAYS + i as u64)))
                .collect(),
            knots: (!cfg.knots.is_empty()).then(|| KnotColour::new(&cfg.knot_colour)),
            figure: cfg
                .figure
                .as_ref()
                .map(|f| Figure::new(f, stream_seed(seed, stream::FIGURE))),
            burl: cfg
                .burl
                .as_ref()
                .map(|b| Burl::new(b, &field.pith, stream_seed(seed, stream::BURL))),
            field,
        }
    }

    /// The idealised point of the strongest curl level that `p` shows (figure, then burl).
    pub fn lookup(&self, p: Vec3) -> Vec3 {
        self.lookup_level(self.figured(p), 0)
    }

    fn figured(&self, p: Vec3) -> Vec3 {
        match &self.figure {
            Some(f) => f.apply(&self.field.pith, p),
            None => p,
        }
    }

    fn lookup_level(&self, q: Vec3, level: usize) -> Vec3 {
        match &self.burl {
            Some(b) => b.lookup(q, level),
            None => q,
        }
    }

    /// The ring time T at `p` (what a synthetic sample's ring images show).
    pub(crate) fn ring_time(&self, p: Vec3) -> f32 {
        self.years.time(self.field.value(self.lookup(p)))
    }

    /// All intermediate quantities at `p` (strongest curl level for burl).
    pub fn sample(&self, p: Vec3) -> WoodSample {
        self.sample_at(self.lookup(p))
    }

    /// The model at an idealised lookup point.
    pub(crate) fn sample_at(&self, q: Vec3) -> WoodSample {
        let field = self.field.sample(q);
        let tree = TreePoint::new(&self.field.pith, q);
        let time = self.years.time(field.g + self.phase_offset);
        let phase = fract(time);
        let latewood = self.rings.latewood(phase);
        let knot = self.knots.as_ref().map_or(0.0, |k| k.mask(&field));
        let outside = knot < 1.0;
        let rho = field.g / self.field.years_per_unit;
        let pore = match &self.pores {
            Some(p) if outside => {
                let years = (&self.years, self.phase_offset);
                p.weight(&tree, rho, years, self.field.years_per_unit, || {
                    self.radial_rate(&tree)
                })
            }
            _ => 0.0,
        };
        let mut rays = [0.0; MAX_RAYS];
        if outside {
            for (w, layer) in rays.iter_mut().zip(&self.rays) {
                *w = layer.weight(rho, tree.phi, tree.h);
            }
        }
        let fibre = self.fibres.as_ref().map_or(0.0, |f| f.value(&tree));
        let pigment =
            self.years.colour_offset(time) + self.pigment.as_ref().map_or(0.0, |n| n.offset(&tree));
        WoodSample {
            field,
            tree,
            time,
            phase,
            latewood,
            knot,
            pore,
            rays,
            fibre,
            pigment,
        }
    }

    /// d rho / d r at a tree point: the stem's interpolated growth rate relative to
    /// `years_per_unit` (1 without a rate grid).
    fn radial_rate(&self, tree: &TreePoint) -> f32 {
        self.field.rates.as_ref().map_or(1.0, |grid| {
            grid.rate(&Cylindrical {
                h: tree.h,
                r: tree.r,
                phi: tree.phi,
            })
        })
    }

    /// The colour of one sample (display-referred RGB in [0, 1]).
    pub fn shade(&self, s: &WoodSample) -> Vec3 {
        let mut base = self.rings.colour(s.time, s.latewood);
        let mut delta = s.pigment;
        let clear = 1.0 - s.knot;
        if let Some(k) = &self.knots {
            base = base.lerp(k.colour(&s.field), s.knot * k.opacity);
            delta += s.knot * k.darken;
        }
        if let Some(f) = &self.fibres {
            delta += clear * f.offset(s.fibre, s.latewood);
        }
        let mut c = absorb(base, delta);
        if let Some(p) = &self.pores {
            // The kernel's soft shoulder is steepened so pores read as holes, not smudges.
            let w = (8.0 * s.pore).min(1.0);
            c = c.lerp(p.colour, w * p.opacity * clear);
        }
        for (w, layer) in s.rays.iter().zip(&self.rays) {
            // Rays are flat ribbons with crisp edges: a soft kernel cut obliquely would smear
            // them over millimetres, so the weight is thresholded with a short ramp.
            let w = smoothstep(0.02, 0.2, *w);
            c = c.lerp(layer.colour, w * layer.opacity * clear);
        }
        if let Some(k) = &self.knots {
            c = c.lerp(k.outline_colour, k.outline(&s.field));
        }
        c.clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// The colour at `p`: one lookup, or with burl the blend of all curl levels and the buds'
    /// eyes.
    pub fn colour(&self, p: Vec3) -> Vec3 {
        let q = self.figured(p);
        let Some(burl) = &self.burl else {
            return self.shade(&self.sample_at(q));
        };
        let mut c = self.shade(&self.sample_at(burl.lookup(q, 0)));
        for level in 1..burl.levels() {
            let other = self.shade(&self.sample_at(burl.lookup(q, level)));
            c = c.lerp(other, burl.balance);
        }
        let (eye, shade) = burl.eye(q);
        c.lerp(burl.bud_colour * shade, eye)
    }
}

/// RGB, display-referred, in [0, 1].
impl SolidTexture for ProceduralWood {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out.copy_from_slice(&self.colour(p).to_array());
    }
}

/// One channel: the model's ring time T (years), for ring localisation images.
pub struct RingTime<'a>(pub &'a ProceduralWood);

impl SolidTexture for RingTime<'_> {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[0] = self.0.ring_time(p);
    }
}
