//! Fibre direction (Liu et al. 2016 section 4.5) for anisotropic rendering.
//!
//! In the idealised tree the fibres run along the pith, kept inside the growth layer they
//! belong to: the pith direction projected onto the iso-surface of G (so they bend around
//! knots with the rings), and along the branch inside a knot. The lookup map L (figure, then
//! the strongest burl level) sends a real point p to the idealised point q = L(p), and a
//! real fibre direction v to J_L v; so the real direction is v = J_L^-1 u(q), normalised. Both
//! J_L and the gradient of G are central differences, so any distortion works; this costs
//! about 13 lookups per point and is only done when asked for (`WithFibreDirection`).

use glam::{Mat3, Vec3};

use super::model::ProceduralWood;
use crate::field::Strand;
use crate::texture::SolidTexture;

/// Finite-difference step (cube units, 0.04 mm).
const EPS: f32 = 1e-3;

impl ProceduralWood {
    /// The unit fibre direction at `p` (cube frame).
    pub fn fibre_direction(&self, p: Vec3) -> Vec3 {
        let q = self.lookup(p);
        let u = self.ideal_direction(q);
        let jacobian = Mat3::from_cols(
            self.lookup(p + Vec3::X * EPS) - self.lookup(p - Vec3::X * EPS),
            self.lookup(p + Vec3::Y * EPS) - self.lookup(p - Vec3::Y * EPS),
            self.lookup(p + Vec3::Z * EPS) - self.lookup(p - Vec3::Z * EPS),
        ) * (0.5 / EPS);
        if jacobian.determinant().abs() < 1e-6 {
            return u;
        }
        (jacobian.inverse() * u).normalize_or(u)
    }

    /// The fibre direction at an idealised point.
    fn ideal_direction(&self, q: Vec3) -> Vec3 {
        let pith = self.field.pith.dir;
        let sample = self.field.sample(q);
        if let Strand::Knot(i) = sample.strand {
            return self.field.knots[i].dir;
        }
        if self.field.knots.is_empty() && self.field.rates.is_none() {
            return pith;
        }
        let g = |d: Vec3| self.field.value(q + d) - self.field.value(q - d);
        let gradient = Vec3::new(g(Vec3::X * EPS), g(Vec3::Y * EPS), g(Vec3::Z * EPS));
        let n = gradient.normalize_or_zero();
        (pith - pith.dot(n) * n).normalize_or(pith)
    }
}

/// Six channels: the model's RGB, then the unit fibre direction (x, y, z in the cube frame,
/// each in [-1, 1]).
pub struct WithFibreDirection<'a>(pub &'a ProceduralWood);

impl SolidTexture for WithFibreDirection<'_> {
    fn channels(&self) -> usize {
        6
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[..3].copy_from_slice(&self.0.colour(p).to_array());
        out[3..].copy_from_slice(&self.0.fibre_direction(p).to_array());
    }
}

/// Three channels: the unit fibre direction alone (x, y, z in the cube frame).
pub struct FibreDirection<'a>(pub &'a ProceduralWood);

impl SolidTexture for FibreDirection<'_> {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out.copy_from_slice(&self.0.fibre_direction(p).to_array());
    }
}
