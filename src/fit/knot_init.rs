//! Knots from the marked knot centres (Mokume 5.2.4): a knot usually crosses the cube, so it
//! is marked where it enters and where it leaves (H11 marks its knot on faces C and F). The
//! line through the two marks is the initial knot axis; the strand starts at the point of
//! that line closest to the pith (branches grow out of the pith) and points towards the marks.
//! A knot marked on one face only starts on the pith at the point nearest the mark and goes
//! through it.
//!
//! Step 1 fits an undistorted field that cannot explain the bent rings around a knot, so
//! contour points near a marked knot are left out of it (`KnotFitConfig::exclusion`).

use glam::Vec3;

use crate::field::{KnotConfig, PithAxis};
use crate::sample::KnotMarker;

/// Growth speeds the fit keeps knots within (`knot_fit::set_knot_params` clamps the same way).
pub const MIN_SPEED: f32 = 0.02;
pub const MAX_SPEED: f32 = 0.8;

/// Where a marked knot runs, before the pith is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KnotMarks {
    /// Entry and exit marks (the two markers farthest apart).
    Through(Vec3, Vec3),
    /// A single mark.
    Single(Vec3),
}

impl KnotMarks {
    /// The marks of one knot (its markers share a grey value); `None` without markers.
    pub fn from_markers(markers: &[KnotMarker]) -> Option<Self> {
        let points: Vec<Vec3> = markers.iter().map(|m| m.point).collect();
        match points.len() {
            0 => None,
            1 => Some(KnotMarks::Single(points[0])),
            _ => {
                let mut best = (points[0], points[1]);
                for (i, &a) in points.iter().enumerate() {
                    for &b in &points[i + 1..] {
                        if a.distance(b) > best.0.distance(best.1) {
                            best = (a, b);
                        }
                    }
                }
                Some(KnotMarks::Through(best.0, best.1))
            }
        }
    }

    /// Distance of `p` from the marked knot: from the line through the marks, or from the
    /// single mark.
    pub fn distance(&self, p: Vec3) -> f32 {
        match *self {
            KnotMarks::Through(a, b) => {
                let d = (b - a).normalize();
                let q = p - a;
                (q - q.dot(d) * d).length()
            }
            KnotMarks::Single(a) => p.distance(a),
        }
    }

    /// The initial knot strand given the fitted pith, with radius `radius` (cube units) at
    /// the marks: the growth speed is that radius over the marks' distance from the pith
    /// (Larsson's knot radius is speed x stem radius).
    pub fn initial_knot(&self, pith: &PithAxis, radius: f32) -> KnotConfig {
        let (origin, direction) = match *self {
            KnotMarks::Through(a, b) => {
                let start = closest_on_line_to_axis(a, b - a, pith);
                let mid = 0.5 * (a + b);
                let mut dir = (b - a).normalize();
                if dir.dot(mid - start) < 0.0 {
                    dir = -dir;
                }
                (start, dir)
            }
            KnotMarks::Single(a) => {
                let start = pith.origin + (a - pith.origin).dot(pith.dir) * pith.dir;
                let dir = (a - start).normalize_or(Vec3::Z);
                (start, dir)
            }
        };
        let mut knot = KnotConfig::alive(origin.into(), direction.into());
        knot.speed = (radius / self.pith_distance(pith).max(1e-3)).clamp(MIN_SPEED, MAX_SPEED);
        knot
    }

    /// Mean distance of the marks from the pith axis.
    fn pith_distance(&self, pith: &PithAxis) -> f32 {
        match *self {
            KnotMarks::Through(a, b) => 0.5 * (pith.radius(a) + pith.radius(b)),
            KnotMarks::Single(a) => pith.radius(a),
        }
    }
}

/// The point of the line (a + s d) closest to the pith axis (a's foot point if parallel).
fn closest_on_line_to_axis(a: Vec3, d: Vec3, pith: &PithAxis) -> Vec3 {
    let d = d.normalize();
    let w = a - pith.origin;
    let b = d.dot(pith.dir);
    let denom = 1.0 - b * b;
    if denom < 1e-6 {
        return a;
    }
    let s = (b * w.dot(pith.dir) - w.dot(d)) / denom;
    a + s * d
}
