//! Surface shading of wood: a key light plus ambient, Lambertian diffuse under a clear coat
//! (Fresnel-weighted, normalised Blinn-Phong highlight), and, where the texture carries a
//! fibre direction, the anisotropic subsurface fibre highlight of Marschner et al. 2005 (as
//! Liu et al. 2016 use it): light and view are refracted into the wood, and the fibres
//! reflect light along the cone where the refracted directions make opposite angles with the
//! fibre axis, a Gaussian lobe in psi_h = psi_i + psi_r scaled by 1 / cos^2(psi_d / 2).
//! Shading is done in linear RGB; texture colours are display-referred (sRGB) and converted.

use glam::Vec3;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightConfig {
    /// Direction towards the key light (need not be normalised).
    pub direction: [f32; 3],
    /// Key light radiance (linear).
    pub intensity: f32,
    /// Ambient light (linear, relative to albedo).
    pub ambient: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    /// Refractive index of the finish (clear coat) and wood.
    pub ior: f32,
    /// Blinn-Phong exponent of the coat highlight (higher: glossier).
    pub coat_shininess: f32,
    /// Scale of the coat highlight (0 disables it: unfinished wood).
    pub coat_strength: f32,
    /// Scale of the fibre highlight (0 disables it).
    pub fibre_strength: f32,
    /// Angular width (degrees) of the fibre highlight lobe.
    pub fibre_width_deg: f32,
}

/// Everything the shader needs at a surface point.
pub struct SurfacePoint {
    pub normal: Vec3,
    /// Unit direction towards the viewer.
    pub view: Vec3,
    /// Display-referred colour of the wood.
    pub albedo: Vec3,
    /// Fibre direction, if the texture has one.
    pub fibre: Option<Vec3>,
}

pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

pub(crate) fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

fn schlick(cos: f32, ior: f32) -> f32 {
    let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
    f0 + (1.0 - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// Direction of `d` (travelling towards the surface, unit) after refraction into a medium of
/// index `ior` below the surface with unit normal `n` (pointing out).
fn refract_in(d: Vec3, n: Vec3, ior: f32) -> Vec3 {
    let eta = 1.0 / ior;
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (eta * d + (eta * cos_i - k.max(0.0).sqrt()) * n).normalize()
}

/// Marschner's fibre lobe for light arriving along `-light` and leaving along `view`.
fn fibre_lobe(p: &SurfacePoint, light: Vec3, fibre: Vec3, m: &MaterialConfig) -> f32 {
    let d_in = refract_in(-light, p.normal, m.ior);
    let d_view = refract_in(-p.view, p.normal, m.ior);
    let psi_i = d_in.dot(fibre).clamp(-1.0, 1.0).asin();
    let psi_r = d_view.dot(fibre).clamp(-1.0, 1.0).asin();
    let (psi_h, psi_d) = (psi_i + psi_r, psi_r - psi_i);
    let beta = m.fibre_width_deg.to_radians().max(1e-3);
    let gauss =
        (-psi_h * psi_h / (2.0 * beta * beta)).exp() / (beta * (std::f32::consts::TAU).sqrt());
    gauss / (psi_d * 0.5).cos().powi(2).max(1e-3)
}

/// Linear RGB leaving the surface towards the viewer.
pub fn shade(p: &SurfacePoint, light: &LightConfig, m: &MaterialConfig, shadowed: bool) -> Vec3 {
    let albedo = Vec3::new(
        srgb_to_linear(p.albedo.x),
        srgb_to_linear(p.albedo.y),
        srgb_to_linear(p.albedo.z),
    );
    let l = Vec3::from(light.direction).normalize();
    let n_dot_l = p.normal.dot(l).max(0.0);
    let n_dot_v = p.normal.dot(p.view).max(0.0);
    let key = if shadowed {
        0.0
    } else {
        light.intensity * n_dot_l
    };
    // Light crossing the coat twice loses what the coat reflects.
    let transmit = (1.0 - schlick(n_dot_l, m.ior)) * (1.0 - schlick(n_dot_v, m.ior));
    let mut colour = albedo * (light.ambient + key * transmit);
    if key > 0.0 {
        let h = (l + p.view).normalize();
        let s = m.coat_shininess;
        let blinn = (s + 8.0) / (8.0 * std::f32::consts::PI) * p.normal.dot(h).max(0.0).powf(s);
        colour += Vec3::splat(m.coat_strength * schlick(p.view.dot(h), m.ior) * blinn * key);
        if let Some(fibre) = p.fibre {
            colour += albedo * (m.fibre_strength * fibre_lobe(p, l, fibre, m) * key * transmit);
        }
    }
    colour
}
