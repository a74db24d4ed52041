//! A pinhole perspective camera.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Camera placement (world = cube coordinates for the cube view).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraConfig {
    /// Eye position.
    pub eye: [f32; 3],
    /// Point looked at.
    pub target: [f32; 3],
    /// Approximate up direction.
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    #[serde(default = "default_fov")]
    pub fov_deg: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    30.0
}

/// A ready camera: orthonormal basis and image-plane scale.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half: f32,
    aspect: f32,
}

/// A ray with unit direction.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Camera {
    /// `width / height` sets the aspect ratio. The config is validated before this is called.
    pub fn new(cfg: &CameraConfig, width: usize, height: usize) -> Self {
        let eye = Vec3::from(cfg.eye);
        let forward = (Vec3::from(cfg.target) - eye).normalize();
        let right = forward.cross(Vec3::from(cfg.up)).normalize();
        let up = right.cross(forward);
        Self {
            eye,
            forward,
            right,
            up,
            tan_half: (cfg.fov_deg.to_radians() * 0.5).tan(),
            aspect: width as f32 / height as f32,
        }
    }

    /// The ray through image position (x, y) in pixels from the top-left corner (continuous).
    pub fn ray(&self, x: f32, y: f32, width: usize, height: usize) -> Ray {
        let sx = (2.0 * x / width as f32 - 1.0) * self.tan_half * self.aspect;
        let sy = (1.0 - 2.0 * y / height as f32) * self.tan_half;
        Ray {
            origin: self.eye,
            dir: (self.forward + sx * self.right + sy * self.up).normalize(),
        }
    }

    /// The camera orbited by `angle` radians around the vertical axis through `target`.
    pub(crate) fn orbit(cfg: &CameraConfig, angle: f32) -> CameraConfig {
        let target = Vec3::from(cfg.target);
        let offset = Vec3::from(cfg.eye) - target;
        let rotated = glam::Quat::from_rotation_y(angle) * offset;
        CameraConfig {
            eye: (target + rotated).into(),
            ..cfg.clone()
        }
    }
}
