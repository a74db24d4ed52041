//! Agreement of six face images along the 12 shared cube edges.
//!
//! Where two faces meet, a ring crossing the edge must appear at the same place on both
//! sides. Reading both images next to each edge through the face table and correlating the
//! two profiles measures how well a set of face images fits together under the table; a
//! wrong table (transposed or flipped images) scores lower. This is how the DESIGN table is
//! checked against the real Mokume ring images, and it is a useful sanity check for any new
//! sample folder.

use glam::Vec3;

use super::face::{Face, HALF};
use crate::image2::Image2;
use crate::series::pearson;

/// A re-indexing of every face image applied before the face table, used to compare the
/// DESIGN table with its transposed and flipped variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceImageTransform {
    Identity,
    Transpose,
    FlipHorizontal,
    FlipVertical,
    Rotate180,
    AntiTranspose,
}

impl FaceImageTransform {
    pub const ALL: [FaceImageTransform; 6] = [
        FaceImageTransform::Identity,
        FaceImageTransform::Transpose,
        FaceImageTransform::FlipHorizontal,
        FaceImageTransform::FlipVertical,
        FaceImageTransform::Rotate180,
        FaceImageTransform::AntiTranspose,
    ];

    /// Maps continuous pixel coordinates (row, col) of an n x n image.
    pub fn apply(self, row: f32, col: f32, n: usize) -> (f32, f32) {
        let last = (n - 1) as f32;
        match self {
            FaceImageTransform::Identity => (row, col),
            FaceImageTransform::Transpose => (col, row),
            FaceImageTransform::FlipHorizontal => (row, last - col),
            FaceImageTransform::FlipVertical => (last - row, col),
            FaceImageTransform::Rotate180 => (last - row, last - col),
            FaceImageTransform::AntiTranspose => (last - col, last - row),
        }
    }
}

/// The 12 cube edges as the pairs of faces that share them.
pub fn cube_edges() -> Vec<(Face, Face)> {
    let mut edges = Vec::with_capacity(12);
    for (i, &a) in Face::ALL.iter().enumerate() {
        for &b in &Face::ALL[i + 1..] {
            if a.normal().dot(b.normal()).abs() < 0.5 {
                edges.push((a, b));
            }
        }
    }
    edges
}

/// Points along the edge shared by faces `a` and `b`, at `n` pixel-centre positions.
fn edge_points(a: Face, b: Face, n: usize) -> Vec<Vec3> {
    let free = Vec3::ONE - a.normal().abs() - b.normal().abs();
    let base = (a.normal() + b.normal()) * HALF;
    (0..n)
        .map(|i| base + free * super::face::pixel_centre(i, n))
        .collect()
}

/// Mean of `image` just inside `face`, next to the edge it shares with `other`, sampled at
/// depths of 1.5, 2.5 and 3.5 pixels (the outermost pixel row is often damaged in photos).
fn edge_profile(
    image: &Image2,
    face: Face,
    other: Face,
    transform: FaceImageTransform,
    points: &[Vec3],
) -> Vec<f32> {
    let n = image.width;
    points
        .iter()
        .map(|&p| {
            let mut sum = 0.0;
            for depth in [1.5f32, 2.5, 3.5] {
                let q = p - other.normal() * (depth / n as f32);
                let (r, c) = face.point_pixel(q, n);
                let (r, c) = transform.apply(r, c, n);
                sum += image.bilinear(r, c, 0);
            }
            sum / 3.0
        })
        .collect()
}

/// Correlation of the two sides of each of the 12 cube edges (in [`cube_edges`] order) for
/// six square grey images indexed by [`Face::index`], read through the face table after
/// `transform`.
pub fn edge_agreement(images: &[Image2; 6], transform: FaceImageTransform) -> Vec<f32> {
    cube_edges()
        .into_iter()
        .map(|(a, b)| {
            let n = images[a.index()].width;
            let points = edge_points(a, b, n);
            let pa = edge_profile(&images[a.index()], a, b, transform, &points);
            let pb = edge_profile(&images[b.index()], b, a, transform, &points);
            pearson(&pa, &pb)
        })
        .collect()
}
