//! Fits the grain shading (`field::grain_shading`) from the mean colours of the fitted faces:
//! per channel a least-squares line m_f = side + (end - side) w_f over the faces' end-grain
//! weights w_f = (n_f . t)^2. The fit (`fit::run`) first divides each face's mean by what
//! the fitted base colour shows on that face ([`face_content`]), so that the wood on a face
//! (a dark knot, more latewood) is not read as lighting or grain.
//!
//! Six (or five) face means are few, and photos also differ by lighting: on H11 the two
//! end-grain faces differ by 21-45 levels, one lighter and one darker than the side faces.
//! So the line is kept only when the faces show it: the slope of their mean lightness must
//! be at least `MIN_T` standard errors from zero (a t-test with n - 2 degrees of freedom,
//! about 88 % two-sided for 4; 95 % would need 2.78), and only when both kinds of grain
//! are seen on at least two faces each (`MIN_FACES_PER_GRAIN`). Measured (BENCHMARKS.md,
//! with the content correction): CN03 |t| 3.4 with six faces, and 2.5-5.7 for the
//! five-face subsets that keep both end faces; H11 |t| 1.3 with six faces and 1.0-1.8 for
//! those subsets, so H11 keeps the plain mean.

use glam::Vec3;

use super::white_balance::white_balance;
use crate::field::{BaseColour, GrainShading, GrowthField, WhiteBalance};
use crate::frame::Face;
use crate::image2::Image2;

/// Smallest |t| of the lightness slope for the shading to be kept.
pub const MIN_T: f32 = 2.0;

/// Smallest spread of the weights, sum of (w - mean w)^2: the faces must include side and
/// end grain for a slope to mean anything (one end-grain face among five gives 0.8).
const MIN_WEIGHT_SPREAD: f32 = 0.25;

/// Fewest faces on each side of the grain (end-grain weight at least 0.5, and below it).
/// With one end-grain face the slope is that one photo against the side faces: its
/// exposure passes for grain, and the residuals (of side faces only) cannot show it. H11
/// without B kept a shading from D alone (|t| 2.3, end grain 11 % darker) and predicted B
/// 14 levels too dark (base colour dE_mean 10.5 instead of 5.3 plain); CN03 without D
/// gained from B alone (4.7 instead of 6.7). One sample each way; the rule follows the
/// statistics, not the score.
const MIN_FACES_PER_GRAIN: usize = 2;

/// The fitted line, whether or not the photos show it.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingEstimate {
    pub model: GrainShading,
}

impl ShadingEstimate {
    /// The photos show the shading: |t| >= `MIN_T`.
    pub fn is_shown(&self) -> bool {
        self.model.t_statistic.abs() >= MIN_T
    }

    /// The model when the photos show it.
    pub fn kept(&self) -> Option<GrainShading> {
        self.is_shown().then(|| self.model.clone())
    }
}

/// Content of average wood (white-balanced): faces that all have it need no correction.
pub const NEUTRAL_CONTENT: [f32; 3] = [0.5; 3];

/// Points per side at which [`face_content`] samples a face (4 096 per face).
const CONTENT_GRID: usize = 64;

/// The mean white-balanced base colour (no face offset) that the fitted bars give each of
/// `faces`: what the wood itself shows there, darker for a face with a dark knot or more
/// latewood. Other faces get [`NEUTRAL_CONTENT`].
pub fn face_content(colour: &BaseColour, field: &GrowthField, faces: &[Face]) -> [[f32; 3]; 6] {
    let n = CONTENT_GRID;
    let mut content = [NEUTRAL_CONTENT; 6];
    for &face in faces {
        let mut sum = [0.0f64; 3];
        for r in 0..n {
            for c in 0..n {
                let rgb = colour.colour(&field.sample(face.pixel_point(r, c, n)));
                for (s, v) in sum.iter_mut().zip(rgb) {
                    *s += v as f64;
                }
            }
        }
        content[face.index()] = sum.map(|s| (s / (n * n) as f64) as f32);
    }
    content
}

/// Estimates the grain shading of `wb`'s fitted `faces` and keeps it in `wb` when the
/// photos show it; returns the estimate (`None`: undetermined). Each face's photo mean is
/// first divided by what its wood shows relative to the faces' average (`content`, from
/// [`face_content`]; pass [`NEUTRAL_CONTENT`] for none), so a side face darkened by a knot
/// does not hide the grain: on a synthetic softwood photographed with end grain 0.85 the
/// plain means gave |t| 1.9 (not kept) because its two knotty side faces were 9-13 % darker
/// than the others.
pub fn add_grain_shading(
    wb: &mut WhiteBalance,
    faces: &[Face],
    fibre: Vec3,
    content: &[[f32; 3]; 6],
) -> Option<ShadingEstimate> {
    // Relative to the faces' average content: only differences between faces are corrected,
    // so the line keeps the photos' level (the bars' median sits above the mean).
    let average: [f32; 3] = std::array::from_fn(|c| {
        faces.iter().map(|f| content[f.index()][c]).sum::<f32>() / faces.len().max(1) as f32
    });
    let means: Vec<(Face, [f32; 3])> = faces
        .iter()
        .map(|&f| {
            let (m, k) = (wb.face_means[f.index()], content[f.index()]);
            (
                f,
                std::array::from_fn(|c| m[c] * average[c] / k[c].max(1e-3)),
            )
        })
        .collect();
    let estimate = estimate_grain_shading(&means, fibre);
    wb.grain = estimate.as_ref().and_then(ShadingEstimate::kept);
    estimate
}

/// The white balance of the photos of `faces` (indexed by `Face::index`) with the grain
/// shading from their plain means (no content correction), and the estimate.
pub fn shaded_white_balance(
    photos: &[Option<Image2>; 6],
    faces: &[Face],
    fibre: Vec3,
) -> (WhiteBalance, Option<ShadingEstimate>) {
    let mut wb = white_balance(photos, faces);
    let estimate = add_grain_shading(&mut wb, faces, fibre, &[NEUTRAL_CONTENT; 6]);
    (wb, estimate)
}

/// The estimate from the mean real RGB of each fitted face and the fibre direction; `None`
/// when the faces cannot determine it (fewer than two faces of either kind of grain).
pub(crate) fn estimate_grain_shading(
    face_means: &[(Face, [f32; 3])],
    fibre: Vec3,
) -> Option<ShadingEstimate> {
    let t = fibre.try_normalize()?;
    let n = face_means.len();
    let w: Vec<f32> = face_means
        .iter()
        .map(|(f, _)| f.normal().dot(t).powi(2))
        .collect();
    let w_mean = w.iter().sum::<f32>() / n as f32;
    let spread: f32 = w.iter().map(|x| (x - w_mean).powi(2)).sum();
    // Two faces of each grain also leave the t-test at least 2 degrees of freedom.
    let end_faces = w.iter().filter(|&&x| x >= 0.5).count();
    if spread < MIN_WEIGHT_SPREAD || end_faces.min(n - end_faces) < MIN_FACES_PER_GRAIN {
        return None;
    }
    let channel = |c: usize| -> Vec<f32> { face_means.iter().map(|(_, m)| m[c]).collect() };
    let lines: [(f32, f32); 3] = std::array::from_fn(|c| line(&w, &channel(c), w_mean, spread));
    let lightness: Vec<f32> = face_means
        .iter()
        .map(|(_, m)| (m[0] + m[1] + m[2]) / 3.0)
        .collect();
    let t_statistic = slope_t(&w, &lightness, w_mean, spread);
    let clamp = |v: f32| v.clamp(1e-4, 1.0);
    Some(ShadingEstimate {
        model: GrainShading {
            fibre: t.into(),
            side: lines.map(|(a, _)| clamp(a)),
            end: lines.map(|(a, b)| clamp(a + b)),
            t_statistic,
        },
    })
}

/// Least-squares intercept and slope of y over x (`x_mean`, `spread` = sum (x - x_mean)^2).
fn line(x: &[f32], y: &[f32], x_mean: f32, spread: f32) -> (f32, f32) {
    let y_mean = y.iter().sum::<f32>() / y.len() as f32;
    let cov: f32 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - x_mean) * (b - y_mean))
        .sum();
    let slope = cov / spread;
    (y_mean - slope * x_mean, slope)
}

/// Slope of y over x divided by its standard error (n - 2 degrees of freedom); a perfect fit
/// gives a large finite value with the slope's sign.
fn slope_t(x: &[f32], y: &[f32], x_mean: f32, spread: f32) -> f32 {
    let (a, b) = line(x, y, x_mean, spread);
    let rss: f32 = x.iter().zip(y).map(|(u, v)| (v - a - b * u).powi(2)).sum();
    let dof = (x.len() - 2) as f32;
    let se = (rss / dof / spread).sqrt();
    if se > 0.0 {
        (b / se).clamp(-1e6, 1e6)
    } else if b == 0.0 {
        0.0
    } else {
        1e6 * b.signum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Face means of a cube with fibres along y whose end grain is `end` and side grain
    /// `side`, each face with a lighting error from `noise`.
    fn means(side: [f32; 3], end: [f32; 3], noise: [f32; 6]) -> Vec<(Face, [f32; 3])> {
        Face::ALL
            .iter()
            .map(|&f| {
                let w = f.normal().dot(Vec3::Y).powi(2);
                let m =
                    std::array::from_fn(|c| side[c] + (end[c] - side[c]) * w + noise[f.index()]);
                (f, m)
            })
            .collect()
    }

    #[test]
    fn a_clear_end_grain_darkening_is_recovered() {
        let (side, end) = ([0.75, 0.62, 0.5], [0.62, 0.52, 0.44]);
        let noise = [0.01, -0.012, 0.008, 0.01, -0.015, 0.004];
        let est = estimate_grain_shading(&means(side, end, noise), Vec3::Y).unwrap();
        assert!(est.is_shown(), "t = {}", est.model.t_statistic);
        assert!(est.model.t_statistic < 0.0);
        for c in 0..3 {
            assert!(
                (est.model.side[c] - side[c]).abs() < 0.015,
                "{:?}",
                est.model
            );
            assert!((est.model.end[c] - end[c]).abs() < 0.02, "{:?}", est.model);
        }
    }

    #[test]
    fn lighting_differences_alone_are_not_taken_for_grain_shading() {
        // H11-like: one end-grain face lighter, the other darker than the side faces.
        let grey = [0.8; 3];
        let noise = [0.05, 0.03, -0.09, -0.08, 0.06, -0.02];
        let est = estimate_grain_shading(&means(grey, grey, noise), Vec3::Y).unwrap();
        assert!(!est.is_shown(), "t = {}", est.model.t_statistic);
        assert!(est.kept().is_none());
    }

    /// A softwood-like cube: end grain 0.85 of side grain, and two side faces (C, F) 12 %
    /// darker because of the knots they show, which the bars know (`content`).
    #[test]
    fn a_face_darkened_by_its_wood_is_not_read_as_grain() {
        let (side, end) = ([0.8, 0.7, 0.6], [0.68, 0.595, 0.51]);
        let knotty = |f: Face| matches!(f, Face::C | Face::F);
        let mut wb = WhiteBalance {
            face_means: [[0.0; 3]; 6],
            mean: [0.7; 3],
            grain: None,
        };
        let mut content = [NEUTRAL_CONTENT; 6];
        for (f, m) in means(side, end, [0.0; 6]) {
            let k = if knotty(f) { 0.88 } else { 1.0 };
            wb.face_means[f.index()] = m.map(|v| v * k);
            content[f.index()] = NEUTRAL_CONTENT.map(|v| v * k);
        }
        let plain = add_grain_shading(&mut wb.clone(), &Face::ALL, Vec3::Y, &[NEUTRAL_CONTENT; 6]);
        let plain_t = plain.unwrap().model.t_statistic;
        assert!(plain_t.abs() < MIN_T, "plain means: t = {plain_t}");
        let est = add_grain_shading(&mut wb, &Face::ALL, Vec3::Y, &content).unwrap();
        assert!(est.is_shown() && wb.grain.is_some(), "{est:?}");
        for c in 0..3 {
            let ratio = est.model.end[c] / est.model.side[c];
            assert!((ratio - 0.85).abs() < 1e-3, "channel {c}: {ratio}");
        }
    }

    #[test]
    fn faces_of_one_kind_of_grain_determine_nothing() {
        let m = means([0.7; 3], [0.5; 3], [0.0; 6]);
        let side_only: Vec<_> = m
            .into_iter()
            .filter(|(f, _)| !matches!(f, Face::B | Face::D))
            .collect();
        assert!(estimate_grain_shading(&side_only, Vec3::Y).is_none());
        assert!(estimate_grain_shading(&side_only[..2], Vec3::Y).is_none());
    }

    /// Five faces with one end-grain face: however clear the step, one photo cannot tell its
    /// exposure from its grain.
    #[test]
    fn one_end_grain_face_determines_nothing() {
        let m = means([0.8; 3], [0.6; 3], [0.0, 0.0, 0.01, 0.0, -0.01, 0.0]);
        let without_b: Vec<_> = m.iter().copied().filter(|(f, _)| *f != Face::B).collect();
        assert_eq!(without_b.len(), 5);
        assert!(estimate_grain_shading(&without_b, Vec3::Y).is_none());
        assert!(estimate_grain_shading(&m, Vec3::Y).unwrap().is_shown());
    }
}
