//! The unfolded cube (DESIGN section 2): row 2 of the cross is `C A E F`, B sits above A and
//! D below A, so that neighbouring tiles meet along shared cube edges.

use super::face::Face;

/// Tile (column, row) of each face in a 4 x 3 grid of face-sized tiles.
pub(crate) fn cross_tile(face: Face) -> (usize, usize) {
    match face {
        Face::B => (1, 0),
        Face::C => (0, 1),
        Face::A => (1, 1),
        Face::E => (2, 1),
        Face::F => (3, 1),
        Face::D => (1, 2),
    }
}

/// Size of the cross in tiles: (columns, rows).
pub(crate) const CROSS_TILES: (usize, usize) = (4, 3);
