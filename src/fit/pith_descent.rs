//! Step 1b: gradient descent on the pith axis (O, V) of the undistorted field G = r.
//!
//! Gradients are analytic. With d = p - O, v = V / |V| and q = d - (d . v) v (so r = |q|):
//!
//!   dr/dO = -q / r,      dr/dV = -(d . v) q / (r |V|),
//!
//! both perpendicular to v, so the descent never moves O along the axis or changes |V|; after
//! every step V is renormalised and O moved to the axis point closest to the cube centre,
//! which keeps the parameters well scaled. `tests/fit.rs` checks these gradients against
//! finite differences of the loss.

use glam::Vec3;

use super::adam::{Adam, cosine_lr};
use super::config::PithFitConfig;
use super::contours::ContourSet;
use super::iso_loss::iso_loss;
use crate::field::PithAxis;

/// The loss of G = r around the axis (O, V) and its gradient (dL/dO, dL/dV).
pub fn loss_and_gradient(set: &ContourSet, origin: Vec3, direction: Vec3) -> (f32, Vec3, Vec3) {
    let len = direction.length();
    let v = direction / len;
    let radii: Vec<f32> = set
        .points
        .iter()
        .map(|&p| {
            let d = p - origin;
            (d - d.dot(v) * v).length()
        })
        .collect();
    let mut dl_dr = vec![0.0; radii.len()];
    let loss = iso_loss(set, &radii, Some(&mut dl_dr));
    let (mut g_o, mut g_v) = (Vec3::ZERO, Vec3::ZERO);
    for ((&p, &r), &w) in set.points.iter().zip(&radii).zip(&dl_dr) {
        if w == 0.0 || r < 1e-9 {
            continue;
        }
        let d = p - origin;
        let along = d.dot(v);
        let q = d - along * v;
        g_o -= w * q / r;
        g_v -= w * along * q / (r * len);
    }
    (loss, g_o, g_v)
}

/// The axis through the point of `(origin, direction)` closest to the cube centre, its
/// direction turned back onto the cone of `max_tilt` (radians) around the y axis if it left
/// it (the coarse search's domain: faces B and D are end grain by convention).
pub(crate) fn normalised_axis(origin: Vec3, direction: Vec3, max_tilt: f32) -> (Vec3, Vec3) {
    let mut v = direction.normalize();
    if v.y < 0.0 {
        v = -v;
    }
    let tilt = v.y.clamp(-1.0, 1.0).acos();
    if tilt > max_tilt {
        let side = Vec3::new(v.x, 0.0, v.z).normalize_or(Vec3::X);
        v = max_tilt.cos() * Vec3::Y + max_tilt.sin() * side;
    }
    (origin - origin.dot(v) * v, v)
}

/// Adam on (O, V) from `start` for `cfg.iterations` steps, the direction kept within
/// `cfg.max_tilt_deg` of y; returns the best axis seen and its loss. The origin's step is scaled by the start's distance from the cube centre (at least
/// 1): a far axis needs large moves to change the ring curvature noticeably.
pub(crate) fn descend(
    set: &ContourSet,
    start: &PithAxis,
    cfg: &PithFitConfig,
    mut log: impl FnMut(usize, f32),
) -> (PithAxis, f32) {
    let (iterations, max_tilt) = (cfg.iterations, cfg.max_tilt_deg.to_radians());
    let (lr_origin, lr_direction) = (cfg.lr_origin, cfg.lr_direction);
    let (mut origin, mut dir) = normalised_axis(start.origin, start.dir, max_tilt);
    let origin_scale = origin.length().max(1.0);
    let mut adam = Adam::new(6);
    let mut best = (PithAxis::new(origin, dir), f32::INFINITY);
    for it in 0..=iterations {
        let (loss, g_o, g_v) = loss_and_gradient(set, origin, dir);
        log(it, loss);
        if loss < best.1 {
            best = (PithAxis::new(origin, dir), loss);
        }
        if it == iterations {
            break;
        }
        let mut params = [origin.x, origin.y, origin.z, dir.x, dir.y, dir.z];
        let grad = [g_o.x, g_o.y, g_o.z, g_v.x, g_v.y, g_v.z];
        let lo = cosine_lr(lr_origin * origin_scale, it, iterations, 0.05);
        let lv = cosine_lr(lr_direction, it, iterations, 0.05);
        adam.step_scaled(&mut params, &grad, |i| if i < 3 { lo } else { lv });
        (origin, dir) = normalised_axis(
            Vec3::new(params[0], params[1], params[2]),
            Vec3::new(params[3], params[4], params[5]),
            max_tilt,
        );
    }
    best
}
