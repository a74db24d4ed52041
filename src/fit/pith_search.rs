//! Step 1a: coarse search of pith axes on the undistorted field G = r (Mokume 5.2.3).
//!
//! The iso-contour loss of G = r has many local minima in (O, V) (for example an axis on the
//! wrong side of the cube curves the rings the wrong way), so descent starts from the best of
//! a deterministic grid of candidates: directions within `max_tilt_deg` of the y axis (the
//! end-grain faces B and D are by convention across the pith), spread evenly over the
//! spherical cap, and for each direction, axes passing the cube centre at the configured
//! distances (up to 10 units = 40 cm, so near-parallel rings of a far pith are covered) at
//! evenly spaced positions around it. An axis and its reverse give the same G = r, so only
//! one hemisphere of directions is searched.

use glam::Vec3;
use rayon::prelude::*;

use super::config::PithFitConfig;
use super::contours::ContourSet;
use super::iso_loss::iso_loss;
use crate::field::PithAxis;

/// A scored candidate axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    pub axis: PithAxis,
    /// Iso-contour loss of G = r (cube units).
    pub loss: f32,
}

/// Candidate directions: unit vectors within `max_tilt` of +y, about `step` apart.
pub(crate) fn candidate_directions(cfg: &PithFitConfig) -> Vec<Vec3> {
    let step = cfg.direction_step_deg.to_radians();
    let tilts = (cfg.max_tilt_deg / cfg.direction_step_deg).floor() as usize;
    let mut dirs = vec![Vec3::Y];
    for k in 1..=tilts {
        let tilt = k as f32 * step;
        let around = ((std::f32::consts::TAU * tilt.sin() / step).round() as usize).max(1);
        for j in 0..around {
            let psi = j as f32 * std::f32::consts::TAU / around as f32;
            dirs.push(Vec3::new(
                tilt.sin() * psi.cos(),
                tilt.cos(),
                tilt.sin() * psi.sin(),
            ));
        }
    }
    dirs
}

/// All candidate axes: each direction at each distance and position around the cube centre.
pub(crate) fn candidate_axes(cfg: &PithFitConfig) -> Vec<PithAxis> {
    let mut axes = Vec::new();
    for dir in candidate_directions(cfg) {
        let (e1, e2) = dir.any_orthonormal_pair();
        for &d in &cfg.distances {
            let around = if d == 0.0 { 1 } else { cfg.offset_azimuths };
            for k in 0..around {
                let alpha = k as f32 * std::f32::consts::TAU / around as f32;
                let origin = d * (alpha.cos() * e1 + alpha.sin() * e2);
                axes.push(PithAxis::new(origin, dir));
            }
        }
    }
    axes
}

/// Iso-contour loss of the undistorted field around `axis`.
pub(crate) fn axis_loss(set: &ContourSet, axis: &PithAxis) -> f32 {
    let radii: Vec<f32> = set.points.iter().map(|&p| axis.radius(p)).collect();
    iso_loss(set, &radii, None)
}

/// Scores every candidate on `set` and returns the `keep` best that differ from each other
/// ([`axes_differ`]), best first.
pub fn search(set: &ContourSet, cfg: &PithFitConfig, keep: usize) -> Vec<Candidate> {
    let mut scored: Vec<Candidate> = candidate_axes(cfg)
        .into_par_iter()
        .map(|axis| Candidate {
            loss: axis_loss(set, &axis),
            axis,
        })
        .collect();
    scored.sort_by(|a, b| a.loss.total_cmp(&b.loss));
    let mut best: Vec<Candidate> = Vec::with_capacity(keep);
    for c in scored {
        if best.len() == keep {
            break;
        }
        if best.iter().all(|b| axes_differ(&b.axis, &c.axis)) {
            best.push(c);
        }
    }
    best
}

/// Whether two axes differ by more than 5 degrees in direction or 10% of their distance from
/// the cube centre in position.
pub fn axes_differ(a: &PithAxis, b: &PithAxis) -> bool {
    let angle = a.dir.dot(b.dir).abs().min(1.0).acos();
    let gap = a.radius(Vec3::ZERO).max(b.radius(Vec3::ZERO));
    angle > 5f32.to_radians() || (a.origin - b.origin).length() > 0.1 * gap.max(0.5)
}
