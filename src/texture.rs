//! The one solid-texture interface: a function from a point of the cube to a few values.
//!
//! The growth field (1 channel, years), the ring image I(G) (1 channel), the procedural wood
//! model (RGB plus extras) and dense volumes (trilinear lookup) all implement it, so slicing,
//! rendering and comparison take any of them.

use glam::Vec3;

/// A solid texture: values at any point of space (the cube is [-0.5, 0.5]^3).
///
/// Implementations must be deterministic (the same point always gives the same values) and
/// thread-safe, because slicing and rendering evaluate points in parallel.
pub trait SolidTexture: Send + Sync {
    /// Number of values per point (1 for scalar fields, 3 for RGB, more with extra channels
    /// after the first three).
    fn channels(&self) -> usize;

    /// Writes the values at `p` into `out` (`out.len() == self.channels()`).
    fn eval(&self, p: Vec3, out: &mut [f32]);

    /// The values seen on a surface through `p` with unit normal `normal` (cube frame): what
    /// slicing and rendering show. Textures whose look depends on how the surface cuts the
    /// grain (`field::GrainShaded`) override it; for all others it is [`Self::eval`], which
    /// stays the plain lookup that volumes and exports use.
    fn eval_on_surface(&self, p: Vec3, normal: Vec3, out: &mut [f32]) {
        let _ = normal;
        self.eval(p, out)
    }

    /// Convenience: the values at `p` as a new vector.
    fn eval_vec(&self, p: Vec3) -> Vec<f32> {
        let mut out = vec![0.0; self.channels()];
        self.eval(p, &mut out);
        out
    }
}

/// A reference or a smart pointer to a texture is that texture: every method is forwarded,
/// so an overridden `eval_on_surface` is kept.
macro_rules! forward_solid_texture {
    ($($pointer:ty),*) => {$(
        impl<T: SolidTexture + ?Sized> SolidTexture for $pointer {
            fn channels(&self) -> usize {
                (**self).channels()
            }
            fn eval(&self, p: Vec3, out: &mut [f32]) {
                (**self).eval(p, out)
            }
            fn eval_on_surface(&self, p: Vec3, normal: Vec3, out: &mut [f32]) {
                (**self).eval_on_surface(p, normal, out)
            }
        }
    )*};
}

forward_solid_texture!(&T, Box<T>, std::sync::Arc<T>);

/// A texture restricted to its first `n` channels (e.g. the RGB of a texture that also
/// carries a fibre direction).
pub struct FirstChannels<T> {
    pub inner: T,
    pub n: usize,
}

impl<T: SolidTexture> SolidTexture for FirstChannels<T> {
    fn channels(&self) -> usize {
        self.n.min(self.inner.channels())
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        with_values(&self.inner, p, |all| out.copy_from_slice(&all[..out.len()]));
    }
    fn eval_on_surface(&self, p: Vec3, normal: Vec3, out: &mut [f32]) {
        with_surface_values(&self.inner, p, normal, |all| {
            out.copy_from_slice(&all[..out.len()])
        });
    }
}

/// Evaluates `texture` at `p` into a scratch buffer (on the stack for up to 16 channels) and
/// hands the values to `f`; adapters use it to avoid a heap allocation per point.
pub fn with_values<R>(texture: &dyn SolidTexture, p: Vec3, f: impl FnOnce(&[f32]) -> R) -> R {
    with_scratch(texture.channels(), |buf| texture.eval(p, buf), f)
}

/// [`with_values`] for the values seen on a surface with unit normal `normal`.
pub(crate) fn with_surface_values<R>(
    texture: &dyn SolidTexture,
    p: Vec3,
    normal: Vec3,
    f: impl FnOnce(&[f32]) -> R,
) -> R {
    with_scratch(
        texture.channels(),
        |buf| texture.eval_on_surface(p, normal, buf),
        f,
    )
}

fn with_scratch<R>(n: usize, fill: impl FnOnce(&mut [f32]), f: impl FnOnce(&[f32]) -> R) -> R {
    if n <= 16 {
        let mut buf = [0.0f32; 16];
        fill(&mut buf[..n]);
        f(&buf[..n])
    } else {
        let mut buf = vec![0.0f32; n];
        fill(&mut buf);
        f(&buf)
    }
}

/// The first channel of `texture` at `p`.
pub(crate) fn first_channel(texture: &dyn SolidTexture, p: Vec3) -> f32 {
    with_values(texture, p, |v| v[0])
}
