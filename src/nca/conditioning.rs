//! The conditioning of the NCA: base colour B and growth field G, as solid textures sampled
//! at the voxel centres of a region, turned into the channels the network perceives.
//!
//! Decision (DESIGN section 6 allows grey or RGB B): the default is the authors' two channels,
//! grey B - 0.5 and normalised G - 0.5, because
//! - the colour of B already reaches the output (RGB = B + state[0..3]); the network only
//!   needs to know *where in the ring* a voxel is, and the lightness of B says that (early /
//!   late wood), which normalised G cannot (a 128-wide ReLU layer cannot compute frac(G) over
//!   dozens of rings);
//! - RGB B costs 10 more inputs (83 instead of 73, +14% in the first layer) for colour the
//!   output already has.
//!
//! The other channels stay selectable (`model.conditioning` in the config) for the later
//! quality study: `rgb_b` (B - 0.5, 3 channels) and `ring_phase` (cos and sin of 2 pi G,
//! halved: the ring phase from the field itself). An empty list is the position-only
//! ablation.
//!
//! Colours: the NCA works in white-balanced space, where each face photo is divided by twice
//! its mean colour (DESIGN section 6) so every target has mean 0.5. B is brought into the same
//! space with one factor for the whole sample (`white_balance` = 1 / (2 x mean colour of the
//! used photos)); synthesis divides by it again to return to photo colours.

use std::sync::Arc;

use burn::tensor::{Device, Tensor};
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::colour_axes::{project, project_tensor};
use super::cond_channel::CondChannel;
use super::config::ModelSpec;
use super::grain_noise::GrainNoise;
use super::region::Region;
use super::tensors::tensor_from;
use crate::texture::SolidTexture;
use crate::volume::Volume;

/// B and G of a sample as solid textures.
#[derive(Clone)]
pub struct Conditioning {
    /// G in years (1 channel).
    pub growth: Arc<dyn SolidTexture>,
    /// B in photo colours, RGB in [0, 1] (3 channels).
    pub colour: Arc<dyn SolidTexture>,
    /// The fibre direction (unit, cube frame; `PithConfig::fibre_axis`): the axis of the
    /// grain noise.
    pub fibre_axis: Vec3,
    /// The grain noise, set by [`Conditioning::for_model`] for models that perceive it.
    pub grain: Option<Arc<GrainNoise>>,
    /// The ray noise (`ray_noise.rs`), set by [`Conditioning::for_model`] likewise.
    pub rays: Option<Arc<GrainNoise>>,
}

/// How raw B and G are scaled into conditioning channels; fixed at training time and stored
/// with the model so synthesis sees the same numbers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Normalisation {
    /// G at the low and high end of the cube (mapped to 0 and 1).
    pub g_range: [f32; 2],
    /// Per-channel factor from photo colours to white-balanced colours.
    pub white_balance: [f32; 3],
    /// The projection (row-major) of the state's RGB residual onto the photos' main
    /// fine-texture colour axes (`model.colour_axes`; `colour_axes.rs`); `None`: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour_projection: Option<[[f32; 3]; 3]>,
}

/// G (1 channel) and B (3 channels) at the voxel centres of a region, `[X, Y, Z, C]`.
pub struct CondVolumes {
    pub g: Volume,
    pub b: Volume,
    /// The grain noise (1 channel) where the conditioning has one.
    pub grain: Option<Volume>,
    /// The ray noise (1 channel) where the conditioning has one.
    pub rays: Option<Volume>,
}

/// Grid side on which the range of G over the cube is measured.
const G_RANGE_GRID: usize = 32;

impl Conditioning {
    /// Samples G and B at the voxel centres of `region` (in parallel).
    pub fn sample(&self, region: &Region) -> CondVolumes {
        CondVolumes {
            g: sample_region(self.growth.as_ref(), region),
            b: sample_region(self.colour.as_ref(), region),
            grain: self
                .grain
                .as_ref()
                .map(|n| sample_region(n.as_ref(), region)),
            rays: self
                .rays
                .as_ref()
                .map(|n| sample_region(n.as_ref(), region)),
        }
    }

    /// Adds the grain and ray noises of realisation `seed` that `spec` perceives, with their
    /// cells scaled by `cell_scale` (`grain_noise::cell_scale`: 1 in training).
    pub fn for_model(mut self, spec: &ModelSpec, seed: u64, cell_scale: f32) -> Self {
        if spec.conditioning.contains(&CondChannel::GrainNoise) {
            let noise = if spec.grain_noise.follow_rings {
                GrainNoise::following_rings(
                    &spec.grain_noise,
                    self.fibre_axis,
                    self.growth.clone(),
                    seed,
                    cell_scale,
                )
            } else {
                GrainNoise::new(&spec.grain_noise, self.fibre_axis, seed, cell_scale)
            };
            self.grain = Some(Arc::new(noise));
        }
        if spec.conditioning.contains(&CondChannel::RayNoise) {
            let noise =
                spec.ray_noise
                    .noise(self.fibre_axis, self.growth.clone(), seed, cell_scale);
            self.rays = Some(Arc::new(noise));
        }
        self
    }

    /// The normalisation for this sample: range of G over a 32^3 grid of the cube, and the
    /// white balance of the photos' mean colour.
    pub fn normalisation(&self, photo_mean: [f32; 3]) -> Normalisation {
        let g = Volume::from_texture(self.growth.as_ref(), G_RANGE_GRID);
        let lo = g.data.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = g.data.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        Normalisation {
            g_range: [lo, hi.max(lo + 1e-6)],
            white_balance: photo_mean.map(|m| 0.5 / m.max(1e-4)),
            colour_projection: None,
        }
    }
}

/// A texture evaluated at every voxel centre of a region.
fn sample_region(texture: &dyn SolidTexture, region: &Region) -> Volume {
    let c = texture.channels();
    let [_, dy, dz] = region.dims;
    let mut data = vec![0.0f32; region.voxels() * c];
    data.par_chunks_mut(dy * dz * c)
        .enumerate()
        .for_each(|(i, slab)| {
            for j in 0..dy {
                for k in 0..dz {
                    let o = (j * dz + k) * c;
                    texture.eval(region.voxel_point(i, j, k), &mut slab[o..o + c]);
                }
            }
        });
    Volume {
        dims: region.dims,
        channels: c,
        data,
    }
}

impl Normalisation {
    /// The state's RGB `[3, X, Y, Z]` as the residual added to B: projected onto the colour
    /// axes where the model has them.
    pub fn residual_tensor(&self, state_rgb: Tensor<4>, device: &Device) -> Tensor<4> {
        match &self.colour_projection {
            Some(p) => project_tensor(state_rgb, p, device),
            None => state_rgb,
        }
    }

    /// [`Self::residual_tensor`] of one voxel.
    pub fn residual(&self, state_rgb: [f32; 3]) -> [f32; 3] {
        match &self.colour_projection {
            Some(p) => project(p, state_rgb),
            None => state_rgb,
        }
    }

    /// White-balanced B, `[3, X, Y, Z]`: what the state's RGB residual is added to.
    pub fn colour_tensor(&self, vols: &CondVolumes, device: &Device) -> Tensor<4> {
        let [x, y, z] = vols.b.dims;
        tensor_from(self.colour_data(vols), [3, x, y, z], device)
    }

    /// [`Self::colour_tensor`] as plain data `[3, X, Y, Z]`.
    pub(crate) fn colour_data(&self, vols: &CondVolumes) -> Vec<f32> {
        let n = vols.b.dims.iter().product::<usize>();
        let mut data = vec![0.0f32; 3 * n];
        for (v, rgb) in vols.b.data.chunks_exact(3).enumerate() {
            for c in 0..3 {
                data[c * n + v] = rgb[c] * self.white_balance[c];
            }
        }
        data
    }

    /// The conditioning channels `[K, X, Y, Z]` in the order of `channels`.
    pub fn cond_tensor(
        &self,
        channels: &[CondChannel],
        vols: &CondVolumes,
        device: &Device,
    ) -> Tensor<4> {
        let width: usize = channels.iter().map(|c| c.width()).sum();
        let [x, y, z] = vols.g.dims;
        tensor_from(self.cond_data(channels, vols), [width, x, y, z], device)
    }

    /// [`Self::cond_tensor`] as plain data `[K, X, Y, Z]`.
    pub(crate) fn cond_data(&self, channels: &[CondChannel], vols: &CondVolumes) -> Vec<f32> {
        let n = vols.g.dims.iter().product::<usize>();
        let width: usize = channels.iter().map(|c| c.width()).sum();
        let mut data = vec![0.0f32; width * n];
        let span = self.g_range[1] - self.g_range[0];
        let mut base = 0;
        for &channel in channels {
            for v in 0..n {
                let g = vols.g.data[v];
                let rgb = &vols.b.data[3 * v..3 * v + 3];
                let wb = |c: usize| rgb[c] * self.white_balance[c];
                match channel {
                    CondChannel::GreyB => {
                        data[base * n + v] = (wb(0) + wb(1) + wb(2)) / 3.0 - 0.5;
                    }
                    CondChannel::RgbB => {
                        for c in 0..3 {
                            data[(base + c) * n + v] = wb(c) - 0.5;
                        }
                    }
                    CondChannel::G => {
                        data[base * n + v] = (g - self.g_range[0]) / span - 0.5;
                    }
                    CondChannel::RingPhase => {
                        let phase = std::f32::consts::TAU * g;
                        data[base * n + v] = 0.5 * phase.cos();
                        data[(base + 1) * n + v] = 0.5 * phase.sin();
                    }
                    CondChannel::GrainNoise => {
                        data[base * n + v] = 0.5 * sampled(&vols.grain).data[v];
                    }
                    CondChannel::RayNoise => {
                        data[base * n + v] = 0.5 * sampled(&vols.rays).data[v];
                    }
                }
            }
            base += channel.width();
        }
        data
    }
}

/// A noise channel's volume, which `Conditioning::for_model` set up for every noise the
/// model's conditioning lists.
fn sampled(noise: &Option<Volume>) -> &Volume {
    noise
        .as_ref()
        .expect("noise sampled: the conditioning went through for_model")
}

/// Undoes the white balance of `norm` on a white-balanced RGB value.
pub(crate) fn to_photo_colour(norm: &Normalisation, rgb: &mut [f32]) {
    for (v, wb) in rgb.iter_mut().zip(norm.white_balance) {
        *v /= wb;
    }
}
