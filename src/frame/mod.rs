//! The fixed cube frame (DESIGN sections 2 and 3): faces, pixel and voxel centres, the
//! unfolded cross, validation cuts and arbitrary planes, and the edge-agreement check.

pub mod cross;
pub mod edges;
pub mod face;
pub mod plane;

pub(crate) use cross::{CROSS_TILES, cross_tile};
pub use edges::{FaceImageTransform, cube_edges, edge_agreement};
pub use face::{CM_PER_UNIT, Face, mm, pixel_centre};
pub(crate) use face::{HALF, voxel_centre};
pub use plane::{Plane, PlaneSpec};
