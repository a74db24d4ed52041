//! One knot strand (Larsson et al. 2022): its time field and the smoothing it adds to the
//! stem's, for alive and dead knots.
//!
//! Time field: t_b = years_per_unit x distance(p, strand) / speed, the strand being the ray
//! from `origin` along `direction` (points behind the start measure to the start point).
//! Alive: delta = smin(t_s, t_b, k(t_s - t_b)) - min(t_s, t_b) with the adaptive exponent.
//! Dead (stem time t_s past the time of death, tau = t_s - death years later):
//! - the knot stops thickening: t_b' = t_b + tau (its boundary t_b' = t_s freezes at the
//!   radius it had at death);
//! - the union tightens: k' = k + dead_sharpen x tau;
//! - the smoothing is scaled by f(tau) going smoothly from 1 at death to `dead_factor`
//!   (negative: the rings bend the other way, towards the pith) over `dead_transition` years;
//! - butterfly: |f| is weighted by (1 - b) + b |cos beta|, beta the angle around the knot axis
//!   from the pith direction, so the distortion is strongest above and below the knot.
//!
//! The knot's influence fades out between `reach[0]` and `reach[1]` knot radii from its axis
//! (the knot radius being speed x stem radius), as the reference shader's distance range does,
//! so that a knot does not shift rings across the whole cube.

use glam::Vec3;

use super::config::KnotConfig;
use super::smin::{adaptive_k, smoothing, smoothstep};

#[derive(Clone, Debug, PartialEq)]
pub struct Knot {
    pub origin: Vec3,
    /// Unit direction of the strand.
    pub dir: Vec3,
    /// Unit vector perpendicular to `dir`, towards the pith direction (beta = 0, "above").
    pub up: Vec3,
    /// dir x up (beta = pi/2, the knot's side).
    pub side: Vec3,
    pub speed: f32,
    pub k_stem: f32,
    pub k_knot: f32,
    pub k_width: f32,
    pub reach: [f32; 2],
    pub death: Option<f32>,
    pub dead_factor: f32,
    pub dead_transition: f32,
    pub dead_sharpen: f32,
    pub butterfly: f32,
}

/// What one knot contributes at a point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KnotSample {
    /// Knot time t_b (years), after the dead-knot expansion stop.
    pub time: f32,
    /// Smoothing added to the minimum (negative: bulge towards the knot; positive: inverted).
    pub delta: f32,
    /// Distance from the strand (cube units).
    pub distance: f32,
    /// Angle around the strand from the pith direction, in [0, 2 pi).
    pub beta: f32,
    /// The point was laid down after the knot died (t_s > death).
    pub after_death: bool,
}

impl Knot {
    /// `pith_dir` orients the butterfly angle. Configs are validated before this is called.
    pub fn new(cfg: &KnotConfig, pith_dir: Vec3) -> Self {
        let dir = Vec3::from(cfg.direction).normalize();
        let mut up = pith_dir - pith_dir.dot(dir) * dir;
        if up.length_squared() < 1e-8 {
            up = dir.any_orthonormal_vector();
        }
        let up = up.normalize();
        Self {
            origin: Vec3::from(cfg.origin),
            dir,
            up,
            side: dir.cross(up),
            speed: cfg.speed,
            k_stem: cfg.k_stem,
            k_knot: cfg.k_knot,
            k_width: cfg.k_width,
            reach: cfg.reach,
            death: cfg.death,
            dead_factor: cfg.dead_factor,
            dead_transition: cfg.dead_transition,
            dead_sharpen: cfg.dead_sharpen,
            butterfly: cfg.butterfly,
        }
    }

    /// Offset from the nearest point of the strand (a ray) to `p`.
    pub fn offset(&self, p: Vec3) -> Vec3 {
        let d = p - self.origin;
        let along = d.dot(self.dir).max(0.0);
        d - along * self.dir
    }

    /// The knot's contribution at `p`, given the stem time there and years per unit.
    pub fn sample(&self, p: Vec3, stem_time: f32, years_per_unit: f32) -> KnotSample {
        let offset = self.offset(p);
        let distance = offset.length();
        let mut beta = offset.dot(self.side).atan2(offset.dot(self.up));
        if beta < 0.0 {
            beta += std::f32::consts::TAU;
        }
        let mut time = years_per_unit * distance / self.speed;
        let mut k = adaptive_k(stem_time - time, self.k_stem, self.k_knot, self.k_width);
        let mut factor = 1.0;
        let tau = self.death.map(|d| stem_time - d).filter(|&t| t > 0.0);
        if let Some(tau) = tau {
            time += tau;
            k += self.dead_sharpen * tau;
            let f = 1.0 + (self.dead_factor - 1.0) * smoothstep(0.0, self.dead_transition, tau);
            let wings = (1.0 - self.butterfly) + self.butterfly * beta.cos().abs();
            factor = f * wings;
        }
        let knot_radius = self.speed * stem_time / years_per_unit;
        let fade = 1.0
            - smoothstep(
                self.reach[0] * knot_radius,
                self.reach[1] * knot_radius + 1e-4,
                distance,
            );
        KnotSample {
            time,
            delta: factor * fade * smoothing(stem_time, time, k),
            distance,
            beta,
            after_death: tau.is_some(),
        }
    }
}
