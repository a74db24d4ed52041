//! Rendering any solid texture: a lit cube seen from a corner, or an object carved from the
//! wood (an OBJ mesh), with a perspective camera, key light + ambient, diffuse, clear-coat
//! and fibre highlights, and stratified anti-aliasing. CPU, parallel over rows.

pub(crate) mod bvh;
pub mod camera;
pub mod config;
pub mod lathe;
pub mod mesh;
pub(crate) mod mesh_shape;
pub mod renderer;
pub mod shading;

pub use camera::Camera;
pub use camera::CameraConfig;
pub use config::RenderConfig;
pub use mesh::TriMesh;

pub use renderer::{Shape, render, turntable};
