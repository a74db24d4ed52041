//! Derivatives of the knotted field for step 2: G = union(stem time, knots) as the field
//! computes it (`field::knot_union`), differentiated with respect to the stem time (chained
//! into the rate grid) and to each knot's origin, direction and speed.
//!
//! A decision: these derivatives are central differences of the field's own union function
//! rather than a second, hand-differentiated copy of Larsson's smooth minimum with its
//! adaptive exponent, knot fade and dead-knot terms. They stay exactly consistent with what
//! `GrowthField` evaluates (a copy could drift), cost 2 + 14 union evaluations per point and
//! knot, and are accurate to about 1e-3 relative in f32, which is plenty for Adam. Everything
//! else in the fit (pith, rates, grey map, colour bars) has analytic gradients;
//! `tests/fit.rs` checks the chained result against finite differences of the whole loss.

use glam::Vec3;

use super::knot_init::{MAX_SPEED, MIN_SPEED};
use crate::field::{Knot, KnotConfig, knot_union};

/// Fitted parameters per knot: origin (3), direction (3), speed.
pub const KNOT_PARAMS: usize = 7;

/// Finite-difference steps: cube units for origin and direction, relative speed units.
const PARAM_STEP: f32 = 1e-3;
/// Finite-difference step of the stem time (years).
const STEM_STEP: f32 = 1e-2;

/// The parameter vector of a knot.
pub fn knot_params(k: &KnotConfig) -> [f32; KNOT_PARAMS] {
    [
        k.origin[0],
        k.origin[1],
        k.origin[2],
        k.direction[0],
        k.direction[1],
        k.direction[2],
        k.speed,
    ]
}

/// Writes a parameter vector back (direction normalised, speed kept within
/// [`MIN_SPEED`, `MAX_SPEED`], or left as it was unless `speed` is set).
pub fn set_knot_params(k: &mut KnotConfig, p: &[f32], speed: bool) {
    k.origin = [p[0], p[1], p[2]];
    let d = Vec3::new(p[3], p[4], p[5]).normalize_or(Vec3::Z);
    k.direction = d.into();
    if speed {
        k.speed = p[6].clamp(MIN_SPEED, MAX_SPEED);
    }
}

/// The knots and, for every parameter, the knots with that parameter moved up and down.
pub(crate) struct KnotVariants {
    base: Vec<Knot>,
    /// `[param][sign]`: the knot set with knot `param / KNOT_PARAMS`'s parameter moved.
    moved: Vec<[Vec<Knot>; 2]>,
}

impl KnotVariants {
    pub(crate) fn new(cfgs: &[KnotConfig], pith_dir: Vec3) -> Self {
        let build = |cfgs: &[KnotConfig]| -> Vec<Knot> {
            cfgs.iter().map(|k| Knot::new(k, pith_dir)).collect()
        };
        let mut moved = Vec::new();
        for (i, k) in cfgs.iter().enumerate() {
            let params = knot_params(k);
            for j in 0..KNOT_PARAMS {
                let sets = [-1.0f32, 1.0].map(|sign| {
                    let mut p = params;
                    p[j] += sign * PARAM_STEP;
                    let mut all = cfgs.to_vec();
                    // No renormalisation or clamping here: the raw move is what is measured.
                    all[i].origin = [p[0], p[1], p[2]];
                    all[i].direction = [p[3], p[4], p[5]];
                    all[i].speed = p[6];
                    build(&all)
                });
                moved.push(sets);
            }
        }
        Self {
            base: build(cfgs),
            moved,
        }
    }

    /// Number of knot parameters (KNOT_PARAMS per knot).
    pub(crate) fn n_params(&self) -> usize {
        self.moved.len()
    }

    /// G at p for stem time `stem`, dG/dstem, and (with `d_params` non-empty) dG/dparam into
    /// `d_params`.
    pub(crate) fn eval(&self, p: Vec3, stem: f32, ypu: f32, d_params: &mut [f32]) -> (f32, f32) {
        d_params.fill(0.0);
        if self.no_influence(p, stem, ypu) {
            // G = stem here, and the knots' fade is flat (C1) at its edge.
            return (stem, 1.0);
        }
        let g = knot_union(&self.base, p, stem, ypu).g;
        let up = knot_union(&self.base, p, stem + STEM_STEP, ypu).g;
        let down = knot_union(&self.base, p, (stem - STEM_STEP).max(0.0), ypu).g;
        let d_stem = (up - down) / (stem + STEM_STEP - (stem - STEM_STEP).max(0.0));
        for (d, [minus, plus]) in d_params.iter_mut().zip(&self.moved) {
            let gp = knot_union(plus, p, stem, ypu).g;
            let gm = knot_union(minus, p, stem, ypu).g;
            *d = (gp - gm) / (2.0 * PARAM_STEP);
        }
        (g, d_stem)
    }

    /// Whether no knot changes G at p (outside every knot and past every fade).
    fn no_influence(&self, p: Vec3, stem: f32, ypu: f32) -> bool {
        self.base.iter().all(|k| {
            let s = k.sample(p, stem, ypu);
            s.delta == 0.0 && s.time > stem + 2.0 * STEM_STEP
        })
    }
}

/// Sum over `marks` of the squared distance from the knot's strand line, and its gradient in
/// the [`knot_params`] layout (speed: 0). The marks are a person's reading of the photos and
/// the ring images hardly show a knot's inside, so step 2 keeps the strand close to them with
/// this penalty while it adjusts where the knot leaves the pith and its exact heading.
pub fn anchor_penalty(knot: &KnotConfig, marks: &[Vec3]) -> (f32, [f32; KNOT_PARAMS]) {
    let o = Vec3::from(knot.origin);
    let raw = Vec3::from(knot.direction);
    let len = raw.length().max(1e-9);
    let d = raw / len;
    let mut grad = [0.0; KNOT_PARAMS];
    let mut sum = 0.0;
    for &m in marks {
        let w = m - o;
        let along = w.dot(d);
        let q = w - along * d;
        sum += q.length_squared();
        let (g_o, g_d) = (-2.0 * q, -2.0 * along * q / len);
        for a in 0..3 {
            grad[a] += g_o[a];
            grad[3 + a] += g_d[a];
        }
    }
    (sum, grad)
}
