//! Images into loss inputs and back: `Image2` (`[H, W, C]`, interleaved) <-> burn tensors
//! `[3, H, W]` (planar).

use burn::tensor::{Device, Tensor, TensorData};

use crate::error::{Result, XylemError};
use crate::image2::Image2;

/// An image as an RGB tensor `[3, H, W]` on `device` (grey is repeated, extra channels are
/// dropped).
pub fn image_to_tensor(img: &Image2, device: &Device) -> Tensor<3> {
    planar_tensor(&img.with_channels(3), device)
}

/// An image with any number of channels as a planar tensor `[C, H, W]`.
pub(crate) fn planar_tensor(img: &Image2, device: &Device) -> Tensor<3> {
    let (h, w, c) = (img.height, img.width, img.channels);
    let mut planar = vec![0.0f32; c * h * w];
    for (p, px) in img.data.chunks_exact(c).enumerate() {
        for (ch, &v) in px.iter().enumerate() {
            planar[ch * h * w + p] = v;
        }
    }
    Tensor::from_data(TensorData::new(planar, [c, h, w]), device)
}

/// An RGB tensor `[3, H, W]` as an image (values as they are, not clamped).
pub fn tensor_to_image(t: Tensor<3>) -> Result<Image2> {
    let [c, h, w] = t.dims();
    let planar = tensor_values(t)?;
    let mut data = vec![0.0f32; c * h * w];
    for (p, px) in data.chunks_exact_mut(c).enumerate() {
        for (ch, v) in px.iter_mut().enumerate() {
            *v = planar[ch * h * w + p];
        }
    }
    Image2::from_data(w, h, c, data)
}

/// The values of a tensor, row-major.
pub(crate) fn tensor_values<const D: usize>(t: Tensor<D>) -> Result<Vec<f32>> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .map_err(|e| XylemError::numeric("tensor readback", format!("{e:?}")))
}
