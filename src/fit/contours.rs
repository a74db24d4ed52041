//! Ring contours from ring localisation (ARL) images (Mokume 5.1.2, DESIGN section 5).
//!
//! As in the paper, the image is thresholded and the edges of the thresholded bands are the
//! contours: a pixel is a contour pixel where the ARL image is at or above the threshold and
//! one of its 4 neighbours is below it, so each ring gives two thin curves, one on either side
//! (both are iso-curves of G). Pixels within `border` of the image edge are then dropped (the
//! U-Net output is unreliable there, and the cut where a band leaves the image is not an
//! iso-curve); the rest are grouped into 8-connected components, and components of fewer than
//! `min_pixels` are dropped as specks. Edges rather than whole bands keep a broad, blurred
//! band (typical of faces nearly parallel to the rings) from outweighing the sharp rings of
//! the other faces in the loss. Pixels are lifted to 3D with the face table (DESIGN
//! section 2).

use glam::Vec3;

use super::config::ContourConfig;
use crate::frame::Face;
use crate::image2::Image2;
use crate::mask_patches::patch_at;

/// One connected ring edge on one face.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    pub face: Face,
    /// (row, col) of each pixel.
    pub pixels: Vec<[u32; 2]>,
    /// The 3D pixel centres on the cube face.
    pub points: Vec<Vec3>,
}

/// All contours of one ARL image (grey, square).
pub fn face_contours(arl: &Image2, face: Face, cfg: &ContourConfig) -> Vec<Contour> {
    let n = arl.width;
    let mask = ring_mask(arl, cfg);
    let mut seen = vec![false; n * n];
    let mut contours = Vec::new();
    for start in 0..n * n {
        if !mask[start] || seen[start] {
            continue;
        }
        let pixels = flood(&mask, &mut seen, start, n);
        if pixels.len() < cfg.min_pixels {
            continue;
        }
        let points = pixels
            .iter()
            .map(|&[r, c]| face.pixel_point(r as usize, c as usize, n))
            .collect();
        contours.push(Contour {
            face,
            pixels,
            points,
        });
    }
    contours
}

/// Edge pixels of the thresholded image, away from the border.
fn ring_mask(arl: &Image2, cfg: &ContourConfig) -> Vec<bool> {
    let n = arl.width;
    let ring = |r: usize, c: usize| arl.get(r, c, 0) >= cfg.threshold;
    let inner = |i: usize| i >= cfg.border && i + cfg.border < n;
    let mut mask = vec![false; n * n];
    for r in (0..n).filter(|&r| inner(r)) {
        for c in (0..n).filter(|&c| inner(c)) {
            let outside_next = (r > 0 && !ring(r - 1, c))
                || (r + 1 < n && !ring(r + 1, c))
                || (c > 0 && !ring(r, c - 1))
                || (c + 1 < n && !ring(r, c + 1));
            mask[r * n + c] = ring(r, c) && outside_next;
        }
    }
    mask
}

/// The 8-connected component of `mask` containing `start` as (row, column) pixels, marking
/// it in `seen`.
fn flood(mask: &[bool], seen: &mut [bool], start: usize, n: usize) -> Vec<[u32; 2]> {
    let mut pixels: Vec<[u32; 2]> = patch_at(mask, seen, start, n)
        .into_iter()
        .map(|i| [(i / n) as u32, (i % n) as u32])
        .collect();
    // Row-major order, so that thinning by stride spreads evenly over the curve.
    pixels.sort_unstable();
    pixels
}

/// Points every contour keeps at least (when it has them), however much the set is thinned.
const MIN_KEPT: usize = 8;

/// The thinning step of a contour of `len` points under a global `stride`.
fn thin_step(len: usize, stride: usize) -> usize {
    stride.min((len / MIN_KEPT).max(1))
}

/// Contours flattened for fast evaluation: all points in one array, contour `i` owning
/// `points[ranges[i].0 .. ranges[i].1]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContourSet {
    pub points: Vec<Vec3>,
    pub ranges: Vec<(usize, usize)>,
    pub faces: Vec<Face>,
}

impl ContourSet {
    /// Flattens contours, thinning each by the same stride so that at most about
    /// `max_points` points remain (every contour keeps at least a few points).
    pub fn new(contours: &[Contour], max_points: usize) -> Self {
        let total: usize = contours.iter().map(|c| c.points.len()).sum();
        let stride = total.div_ceil(max_points.max(1)).max(1);
        let mut set = ContourSet::default();
        for contour in contours {
            let start = set.points.len();
            let step = thin_step(contour.points.len(), stride);
            set.points.extend(contour.points.iter().step_by(step));
            set.ranges.push((start, set.points.len()));
            set.faces.push(contour.face);
        }
        set
    }

    pub fn len(&self) -> usize {
        self.ranges.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// The subset of points for which `keep` holds (contours left with fewer than 2 points are
    /// dropped).
    pub fn filter(&self, keep: impl Fn(Vec3) -> bool) -> Self {
        let mut out = ContourSet::default();
        for (&(a, b), &face) in self.ranges.iter().zip(&self.faces) {
            let start = out.points.len();
            out.points
                .extend(self.points[a..b].iter().copied().filter(|&p| keep(p)));
            if out.points.len() - start < 2 {
                out.points.truncate(start);
                continue;
            }
            out.ranges.push((start, out.points.len()));
            out.faces.push(face);
        }
        out
    }

    /// The same contours thinned to at most about `max_points` points.
    pub fn thinned(&self, max_points: usize) -> Self {
        let stride = self.points.len().div_ceil(max_points.max(1)).max(1);
        if stride == 1 {
            return self.clone();
        }
        let mut out = ContourSet::default();
        for (&(a, b), &face) in self.ranges.iter().zip(&self.faces) {
            let step = thin_step(b - a, stride);
            let start = out.points.len();
            out.points.extend(self.points[a..b].iter().step_by(step));
            out.ranges.push((start, out.points.len()));
            out.faces.push(face);
        }
        out
    }
}
