//! A triangle mesh ready for ray casting: its BVH, nearest hits with interpolated normals,
//! and shadow tests.

use glam::Vec3;

use super::bvh::Bvh;
use super::camera::Ray;
use super::mesh::TriMesh;

/// A surface hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub point: Vec3,
    /// Unit shading normal facing the ray origin.
    pub normal: Vec3,
}

/// A mesh ready for ray casting.
pub struct MeshShape {
    pub mesh: TriMesh,
    bvh: Bvh,
}

impl MeshShape {
    pub fn new(mesh: TriMesh) -> Self {
        let bvh = Bvh::build(&mesh);
        Self { mesh, bvh }
    }

    /// Nearest hit along the ray within (t_min, t_max).
    pub(crate) fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let (tri, t, u, v) = self.bvh.intersect(&self.mesh, ray, t_min, t_max)?;
        let [a, b, c] = self.mesh.triangle(tri);
        let geometric = (b - a).cross(c - a).normalize();
        let mut normal = if self.mesh.normals.is_empty() {
            geometric
        } else {
            let [ia, ib, ic] = self.mesh.triangles[tri];
            let n = self.mesh.normals[ia as usize] * (1.0 - u - v)
                + self.mesh.normals[ib as usize] * u
                + self.mesh.normals[ic as usize] * v;
            n.try_normalize().unwrap_or(geometric)
        };
        if normal.dot(ray.dir) > 0.0 {
            normal = -normal;
        }
        Some(Hit {
            point: ray.origin + t * ray.dir,
            normal,
        })
    }

    /// Whether anything blocks the segment (for shadows).
    pub(crate) fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.bvh.intersect(&self.mesh, ray, 1e-4, t_max).is_some()
    }
}
