//! The direction the fibres run, measured on the face photos.
//!
//! Why: the fitted pith axis explains where the rings cross the faces, not which way the
//! fibres run. On CN03 the rings of the flat-sawn faces A and F cross the faces diagonally and
//! the fit explains that with a tilted axis ((0.40, 0.91, 0.13) with all six faces,
//! (-0.73, 0.61, 0.31) without F), while the photos' pore dashes run straight up A and F and
//! 15 degrees off vertical on C and E: fibres along (0.00, 0.96, 0.27). Anything that draws
//! fibres or vessels along the pith axis (the NCA's grain noise) then draws them 20-50 degrees
//! off on those faces.
//!
//! Each used face gives, from the structure tensor of its high-passed lightness (pores, fibre
//! streaks; the ring-scale shading removed), the dominant gradient direction G (lifted into the
//! cube frame) and how oriented the face is (coherence c in [0, 1]). Dashes run across G, so
//! the fibre direction t is the unit vector minimising sum_f w_f (t . G_f)^2, the eigenvector
//! of the smallest eigenvalue of M = sum_f w_f G_f G_f^T. The weight w_f = c_f (1 - (n_f . a)^2)
//! drops faces the fitted axis a crosses (end grain, whose orientation comes from rings and
//! rays, not fibres). The weights come from the axis, not from the estimate itself: iterated
//! on the estimate, H11 without F ran away to fibres along x (the faces that disagreed were
//! weighted out one by one).
//!
//! The answer is kept only when the photos determine it: M's smallest eigenvalue must be
//! under [`MAX_EIGEN_RATIO`] of the middle one, and the middle one at least [`MIN_EVIDENCE`]
//! (two independent side-grain faces, clearly oriented, agreeing); and only when it disagrees
//! with the fitted axis by more than [`AGREEMENT_DEG`]: the axis, fitted to every ring
//! contour, is the better estimate of where vessels run when the two agree (see the
//! constant). Measured (ratio, evidence): CN03 0.001-0.005 and 0.38-0.78 for six faces and
//! every five, kept; the demo chestnut 0.001, 4.6 degrees from its fitted axis, so the axis
//! stays; H11 0.11-0.18 and 0.09-0.18 (pale softwood whose straightest fine lines are
//! diagonal sanding marks): not determined, the axis stands.

use glam::{DMat3, DVec3, Vec3};

use crate::symmetric_eigen::symmetric_eigen;

use crate::frame::Face;
use crate::image_filter::{gaussian_gradient, high_pass};
use crate::image2::Image2;

/// Side the photos are measured at (the sigmas are in pixels at this size).
const SIDE: usize = 256;
/// Width of the blur subtracted from the lightness: keeps pores and fibres, drops rings.
const HIGH_PASS_SIGMA: f32 = 3.0;
/// Gradient scale: a pore's width.
const GRADIENT_SIGMA: f32 = 0.7;
/// Largest accepted ratio of M's smallest to middle eigenvalue (see the module doc).
pub const MAX_EIGEN_RATIO: f64 = 0.05;
/// Least middle eigenvalue of M: the weaker direction across the fibres must be pinned by
/// the equivalent of one fully weighted face of coherence 0.25. A small ratio alone is not
/// enough: H11 without F, weighted from the y axis, had ratio 0.01 because its middle
/// eigenvalue was tiny too (one knotty face of coherence 0.08 "pinned" fibres along x).
/// Measured, weighted from the y axis, all six faces and every five: CN03 0.38-0.78 (0.38
/// without F, where A alone pins x), H11 0.09-0.18.
pub const MIN_EVIDENCE: f64 = 0.25;
/// Angle within which the measurement is taken to confirm the fitted axis: twice the error
/// measured on the procedural chestnut, whose vessels run along its axis while the photos'
/// fine texture (vessels and fibres bent by the tilted growth layers) reads 4 degrees off.
/// Used there, the measured direction made the NCA's cuts worse (cut1 aniso 0.40 against
/// the truth's 0.29, the axis's 0.30; docs/DESIGN.md "NCA study", row f1).
pub const AGREEMENT_DEG: f32 = 8.0;

/// What the fit does with a measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FibreChoice {
    /// The photos' direction differs from the axis: the fibres run along it.
    Measured(Vec3),
    /// The photos confirm the axis within [`AGREEMENT_DEG`] (the angle between them).
    AlongAxis(f32),
    /// The photos do not determine a direction.
    Undetermined,
}

/// What one face says about the fibres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceGrain {
    pub face: Face,
    /// Unit dominant gradient direction of the fine texture, cube frame (sign arbitrary).
    pub across: Vec3,
    /// How oriented the fine texture is: (lambda1 - lambda2) / (lambda1 + lambda2).
    pub coherence: f32,
}

/// The measured fibre direction and how well the photos determine it.
#[derive(Clone, Debug, PartialEq)]
pub struct FibreMeasure {
    /// Unit direction, on the pith direction's side.
    pub direction: Vec3,
    /// Smallest over middle eigenvalue of the final M (0: exactly determined).
    pub eigen_ratio: f64,
    /// The middle eigenvalue of M: the coherence-weighted evidence that pins the weaker of the
    /// two directions across the fibres.
    pub evidence: f64,
    pub faces: Vec<FaceGrain>,
}

impl FibreMeasure {
    /// Whether the photos determine the direction ([`MAX_EIGEN_RATIO`], [`MIN_EVIDENCE`]).
    pub fn is_determined(&self) -> bool {
        self.eigen_ratio < MAX_EIGEN_RATIO && self.evidence >= MIN_EVIDENCE
    }

    /// The choice against the fitted `axis` (see the module doc).
    pub fn choice(&self, axis: Vec3) -> FibreChoice {
        if !self.is_determined() {
            return FibreChoice::Undetermined;
        }
        let cos = self.direction.dot(axis.normalize_or(Vec3::Y)).abs();
        let degrees = cos.clamp(0.0, 1.0).acos().to_degrees();
        if degrees <= AGREEMENT_DEG {
            FibreChoice::AlongAxis(degrees)
        } else {
            FibreChoice::Measured(self.direction)
        }
    }
}

/// The fibre direction of the used `faces` of `photos` (RGB, any square size), the faces
/// weighted by the fitted axis `pith` (see the module doc); `rings` (ring-localisation images, bright on the ring
/// boundaries) mask the boundaries where given. `None` when no used face has a photo.
pub fn measure_fibre_direction(
    photos: &[Option<Image2>; 6],
    rings: &[Option<Image2>; 6],
    faces: &[Face],
    pith: Vec3,
) -> Option<FibreMeasure> {
    let grains: Vec<FaceGrain> = faces
        .iter()
        .filter_map(|&f| {
            let photo = photos[f.index()].as_ref()?;
            Some(face_grain(f, photo, rings[f.index()].as_ref()))
        })
        .collect();
    if grains.is_empty() {
        return None;
    }
    let axis = pith.normalize_or(Vec3::Y).as_dvec3();
    let (v, [low, mid]) = smallest_direction(&weighted_tensor(&grains, axis));
    let t = if v.dot(axis) < 0.0 { -v } else { v };
    Some(FibreMeasure {
        direction: t.as_vec3(),
        eigen_ratio: if mid > 1e-12 { low / mid } else { 1.0 },
        evidence: mid,
        faces: grains,
    })
}

/// The dominant gradient direction and coherence of one photo's fine texture, each pixel
/// weighted by (1 - ring image)^2: a ring boundary's own edge is a long line that would read
/// as fibres on faces the rings cross diagonally (on H11 it tilted the estimate 30 degrees
/// before this mask; on CN03 and the chestnut sample the mask moves it under 1 degree).
pub(crate) fn face_grain(face: Face, photo: &Image2, rings: Option<&Image2>) -> FaceGrain {
    let light = photo.with_channels(3).resized(SIDE, SIDE).luminance();
    let weight: Vec<f64> = match rings {
        Some(r) => r
            .channel(0)
            .resized(SIDE, SIDE)
            .data
            .iter()
            .map(|&v| (1.0 - v.clamp(0.0, 1.0) as f64).powi(2))
            .collect(),
        None => vec![1.0; SIDE * SIDE],
    };
    let fine = high_pass(&light, HIGH_PASS_SIGMA);
    let [gx, gy] = gaussian_gradient(&fine, GRADIENT_SIGMA);
    let (mut xx, mut xy, mut yy) = (0f64, 0f64, 0f64);
    for ((&a, &b), &w) in gx.data.iter().zip(&gy.data).zip(&weight) {
        let (a, b) = (a as f64, b as f64);
        xx += w * a * a;
        xy += w * a * b;
        yy += w * b * b;
    }
    let energy = xx + yy;
    let coherence = if energy > 1e-20 {
        ((xx - yy).hypot(2.0 * xy) / energy) as f32
    } else {
        0.0
    };
    // Angle of the dominant gradient in image axes (x = columns, y = rows).
    let angle = 0.5 * (2.0 * xy).atan2(xx - yy);
    let (column, row) = image_axes(face);
    FaceGrain {
        face,
        across: (column * angle.cos() as f32 + row * angle.sin() as f32).normalize(),
        coherence,
    }
}

/// The cube-frame unit directions of a face image's columns (left to right) and rows (top to
/// bottom), from the face table.
fn image_axes(face: Face) -> (Vec3, Vec3) {
    let origin = face.point(0.0, 0.0);
    (
        (face.point(0.5, 0.0) - origin).normalize(),
        (face.point(0.0, 0.5) - origin).normalize(),
    )
}

/// M = sum_f c_f (1 - (n_f . a)^2) G_f G_f^T for the unit axis a.
fn weighted_tensor(grains: &[FaceGrain], axis: DVec3) -> DMat3 {
    let mut m = DMat3::ZERO;
    for g in grains {
        let n = g.face.normal().as_dvec3();
        let w = g.coherence as f64 * (1.0 - n.dot(axis).powi(2)).max(0.0);
        let a = g.across.as_dvec3();
        m += DMat3::from_cols(a * a.x, a * a.y, a * a.z) * w;
    }
    m
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix, with the
/// smallest and the middle eigenvalue (clamped at 0).
fn smallest_direction(m: &DMat3) -> (DVec3, [f64; 2]) {
    let (values, vectors) = symmetric_eigen(m); // ascending
    (
        vectors.col(0).normalize(),
        [values[0].max(0.0), values[1].max(0.0)],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_finds_the_smallest_eigenvector() {
        // The smallest eigenvector of R diag(3, 1, 0.2) R^T is R's third column.
        let (r, m) = crate::symmetric_eigen::tests::rotated_diagonal();
        let (v, [low, mid]) = smallest_direction(&m);
        assert!(v.dot(r.z_axis).abs() > 1.0 - 1e-9, "{v} vs {}", r.z_axis);
        assert!(
            (low - 0.2).abs() < 1e-9 && (mid - 1.0).abs() < 1e-9,
            "{low} {mid}"
        );
    }

    /// Dashes along `t` drawn on a face: a grey image whose value changes only across the
    /// projection of `t` (stripes one pore wide, a few px apart).
    fn streaks(face: Face, t: Vec3) -> Image2 {
        let (column, row) = image_axes(face);
        let d = glam::Vec2::new(t.dot(column), t.dot(row)).normalize();
        let across = glam::Vec2::new(-d.y, d.x);
        let mut img = Image2::filled(SIDE, SIDE, 3, 0.0);
        for r in 0..SIDE {
            for c in 0..SIDE {
                let s = across.dot(glam::Vec2::new(c as f32, r as f32));
                let v = 0.6 + 0.2 * (s * 1.3).sin() * (s * 0.31).cos();
                img.pixel_mut(r, c).fill(v);
            }
        }
        img
    }

    #[test]
    fn streaks_on_side_grain_give_back_their_direction() {
        let t = Vec3::new(0.1, 0.95, 0.3).normalize();
        let photos: [Option<Image2>; 6] = std::array::from_fn(|i| {
            let face = Face::ALL[i];
            (face.normal().dot(t).abs() < 0.5).then(|| streaks(face, t))
        });
        let m = measure_fibre_direction(&photos, &Default::default(), &Face::ALL, Vec3::Y).unwrap();
        let angle = m.direction.dot(t).clamp(-1.0, 1.0).acos().to_degrees();
        assert!(angle < 1.0, "{:?} vs {t}: {angle} degrees", m.direction);
        assert!(m.is_determined(), "{m:?}");
    }

    #[test]
    fn one_oriented_face_does_not_determine_the_direction() {
        let t = Vec3::new(0.3, 0.95, 0.0).normalize();
        let mut photos: [Option<Image2>; 6] = Default::default();
        photos[Face::A.index()] = Some(streaks(Face::A, t));
        let m = measure_fibre_direction(&photos, &Default::default(), &Face::ALL, Vec3::Y).unwrap();
        assert!(!m.is_determined(), "{m:?}");
        let none: [Option<Image2>; 6] = Default::default();
        assert!(measure_fibre_direction(&none, &none, &Face::ALL, Vec3::Y).is_none());
    }
}
