//! The annual-ring localisation (ARL) image of a field: I(g) = ((cos 2 pi g + 1) / 2)^10.
//! Peaks (white) sit on integer years; the power of 10 makes them narrow lines.

use glam::Vec3;

use crate::texture::SolidTexture;

/// I(g) for g in years.
pub fn ring_intensity(g: f32) -> f32 {
    let c = 0.5 * ((std::f32::consts::TAU * g).cos() + 1.0);
    c.powi(10)
}

/// A scalar texture (years) seen through [`ring_intensity`].
pub struct RingImage<T>(pub T);

impl<T: SolidTexture> SolidTexture for RingImage<T> {
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out[0] = ring_intensity(crate::texture::first_channel(&self.0, p));
    }
}
