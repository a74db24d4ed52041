//! The six cube faces and the fixed face table of DESIGN section 2.
//!
//! The cube is [-0.5, 0.5]^3 (1 unit = 4 cm). Pixel (row r, column c) of an N x N face image
//! has image coordinates u = (c + 0.5)/N - 0.5 (left to right) and v = (r + 0.5)/N - 0.5 (top
//! to bottom); the table below lifts (u, v) to the 3D point. This is the convention of the
//! Mokume files `A_col.png` .. `F_col.png`; `tests/frame.rs` checks it against the real ring
//! images (shared cube edges agree best under this table).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Half the cube side in cube units.
pub(crate) const HALF: f32 = 0.5;

/// Centimetres per cube unit (the Mokume cubes are 4.0 cm).
pub const CM_PER_UNIT: f32 = 4.0;

/// Millimetres to cube units (1 unit = `CM_PER_UNIT` cm).
pub fn mm(value: f32) -> f32 {
    value / (10.0 * CM_PER_UNIT)
}

/// One face of the sample cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Face {
    A,
    B,
    C,
    D,
    E,
    F,
}

impl Face {
    /// All faces in file order A..F.
    pub const ALL: [Face; 6] = [Face::A, Face::B, Face::C, Face::D, Face::E, Face::F];

    /// Index 0..6 in file order.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The face's letter, as in the Mokume file names.
    pub fn letter(self) -> char {
        (b'A' + self as u8) as char
    }

    /// Parses "A".."F" (case-insensitive).
    pub fn parse(s: &str) -> Option<Face> {
        match s.trim().to_ascii_uppercase().as_str() {
            "A" => Some(Face::A),
            "B" => Some(Face::B),
            "C" => Some(Face::C),
            "D" => Some(Face::D),
            "E" => Some(Face::E),
            "F" => Some(Face::F),
            _ => None,
        }
    }

    /// The 3D point of image coordinates (u, v) in [-0.5, 0.5]^2 (DESIGN table).
    pub fn point(self, u: f32, v: f32) -> Vec3 {
        match self {
            Face::A => Vec3::new(u, -v, HALF),
            Face::B => Vec3::new(u, HALF, v),
            Face::C => Vec3::new(-HALF, -v, u),
            Face::D => Vec3::new(u, -HALF, -v),
            Face::E => Vec3::new(HALF, -v, -u),
            Face::F => Vec3::new(-u, -v, -HALF),
        }
    }

    /// The image coordinates (u, v) of a point, inverting [`Face::point`]; the coordinate along
    /// the face normal is ignored, so points off the face project onto it.
    pub fn uv(self, p: Vec3) -> (f32, f32) {
        match self {
            Face::A => (p.x, -p.y),
            Face::B => (p.x, p.z),
            Face::C => (p.z, -p.y),
            Face::D => (p.x, -p.z),
            Face::E => (-p.z, -p.y),
            Face::F => (-p.x, -p.y),
        }
    }

    /// Outward unit normal.
    pub fn normal(self) -> Vec3 {
        match self {
            Face::A => Vec3::Z,
            Face::B => Vec3::Y,
            Face::C => Vec3::NEG_X,
            Face::D => Vec3::NEG_Y,
            Face::E => Vec3::X,
            Face::F => Vec3::NEG_Z,
        }
    }

    /// The 3D centre of pixel (row, col) of an n x n face image.
    pub fn pixel_point(self, row: usize, col: usize, n: usize) -> Vec3 {
        self.point(pixel_centre(col, n), pixel_centre(row, n))
    }

    /// Continuous pixel coordinates (row, col) of a point: pixel centres are at integers.
    pub fn point_pixel(self, p: Vec3, n: usize) -> (f32, f32) {
        let (u, v) = self.uv(p);
        let n = n as f32;
        ((v + HALF) * n - 0.5, (u + HALF) * n - 0.5)
    }
}

impl std::fmt::Display for Face {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// Centre of pixel or voxel `index` along an axis of `n` samples: (index + 0.5)/n - 0.5.
pub fn pixel_centre(index: usize, n: usize) -> f32 {
    (index as f32 + 0.5) / n as f32 - HALF
}

/// Voxel centres follow the pixel rule (DESIGN section 2).
pub(crate) fn voxel_centre(index: usize, n: usize) -> f32 {
    pixel_centre(index, n)
}
