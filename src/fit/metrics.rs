//! Accuracy measures of a fit: pith axis errors against a known truth, the iso-contour error
//! as a distance, and the agreement of ring images.

use glam::Vec3;

use super::contours::ContourSet;
use super::iso_loss::contour_medians;
use crate::field::PithAxis;
use crate::frame::CM_PER_UNIT;
use crate::image2::Image2;
use crate::texture::SolidTexture;

/// Errors of a fitted pith axis against the true one: the distance (cm) between the two axes'
/// points closest to the cube centre, and the angle (degrees) between the two lines.
pub fn axis_errors(fit: &PithAxis, truth: &PithAxis) -> (f32, f32) {
    let centre_point = |a: &PithAxis| a.origin + (Vec3::ZERO - a.origin).dot(a.dir) * a.dir;
    let distance = centre_point(fit).distance(centre_point(truth)) * CM_PER_UNIT;
    let angle = fit.dir.dot(truth.dir).abs().min(1.0).acos().to_degrees();
    (distance, angle)
}

/// Mean distance (mm) from contour points to the iso-surface of G through their contour's
/// median: |G(p) - m_C| / |grad G(p)| (first order), with the gradient from central
/// differences. Unlike the loss (in years), this does not change when G is rescaled.
pub fn iso_error_mm(field: &dyn SolidTexture, set: &ContourSet) -> f32 {
    let g: Vec<f32> = set.points.iter().map(|&p| first(field, p)).collect();
    let medians = contour_medians(set, &g);
    let h = 1e-3;
    let mut sum = 0.0f64;
    for (&(a, b), &m) in set.ranges.iter().zip(&medians) {
        for (&p, &gp) in set.points[a..b].iter().zip(&g[a..b]) {
            let grad = Vec3::new(
                first(field, p + Vec3::X * h) - first(field, p - Vec3::X * h),
                first(field, p + Vec3::Y * h) - first(field, p - Vec3::Y * h),
                first(field, p + Vec3::Z * h) - first(field, p - Vec3::Z * h),
            ) / (2.0 * h);
            sum += ((gp - m).abs() / grad.length().max(1e-6)) as f64;
        }
    }
    let mm_per_unit = CM_PER_UNIT * 10.0;
    (sum / set.points.len().max(1) as f64) as f32 * mm_per_unit
}

fn first(field: &dyn SolidTexture, p: Vec3) -> f32 {
    crate::texture::first_channel(field, p)
}

/// Pearson correlation of two grey images of the same size, leaving out `border` pixels at
/// each edge: [`shifted_correlation`] without shifts.
pub fn image_correlation(a: &Image2, b: &Image2, border: usize) -> f32 {
    shifted_correlation(a, b, border, 0)
}

/// The best [`image_correlation`] over shifts of up to a few pixels (the ring metric's).
pub use crate::metrics::ring::shifted_correlation;

/// How well a fitted field predicts a known one: the correlation of their ring images I(G)
/// at `size` px, as [mean over the six faces, cut1, cut2] (the hidden validation cuts).
pub fn truth_ring_correlations(
    fitted: &crate::field::GrowthField,
    truth: &crate::field::GrowthField,
    size: usize,
) -> [f32; 3] {
    use crate::field::RingImage;
    use crate::frame::{Face, Plane};
    use crate::slice::{slice_face, slice_plane};
    let faces = Face::ALL
        .iter()
        .map(|&f| {
            image_correlation(
                &slice_face(&RingImage(fitted), f, size),
                &slice_face(&RingImage(truth), f, size),
                0,
            )
        })
        .sum::<f32>()
        / Face::ALL.len() as f32;
    let cut = |plane: Plane| {
        image_correlation(
            &slice_plane(&RingImage(fitted), &plane, size, size),
            &slice_plane(&RingImage(truth), &plane, size, size),
            0,
        )
    };
    [faces, cut(Plane::cut1()), cut(Plane::cut2())]
}
