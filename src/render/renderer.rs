//! Ray casting of a solid texture on a cube or a carved mesh, in parallel over rows, with
//! n x n stratified (deterministically jittered) samples per pixel.

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use super::camera::{Camera, CameraConfig, Ray};
use super::config::{CarveConfig, RenderConfig};
use super::mesh::TriMesh;
use super::mesh_shape::{Hit, MeshShape};
use super::shading::{SurfacePoint, linear_to_srgb, shade};
use crate::frame::HALF;
use crate::image2::Image2;
use crate::rng::{hash3, unit};
use crate::texture::{SolidTexture, with_surface_values};

/// What is rendered.
// One Shape exists per render, so the mesh variant's size costs nothing worth a Box.
#[allow(clippy::large_enum_variant)]
pub enum Shape {
    /// The sample cube [-0.5, 0.5]^3 itself.
    Cube,
    /// A mesh in world space and the transforms between world and cube (texture) coordinates.
    Mesh {
        shape: MeshShape,
        world_to_cube: Mat4,
        cube_to_world: Mat4,
    },
}

impl Shape {
    /// A mesh carved out of the wood: fitted into the cube with `carve.margin` to spare and
    /// rotated by `carve.rotate_deg` inside the wood. The mesh is rendered upright (world =
    /// the fitted mesh); the rotation only changes which wood each surface point shows.
    pub fn carved(mesh: &TriMesh, carve: &CarveConfig) -> Shape {
        let fit = mesh.fit_into_cube(carve.margin);
        let [rx, ry, rz] = carve.rotate_deg.map(f32::to_radians);
        let rotation = Mat4::from_euler(glam::EulerRot::XYZ, rx, ry, rz);
        Shape::Mesh {
            shape: MeshShape::new(mesh.transformed(&fit)),
            world_to_cube: rotation,
            cube_to_world: rotation.inverse(),
        }
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Shape::Cube => cube_hit(ray),
            Shape::Mesh { shape, .. } => shape.intersect(ray, 1e-5, f32::INFINITY),
        }
    }

    /// Texture coordinates of a surface point, nudged inside so lookups on the cube's faces
    /// read the wood just below the surface.
    fn texture_point(&self, hit: &Hit) -> Vec3 {
        let inside = hit.point - hit.normal * 1e-4;
        match self {
            Shape::Cube => inside,
            Shape::Mesh { world_to_cube, .. } => world_to_cube.transform_point3(inside),
        }
    }

    /// The surface normal in texture (cube) coordinates, for textures whose look depends on
    /// how the surface cuts the grain.
    fn texture_normal(&self, hit: &Hit) -> Vec3 {
        match self {
            Shape::Cube => hit.normal,
            Shape::Mesh { world_to_cube, .. } => world_to_cube
                .transform_vector3(hit.normal)
                .normalize_or_zero(),
        }
    }

    fn world_direction(&self, d: Vec3) -> Vec3 {
        match self {
            Shape::Cube => d,
            Shape::Mesh { cube_to_world, .. } => {
                cube_to_world.transform_vector3(d).normalize_or_zero()
            }
        }
    }

    fn shadowed(&self, hit: &Hit, light: Vec3) -> bool {
        match self {
            // A convex cube never shadows itself where the light reaches the surface.
            Shape::Cube => false,
            Shape::Mesh { shape, .. } => {
                let ray = Ray {
                    origin: hit.point + hit.normal * 1e-4,
                    dir: light,
                };
                shape.occluded(&ray, f32::INFINITY)
            }
        }
    }

    /// The config camera that suits this shape.
    pub fn camera<'a>(&self, cfg: &'a RenderConfig) -> &'a CameraConfig {
        match self {
            Shape::Cube => &cfg.camera,
            Shape::Mesh { .. } => &cfg.mesh_camera,
        }
    }
}

/// Ray / cube intersection with the face normal.
fn cube_hit(ray: &Ray) -> Option<Hit> {
    let inv = ray.dir.recip();
    let t0 = (Vec3::splat(-HALF) - ray.origin) * inv;
    let t1 = (Vec3::splat(HALF) - ray.origin) * inv;
    let near = t0.min(t1);
    let far = t0.max(t1).min_element();
    let t = near.max_element();
    if t > far || far < 0.0 || t < 0.0 {
        return None;
    }
    let axis = (0..3).fold(0, |best, a| if near[a] > near[best] { a } else { best });
    let mut normal = Vec3::ZERO;
    normal[axis] = -ray.dir[axis].signum();
    Some(Hit {
        point: ray.origin + t * ray.dir,
        normal,
    })
}

/// Radiance (display-referred RGB) along one camera ray.
fn trace(ray: &Ray, shape: &Shape, texture: &dyn SolidTexture, cfg: &RenderConfig) -> Vec3 {
    let Some(hit) = shape.intersect(ray) else {
        return Vec3::from(cfg.background);
    };
    let p = shape.texture_point(&hit);
    let (albedo, fibre) = with_surface_values(texture, p, shape.texture_normal(&hit), |v| {
        let albedo = if v.len() >= 3 {
            Vec3::new(v[0], v[1], v[2])
        } else {
            Vec3::splat(v[0])
        };
        // Channels 3..6, when present, are the fibre direction in cube coordinates.
        let fibre = (v.len() >= 6)
            .then(|| Vec3::new(v[3], v[4], v[5]))
            .and_then(|f| f.try_normalize());
        (albedo, fibre)
    });
    let light = Vec3::from(cfg.light.direction).normalize();
    let surface = SurfacePoint {
        normal: hit.normal,
        view: -ray.dir,
        albedo,
        fibre: fibre.map(|f| shape.world_direction(f)),
    };
    let linear = shade(
        &surface,
        &cfg.light,
        &cfg.material,
        shape.shadowed(&hit, light),
    );
    Vec3::new(
        linear_to_srgb(linear.x),
        linear_to_srgb(linear.y),
        linear_to_srgb(linear.z),
    )
}

/// Renders `texture` on `shape` seen by `camera` into a `width` x `height` RGB image.
pub fn render(
    texture: &dyn SolidTexture,
    shape: &Shape,
    camera: &CameraConfig,
    cfg: &RenderConfig,
    width: usize,
    height: usize,
) -> Image2 {
    let cam = Camera::new(camera, width, height);
    let n = cfg.samples_per_axis;
    let mut data = vec![0.0f32; width * height * 3];
    data.par_chunks_mut(width * 3)
        .enumerate()
        .for_each(|(row, line)| {
            for col in 0..width {
                let mut sum = Vec3::ZERO;
                for s in 0..n * n {
                    let h = hash3(cfg.seed, col as i32, row as i32, s as i32);
                    let jx = (s % n) as f32 + unit(h);
                    let jy = (s / n) as f32 + unit(h.rotate_left(32));
                    let ray = cam.ray(
                        col as f32 + jx / n as f32,
                        row as f32 + jy / n as f32,
                        width,
                        height,
                    );
                    sum += trace(&ray, shape, texture, cfg);
                }
                let c = sum / (n * n) as f32;
                line[col * 3..col * 3 + 3].copy_from_slice(&c.to_array());
            }
        });
    Image2 {
        width,
        height,
        channels: 3,
        data,
    }
}

/// `views` renders orbiting the target around the vertical axis, side by side.
pub fn turntable(
    texture: &dyn SolidTexture,
    shape: &Shape,
    cfg: &RenderConfig,
    width: usize,
    height: usize,
) -> Image2 {
    let base = shape.camera(cfg);
    let views: Vec<Image2> = (0..cfg.turntable_views)
        .map(|i| {
            let angle = std::f32::consts::TAU * i as f32 / cfg.turntable_views as f32;
            render(
                texture,
                shape,
                &Camera::orbit(base, angle),
                cfg,
                width,
                height,
            )
        })
        .collect();
    Image2::hstack(&views, 0, 1.0)
}
