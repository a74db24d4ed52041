//! Triangle meshes: loading OBJ files (`tobj`), placing them in the cube, writing OBJ.

use std::path::Path;

use glam::{Mat4, Vec3};

use crate::error::{Result, XylemError};

/// A triangle mesh with optional per-vertex normals.
#[derive(Clone, Debug, Default)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (same length as positions) or empty for flat shading.
    pub normals: Vec<Vec3>,
    /// Triangles as vertex index triples.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Loads an OBJ file (all its models merged; faces triangulated).
    pub fn load_obj(path: &Path) -> Result<Self> {
        if !path.is_file() {
            return Err(XylemError::input(
                path.display().to_string(),
                "mesh file not found (expected an .obj file)",
            ));
        }
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let (models, _) = tobj::load_obj(path, &options).map_err(|e| {
            XylemError::input(
                path.display().to_string(),
                format!("cannot read as OBJ: {e}"),
            )
        })?;
        let mut mesh = TriMesh::default();
        let mut all_normals = true;
        for model in &models {
            let m = &model.mesh;
            let base = mesh.positions.len() as u32;
            let count = m.positions.len() / 3;
            mesh.positions.extend(
                m.positions
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
            if m.normals.len() == m.positions.len() {
                mesh.normals.extend(
                    m.normals
                        .chunks_exact(3)
                        .map(|n| Vec3::new(n[0], n[1], n[2]).normalize_or_zero()),
                );
            } else {
                all_normals = false;
                mesh.normals.extend(std::iter::repeat_n(Vec3::ZERO, count));
            }
            mesh.triangles.extend(
                m.indices
                    .chunks_exact(3)
                    .map(|t| [base + t[0], base + t[1], base + t[2]]),
            );
        }
        if !all_normals {
            mesh.normals.clear();
        }
        if mesh.triangles.is_empty() {
            return Err(XylemError::input(
                path.display().to_string(),
                "OBJ file has no faces",
            ));
        }
        // A NaN or infinite vertex poisons the bounds that place the mesh in the cube, and
        // the render would silently show only the background.
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(XylemError::input(
                path.display().to_string(),
                format!(
                    "vertex {} is {:?}: expected finite coordinates",
                    i + 1,
                    mesh.positions[i].to_array()
                ),
            ));
        }
        Ok(mesh)
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// The uniform scale + translation that fits the mesh's bounding box centred inside the
    /// cube with `margin` (cube units) to spare: the mesh-to-cube transform used to carve the
    /// object from the wood.
    pub(crate) fn fit_into_cube(&self, margin: f32) -> Mat4 {
        let (lo, hi) = self.bounds();
        let extent = (hi - lo).max_element().max(1e-12);
        let scale = (1.0 - 2.0 * margin) / extent;
        Mat4::from_scale(Vec3::splat(scale)) * Mat4::from_translation(-(lo + hi) * 0.5)
    }

    /// The mesh with every vertex transformed (normals by the inverse transpose).
    pub fn transformed(&self, m: &Mat4) -> TriMesh {
        let normal_matrix = m.inverse().transpose();
        TriMesh {
            positions: self
                .positions
                .iter()
                .map(|p| m.transform_point3(*p))
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|n| normal_matrix.transform_vector3(*n).normalize_or_zero())
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Writes a Wavefront OBJ with vertex normals.
    pub fn to_obj_string(&self, comment: &str) -> String {
        use std::fmt::Write;
        let mut s = format!("# {comment}\n");
        for p in &self.positions {
            let _ = writeln!(s, "v {:.5} {:.5} {:.5}", p.x, p.y, p.z);
        }
        for n in &self.normals {
            let _ = writeln!(s, "vn {:.4} {:.4} {:.4}", n.x, n.y, n.z);
        }
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| i + 1);
            if self.normals.is_empty() {
                let _ = writeln!(s, "f {a} {b} {c}");
            } else {
                let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
            }
        }
        s
    }
}
