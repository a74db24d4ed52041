//! The render config (`configs/render/default.toml`, also built in).

use serde::{Deserialize, Serialize};

use super::camera::CameraConfig;
use super::shading::{LightConfig, MaterialConfig};
use crate::config::{Checker, ConfigFile};
use crate::error::Result;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderConfig {
    /// Camera for the cube view (world = cube coordinates).
    pub camera: CameraConfig,
    /// Camera for carved meshes (the mesh is fitted into the unit cube around the origin).
    pub mesh_camera: CameraConfig,
    pub light: LightConfig,
    pub material: MaterialConfig,
    /// Samples per pixel along each axis (n x n stratified samples).
    pub samples_per_axis: usize,
    /// Background colour (display-referred).
    pub background: [f32; 3],
    /// How a mesh is carved out of the wood.
    pub carve: CarveConfig,
    /// Number of views of the turntable strip.
    pub turntable_views: usize,
    /// Seed of the sub-pixel jitter.
    pub seed: u64,
}

/// Placement of a mesh inside the wood: the mesh is scaled uniformly and centred into the
/// cube with `margin` to spare, then rotated by `rotate_deg` (XYZ Euler angles, degrees)
/// about the cube centre to choose which grain it shows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarveConfig {
    pub margin: f32,
    pub rotate_deg: [f32; 3],
}

pub(crate) const DEFAULT_RENDER: &str = include_str!("../../configs/render/default.toml");

impl RenderConfig {
    /// The built-in default (same as `configs/render/default.toml`).
    pub fn default_config() -> Self {
        Self::built_in(DEFAULT_RENDER, "<built-in configs/render/default.toml>")
    }
}

impl ConfigFile for RenderConfig {
    fn validate(&self, check: &Checker) -> Result<()> {
        for (name, cam) in [("camera", &self.camera), ("mesh_camera", &self.mesh_camera)] {
            let c = check.nested(name);
            c.vector("eye", cam.eye, 1000.0, "a camera position")?;
            c.vector("target", cam.target, 1000.0, "a point")?;
            c.direction("up", cam.up)?;
            c.range(
                "fov_deg",
                cam.fov_deg,
                1.0,
                170.0,
                "a vertical field of view in degrees",
            )?;
            let forward = glam::Vec3::from(cam.target) - glam::Vec3::from(cam.eye);
            if forward.length() < 1e-6
                || forward
                    .normalize()
                    .cross(glam::Vec3::from(cam.up).normalize())
                    .length()
                    < 1e-3
            {
                return Err(c.error(
                    "up",
                    "is parallel to the viewing direction (or eye == target)",
                ));
            }
        }
        let l = check.nested("light");
        l.direction("direction", self.light.direction)?;
        l.range(
            "intensity",
            self.light.intensity,
            0.0,
            100.0,
            "a light intensity",
        )?;
        l.range("ambient", self.light.ambient, 0.0, 10.0, "an ambient level")?;
        let m = check.nested("material");
        m.range("ior", self.material.ior, 1.0, 3.0, "a refractive index")?;
        m.range(
            "coat_shininess",
            self.material.coat_shininess,
            1.0,
            100_000.0,
            "a Blinn-Phong exponent",
        )?;
        m.range(
            "coat_strength",
            self.material.coat_strength,
            0.0,
            10.0,
            "a highlight scale",
        )?;
        m.range(
            "fibre_strength",
            self.material.fibre_strength,
            0.0,
            10.0,
            "a highlight scale",
        )?;
        m.range(
            "fibre_width_deg",
            self.material.fibre_width_deg,
            0.1,
            90.0,
            "a lobe width in degrees",
        )?;
        check.count(
            "samples_per_axis",
            self.samples_per_axis,
            1,
            16,
            "samples per pixel along each axis",
        )?;
        for (i, c) in self.background.iter().enumerate() {
            check.range(
                &format!("background[{i}]"),
                *c,
                0.0,
                1.0,
                "a colour component",
            )?;
        }
        let c = check.nested("carve");
        c.range(
            "margin",
            self.carve.margin,
            0.0,
            0.45,
            "a margin in cube units",
        )?;
        c.vector(
            "rotate_deg",
            self.carve.rotate_deg,
            360.0,
            "Euler angles in degrees",
        )?;
        check.count("turntable_views", self.turntable_views, 1, 64, "views")
    }
}
