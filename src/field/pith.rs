//! The pith axis and the cylindrical coordinates around it (height h along the axis, radius
//! r, azimuth phi from a reference vector perpendicular to the axis).

use glam::Vec3;

use crate::frame::HALF;

/// Cylindrical coordinates of a point around the pith.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylindrical {
    /// Signed distance along the axis from the origin.
    pub h: f32,
    /// Distance from the axis.
    pub r: f32,
    /// Azimuth in [0, 2 pi).
    pub phi: f32,
}

/// A straight pith axis with an orthonormal frame (dir, e1, e2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PithAxis {
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Azimuth reference (phi = 0): world +z projected perpendicular to the axis, or +x when
    /// the axis is nearly along z. +z faces face A; for the usual axis along y this makes the
    /// azimuth continuous for every tilt the fit explores.
    pub e1: Vec3,
    /// dir x e1 (phi = pi/2).
    pub e2: Vec3,
}

impl PithAxis {
    /// `direction` must be non-zero (configs are validated before this is called).
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        let dir = direction.normalize();
        let reference = if dir.z.abs() < 0.99 { Vec3::Z } else { Vec3::X };
        let e1 = (reference - reference.dot(dir) * dir).normalize();
        let e2 = dir.cross(e1);
        Self {
            origin,
            dir,
            e1,
            e2,
        }
    }

    /// Distance of `p` from the axis.
    pub fn radius(&self, p: Vec3) -> f32 {
        let d = p - self.origin;
        (d - d.dot(self.dir) * self.dir).length()
    }

    pub fn cylindrical(&self, p: Vec3) -> Cylindrical {
        let d = p - self.origin;
        let h = d.dot(self.dir);
        let q = d - h * self.dir;
        let mut phi = q.dot(self.e2).atan2(q.dot(self.e1));
        if phi < 0.0 {
            phi += std::f32::consts::TAU;
        }
        Cylindrical {
            h,
            r: q.length(),
            phi,
        }
    }

    /// Heights spanned by the cube along the axis.
    pub fn cube_height_range(&self) -> [f32; 2] {
        let centre = (Vec3::ZERO - self.origin).dot(self.dir);
        let half = HALF * (self.dir.x.abs() + self.dir.y.abs() + self.dir.z.abs());
        [centre - half, centre + half]
    }

    /// Radii spanned by the cube: from the nearest point of the cube to the axis (0 when the
    /// axis passes through the cube) to the farthest corner.
    pub fn cube_radius_range(&self) -> [f32; 2] {
        let corners = cube_corners();
        let far = corners.iter().map(|&c| self.radius(c)).fold(0.0, f32::max);
        let near = if self.crosses_cube() {
            0.0
        } else {
            cube_edges(&corners)
                .map(|(a, b)| self.segment_distance(a, b))
                .fold(f32::INFINITY, f32::min)
        };
        [near, far]
    }

    /// Whether the (infinite) axis line passes through the cube (slab test).
    fn crosses_cube(&self) -> bool {
        let (mut lo, mut hi) = (f32::NEG_INFINITY, f32::INFINITY);
        for a in 0..3 {
            let (o, d) = (self.origin[a], self.dir[a]);
            if d.abs() < 1e-12 {
                if o.abs() > HALF {
                    return false;
                }
                continue;
            }
            let (t0, t1) = ((-HALF - o) / d, (HALF - o) / d);
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        }
        lo <= hi
    }

    /// Smallest distance between the axis line and the segment [a, b]: the squared distance
    /// is a convex quadratic along the segment, minimised in closed form and clamped.
    fn segment_distance(&self, a: Vec3, b: Vec3) -> f32 {
        let perp = |v: Vec3| v - v.dot(self.dir) * self.dir;
        let qa = perp(a - self.origin);
        let qe = perp(b - a);
        let denom = qe.length_squared();
        let t = if denom < 1e-12 {
            0.0
        } else {
            (-qa.dot(qe) / denom).clamp(0.0, 1.0)
        };
        (qa + t * qe).length()
    }
}

fn cube_corners() -> [Vec3; 8] {
    std::array::from_fn(|i| {
        let s = |bit: usize| if i >> bit & 1 == 1 { HALF } else { -HALF };
        Vec3::new(s(0), s(1), s(2))
    })
}

/// The 12 edges of the cube as corner pairs differing in one coordinate.
fn cube_edges(corners: &[Vec3; 8]) -> impl Iterator<Item = (Vec3, Vec3)> + '_ {
    (0..8usize).flat_map(move |i| {
        (0..3).filter_map(move |bit| {
            let j = i | (1 << bit);
            (j != i).then(|| (corners[i], corners[j]))
        })
    })
}
