//! Knots from the marked knot centres (Mokume 5.2.4): a knot usually crosses the cube, so it
//! is marked where it enters and where it leaves (H11 marks its knot on faces C and F). The
//! line through the two marks is the initial knot axis; the strand starts at the point of
//! that line closest to the pith (branches grow out of the pith) and points towards the marks.
//! A knot marked on one face only starts on the pith at the point nearest the mark and goes
//! through it.
//!
//! Step 1 fits an undistorted field that cannot explain the bent rings around a knot, so
//! contour points near a marked knot are left out of it (`KnotFitConfig::exclusion`).
//!
//! Knot size: the ring images hardly show a knot's inside (the U-Net was not trained on
//! knots: the H11 knot is black in them), so the losses cannot tell how big a knot is and
//! tend to shrink it. The photos show it plainly as a dark disc, so the initial radius is
//! measured there ([`photo_knot_radius`]): the mean lightness in rings around the mark rises
//! from the knot's to the face's; the knot ends where it is halfway. The growth speed
//! follows as that radius over the mark's distance from the pith (Larsson's knot radius is
//! speed x stem radius).

use glam::Vec3;

use super::config::KnotFitConfig;
use crate::field::{KnotConfig, PithAxis};
use crate::image2::Image2;
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
    pub(crate) fn from_markers(markers: &[KnotMarker]) -> Option<Self> {
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
    fn initial_knot(&self, pith: &PithAxis, radius: f32) -> KnotConfig {
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

/// A marked knot and its radius at the marks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MarkedKnot {
    pub marks: KnotMarks,
    /// Cube units: the median of the photo estimates at the marks, or the config's radius.
    pub radius: f32,
}

impl MarkedKnot {
    /// The knot of one group of markers, sized from the photos of the marked faces that are
    /// loaded (`photos` indexed by `Face::index`).
    pub(crate) fn new(
        markers: &[KnotMarker],
        photos: &[Option<Image2>; 6],
        cfg: &KnotFitConfig,
    ) -> Option<Self> {
        let marks = KnotMarks::from_markers(markers)?;
        let estimates: Vec<f32> = markers
            .iter()
            .filter_map(|m| {
                let photo = photos[m.face.index()].as_ref()?;
                photo_knot_radius(photo, m, cfg.max_radius)
            })
            .collect();
        let radius = if estimates.is_empty() {
            cfg.radius
        } else {
            super::iso_loss::median(&estimates)
        };
        Some(Self { marks, radius })
    }

    /// The marked points.
    pub(crate) fn points(&self) -> Vec<Vec3> {
        match self.marks {
            KnotMarks::Through(a, b) => vec![a, b],
            KnotMarks::Single(a) => vec![a],
        }
    }

    /// Distance of `p` from the marked knot ([`KnotMarks::distance`]).
    pub(crate) fn distance(&self, p: Vec3) -> f32 {
        self.marks.distance(p)
    }

    /// The initial knot strand given the fitted pith.
    pub(crate) fn initial_knot(&self, pith: &PithAxis) -> KnotConfig {
        self.marks.initial_knot(pith, self.radius)
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

/// The radius (cube units) of the dark knot disc around `mark` in `photo`: the first radius
/// where the mean lightness of a 2-pixel ring reaches halfway from the knot centre's (within
/// 3 px) to the face's median; `None` if it never does within `max_radius` (cube units).
pub fn photo_knot_radius(photo: &Image2, mark: &KnotMarker, max_radius: f32) -> Option<f32> {
    let lum = photo.luminance();
    let n = lum.width;
    let max_px = (max_radius * n as f32).ceil() as usize;
    let rings = max_px / 2 + 1;
    let (mut sum, mut count) = (vec![0.0f64; rings], vec![0usize; rings]);
    for r in 0..n {
        for c in 0..n {
            let d = (r as f32 - mark.row).hypot(c as f32 - mark.col);
            let k = (d / 2.0) as usize;
            if k < rings {
                sum[k] += lum.get(r, c, 0) as f64;
                count[k] += 1;
            }
        }
    }
    let mean = |k: usize| (count[k] > 0).then(|| (sum[k] / count[k] as f64) as f32);
    let centre = mean(0).zip(mean(1)).map(|(a, b)| 0.5 * (a + b))?;
    let face = super::iso_loss::median(&lum.data);
    if face <= centre {
        return None;
    }
    let half = 0.5 * (centre + face);
    (2..rings)
        .find(|&k| mean(k).is_some_and(|m| m >= half))
        .map(|k| (2 * k + 1) as f32 / n as f32)
}
