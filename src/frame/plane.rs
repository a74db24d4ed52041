//! Planes through the cube: the six faces, the two validation cuts of DESIGN section 3, and
//! arbitrary planes given by an origin and two in-plane axes.
//!
//! A plane is sampled as an image: pixel (row r, column c) of a W x H image sits at
//! `origin + s * u + t * v` with s = (c + 0.5)/W and t = (r + 0.5)/H. So `origin` is the
//! top-left corner of the image area, `u` spans its width and `v` its height. The faces and
//! cuts are expressed in this form so that one sampler serves all of them.

use std::str::FromStr;

use glam::Vec3;

use super::face::{Face, HALF};
use crate::error::XylemError;

/// A rectangular patch of a plane, parameterised over [0, 1]^2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Corner at (s, t) = (0, 0): the image's top-left corner.
    pub origin: Vec3,
    /// Edge vector from the top-left to the top-right corner.
    pub u: Vec3,
    /// Edge vector from the top-left to the bottom-left corner.
    pub v: Vec3,
}

impl Plane {
    pub fn new(origin: Vec3, u: Vec3, v: Vec3) -> Self {
        Self { origin, u, v }
    }

    /// The point at parameters (s, t) in [0, 1]^2.
    pub fn at(&self, s: f32, t: f32) -> Vec3 {
        self.origin + s * self.u + t * self.v
    }

    /// The centre of pixel (row, col) of a `width` x `height` image of this plane.
    pub fn pixel_point(&self, row: usize, col: usize, width: usize, height: usize) -> Vec3 {
        self.at(
            (col as f32 + 0.5) / width as f32,
            (row as f32 + 0.5) / height as f32,
        )
    }

    /// The plane of a cube face, with the face table's pixel layout.
    pub fn face(face: Face) -> Self {
        let origin = face.point(-HALF, -HALF);
        Self {
            origin,
            u: face.point(HALF, -HALF) - origin,
            v: face.point(-HALF, HALF) - origin,
        }
    }

    /// cut1 (DESIGN section 3): x = 0.575 (y + 0.5) - 0.375, crossing the pith direction.
    /// Column c maps to y = -((c + 0.5)/N - 0.5), row r to z = (r + 0.5)/N - 0.5.
    pub fn cut1() -> Self {
        // At (s, t): y = 0.5 - s, z = t - 0.5, x = 0.575 (1 - s) - 0.375.
        Self {
            origin: Vec3::new(0.575 - 0.375, HALF, -HALF),
            u: Vec3::new(-0.575, -1.0, 0.0),
            v: Vec3::new(0.0, 0.0, 1.0),
        }
    }

    /// cut2 (DESIGN section 3): x = 0.575 (z + 0.5) - 0.375, running along the pith direction.
    pub fn cut2() -> Self {
        // At (s, t): y = 0.5 - s, z = t - 0.5, x = 0.575 t - 0.375.
        Self {
            origin: Vec3::new(-0.375, HALF, -HALF),
            u: Vec3::new(0.0, -1.0, 0.0),
            v: Vec3::new(0.575, 0.0, 1.0),
        }
    }

    /// Unit normal u x v (zero for a degenerate plane).
    pub fn normal(&self) -> Vec3 {
        self.u.cross(self.v).normalize_or_zero()
    }
}

/// A plane named on the command line: `cut1`, `cut2`, a face letter `A`..`F`, or
/// `"ox,oy,oz;ux,uy,uz;vx,vy,vz"` (origin = top-left corner, u = width edge, v = height edge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlaneSpec {
    Cut1,
    Cut2,
    Face(Face),
    Custom(Plane),
}

impl PlaneSpec {
    pub fn plane(&self) -> Plane {
        match self {
            PlaneSpec::Cut1 => Plane::cut1(),
            PlaneSpec::Cut2 => Plane::cut2(),
            PlaneSpec::Face(f) => Plane::face(*f),
            PlaneSpec::Custom(p) => *p,
        }
    }

    /// A short name for file names and captions.
    pub fn name(&self) -> String {
        match self {
            PlaneSpec::Cut1 => "cut1".into(),
            PlaneSpec::Cut2 => "cut2".into(),
            PlaneSpec::Face(f) => f.letter().to_string(),
            PlaneSpec::Custom(_) => "plane".into(),
        }
    }
}

impl FromStr for PlaneSpec {
    type Err = XylemError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let trimmed = s.trim();
        match trimmed.to_ascii_lowercase().as_str() {
            "cut1" => return Ok(PlaneSpec::Cut1),
            "cut2" => return Ok(PlaneSpec::Cut2),
            _ => {}
        }
        if let Some(face) = Face::parse(trimmed) {
            return Ok(PlaneSpec::Face(face));
        }
        parse_custom_plane(trimmed).map(PlaneSpec::Custom)
    }
}

fn plane_error(s: &str, message: &str) -> XylemError {
    XylemError::input(
        format!("$plane {s:?}"),
        format!(
            "{message}; expected cut1, cut2, a face A..F, or \"ox,oy,oz;ux,uy,uz;vx,vy,vz\" \
             (origin = top-left corner, u = width edge, v = height edge, cube units)"
        ),
    )
}

/// Largest plane coordinate accepted (cube units; the cube is 1 wide). Larger values are
/// typos, and from about 1e19 the parallel check's cross product overflows to infinity.
const PLANE_LIMIT: f32 = 1000.0;

fn parse_custom_plane(s: &str) -> Result<Plane, XylemError> {
    let parts: Vec<&str> = s.split(';').collect();
    if parts.len() != 3 {
        return Err(plane_error(s, "need three ';'-separated vectors"));
    }
    let mut vecs = [Vec3::ZERO; 3];
    for (slot, part) in vecs.iter_mut().zip(&parts) {
        let nums: Result<Vec<f32>, _> = part.split(',').map(|x| x.trim().parse::<f32>()).collect();
        match nums {
            Ok(n) if n.len() == 3 && n.iter().all(|x| x.is_finite() && x.abs() <= PLANE_LIMIT) => {
                *slot = Vec3::new(n[0], n[1], n[2])
            }
            _ => {
                return Err(plane_error(
                    s,
                    &format!(
                        "{part:?} is not three comma-separated finite numbers within \
                         +-{PLANE_LIMIT}"
                    ),
                ));
            }
        }
    }
    let plane = Plane::new(vecs[0], vecs[1], vecs[2]);
    if plane.u.cross(plane.v).length() < 1e-9 {
        return Err(plane_error(s, "u and v are parallel or zero"));
    }
    Ok(plane)
}
