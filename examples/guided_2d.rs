//! The 2D proof of the guided loss, as the NCA uses it: an image optimised from noise with
//! Adam, each step through random `PATCH`-px patches compared with the photo's windows
//! around them, guided by the ring phase of a fitted field on that face.
//!
//!     cargo run --release --example guided_2d -- PHOTO FIT FACE NCA_CONFIG OUT.png [STEPS] [PATCH]
//!
//! PHOTO is a face photo (e.g. a sample's C_col.png), FIT the sample's fit.toml, FACE its
//! letter, NCA_CONFIG a training config whose `[loss.style]` and `[loss.guided]` are used.
//! Writes OUT.png: photo | start | result. If this does not paint the photo's pores, no NCA
//! trained through the same loss can.

use burn::tensor::{Device, Tensor, TensorData};
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField};
use xylem::frame::Face;
use xylem::io::{load_rgb, save_png};
use xylem::loss::{GuidedLoss, GuidedPatch, tensor_to_image};
use xylem::nca::TrainConfig;
use xylem::nca::train::face_guides::phase_guide;
use xylem::rng::Rng;

fn main() -> xylem::Result<()> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let photo = load_rgb(std::path::Path::new(&a[0]))?;
    let field = GrowthField::from_config(&FieldConfig::load(std::path::Path::new(&a[1]))?);
    let face = Face::parse(&a[2]).expect("a face letter");
    let cfg = TrainConfig::load(std::path::Path::new(&a[3]))?;
    let steps: usize = a.get(5).and_then(|s| s.parse().ok()).unwrap_or(400);
    let patch: usize = a.get(6).and_then(|s| s.parse().ok()).unwrap_or(32);
    let n = photo.width;
    let device = Device::flex();
    let loss = GuidedLoss::new(&cfg.loss.style, &cfg.loss.guided, &device);
    let guide = phase_guide(&field, face, n);
    let target = loss.target(&photo, &guide)?;
    let means = photo.channel_means();
    let mut rng = Rng::new(1);
    let data: Vec<f32> = (0..3 * n * n)
        .map(|i| means[i / (n * n)] + 0.1 * rng.normal())
        .collect();
    let mut image = Tensor::<3>::from_data(TensorData::new(data, [3, n, n]), &device);
    let initial = tensor_to_image(image.clone())?;
    let (mut m, mut v) = (image.zeros_like(), image.zeros_like());
    for step in 0..steps {
        let x = image.clone().autodiff().require_grad();
        let patches: Vec<GuidedPatch> = (0..16)
            .map(|_| {
                let (r, c) = (rng.below(n - patch + 1), rng.below(n - patch + 1));
                GuidedPatch {
                    image: x.clone().narrow(1, r, patch).narrow(2, c, patch),
                    target: 0,
                    origin: [r, c],
                    guide: None,
                }
            })
            .collect();
        let value = loss
            .terms(&patches, std::slice::from_ref(&target), step as u64 + 1)?
            .total;
        let grads = value.backward();
        if step % 50 == 0 {
            eprintln!("step {step}: {}", value.into_scalar::<f32>());
        }
        let g = x.grad(&grads).expect("gradient");
        m = m.mul_scalar(0.9) + g.clone().mul_scalar(0.1);
        v = v.mul_scalar(0.999) + g.square().mul_scalar(0.001);
        let t = (step + 1) as i32;
        let lr = if step < steps * 6 / 10 { 0.02 } else { 0.006 };
        let update = m.clone().div_scalar(1.0 - 0.9f32.powi(t))
            / v.clone()
                .div_scalar(1.0 - 0.999f32.powi(t))
                .sqrt()
                .add_scalar(1e-8);
        image = image - update.mul_scalar(lr);
    }
    let result = tensor_to_image(image.clamp(0.0, 1.0))?;
    let sheet = xylem::Image2::hstack(&[&photo, &initial, &result], 4, 1.0);
    save_png(&sheet, std::path::Path::new(&a[4]))?;
    Ok(())
}
