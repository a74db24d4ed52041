//! A solid texture seen with grain shading (`grain_shading`): its plain values (volumes,
//! exports) are unchanged, while slices and renders see the first three channels (RGB)
//! multiplied by the shading factor of the surface's normal.

use glam::Vec3;

use super::base_colour::WhiteBalance;
use super::grain_shading::GrainShading;
use crate::texture::SolidTexture;

/// `inner` (RGB at the sample's white balance `mean`) seen with the sample's grain shading;
/// without one it is `inner` unchanged.
#[derive(Clone, Debug)]
pub struct GrainShaded<T> {
    pub inner: T,
    shading: Option<(GrainShading, [f32; 3])>,
}

impl<T: SolidTexture> GrainShaded<T> {
    /// `inner` holds colours at `white_balance.mean` (the base colour in `Shown(None)`, the
    /// NCA's volume); the shading is the white balance's, if it has one (and none without a
    /// white balance, e.g. for a stand-in fit without base colour).
    pub fn new(inner: T, white_balance: Option<&WhiteBalance>) -> Self {
        let shading = white_balance.and_then(|wb| wb.grain.clone().map(|g| (g, wb.mean)));
        Self { inner, shading }
    }

    /// `inner` (RGB at white balance `mean`) seen with a given `shading`, e.g. a synthetic
    /// sample's photographing step (`procedural::Photograph`).
    pub fn with_shading(inner: T, shading: GrainShading, mean: [f32; 3]) -> Self {
        let shading = Some((shading, mean));
        Self { inner, shading }
    }
}

impl<T: SolidTexture> SolidTexture for GrainShaded<T> {
    fn channels(&self) -> usize {
        self.inner.channels()
    }

    fn eval(&self, p: Vec3, out: &mut [f32]) {
        self.inner.eval(p, out)
    }

    fn eval_on_surface(&self, p: Vec3, normal: Vec3, out: &mut [f32]) {
        self.inner.eval_on_surface(p, normal, out);
        if let Some((shading, mean)) = &self.shading {
            let factor = shading.factor(normal, *mean);
            for (v, f) in out.iter_mut().zip(factor) {
                *v *= f;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Plane;
    use crate::slice::slice_plane;
    use crate::volume::Volume;

    fn white_balance(grain: Option<GrainShading>) -> WhiteBalance {
        WhiteBalance {
            face_means: [[0.6; 3]; 6],
            mean: [0.6; 3],
            grain,
        }
    }

    #[test]
    fn a_planes_normal_sets_the_colour_of_its_slice() {
        let grey = Volume::from_data([4, 4, 4], 3, vec![0.5; 4 * 4 * 4 * 3]).unwrap();
        let shading = GrainShading {
            fibre: [0.0, 1.0, 0.0],
            side: [0.66, 0.6, 0.54],
            end: [0.48, 0.42, 0.36],
            t_statistic: -3.0,
        };
        let shaded = GrainShaded::new(&grey, Some(&white_balance(Some(shading.clone()))));
        // Plain values are untouched: exports keep the volume's colour.
        assert_eq!(shaded.eval_vec(Vec3::ZERO), vec![0.5; 3]);
        // A face across the fibres (B, normal +y) is end grain, a face along them side grain,
        // and cut2 (normal (0.86, 0, -0.49)) is side grain too.
        for (plane, mean) in [
            (Plane::face(crate::frame::Face::B), shading.end),
            (Plane::face(crate::frame::Face::A), shading.side),
            (Plane::cut2(), shading.side),
        ] {
            let img = slice_plane(&shaded, &plane, 4, 4);
            for (c, m) in img.channel_means().iter().enumerate() {
                let want = 0.5 * mean[c] / 0.6;
                assert!((m - want).abs() < 1e-5, "channel {c}: {m} vs {want}");
            }
        }
        // Without a fitted shading every surface sees the plain colour.
        let plain = GrainShaded::new(&grey, Some(&white_balance(None)));
        let img = slice_plane(&plain, &Plane::face(crate::frame::Face::B), 4, 4);
        assert!(img.data.iter().all(|v| (*v - 0.5).abs() < 1e-6));
    }
}
