//! Tree-space coordinates of a lookup point (Liu et al. 2016 section 4.1): height along the
//! pith, the cross-section position in the pith frame, radius and azimuth. Pores, rays,
//! fibres and noise are all placed in these coordinates, so they follow the stem's axis
//! wherever the cube sits.

use glam::{Vec2, Vec3};

use crate::field::PithAxis;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreePoint {
    /// Signed height along the pith from its origin (cube units).
    pub h: f32,
    /// Cross-section position (e1, e2 components of the offset from the axis).
    pub cross: Vec2,
    /// Distance from the axis.
    pub r: f32,
    /// Azimuth in [0, 2 pi) from e1.
    pub phi: f32,
}

impl TreePoint {
    pub fn new(pith: &PithAxis, p: Vec3) -> Self {
        let d = p - pith.origin;
        let cross = Vec2::new(d.dot(pith.e1), d.dot(pith.e2));
        let mut phi = cross.y.atan2(cross.x);
        if phi < 0.0 {
            phi += std::f32::consts::TAU;
        }
        Self {
            h: d.dot(pith.dir),
            cross,
            r: cross.length(),
            phi,
        }
    }

    /// The point in the frame (cross.x, cross.y, h), for 3D noise in tree space.
    pub(crate) fn frame_point(&self) -> Vec3 {
        Vec3::new(self.cross.x, self.cross.y, self.h)
    }
}

/// Unit radial and tangential directions (world space) at `p`; `None` on the axis.
pub fn radial_frame(pith: &PithAxis, p: Vec3) -> Option<(Vec3, Vec3)> {
    let d = p - pith.origin;
    let radial = d - d.dot(pith.dir) * pith.dir;
    let len = radial.length();
    if len < 1e-6 {
        return None;
    }
    let radial = radial / len;
    Some((radial, pith.dir.cross(radial)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_match_the_pith_axis() {
        let pith = PithAxis::new(Vec3::new(0.1, 0.0, -2.0), Vec3::new(0.1, 1.0, 0.2));
        let p = Vec3::new(0.3, -0.2, 0.4);
        let t = TreePoint::new(&pith, p);
        let c = pith.cylindrical(p);
        assert!((t.h - c.h).abs() < 1e-5 && (t.r - c.r).abs() < 1e-5);
        assert!((t.phi - c.phi).abs() < 1e-4);
        let (radial, tangential) = radial_frame(&pith, p).unwrap();
        assert!(radial.dot(pith.dir).abs() < 1e-5 && tangential.dot(radial).abs() < 1e-5);
    }
}
