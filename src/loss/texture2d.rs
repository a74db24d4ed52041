//! The 2D proof of the loss: an image optimised from noise with Adam until its statistics
//! match a target photo's. If this does not reproduce the wood's look, no NCA trained on the
//! same loss can.
//!
//! The image's pixels are the parameters (`[3, N, N]`), initialised to the target's mean
//! colour plus seeded Gaussian noise. Adam (beta 0.9 / 0.999) with the learning rate cut to
//! 30 % at 60 % and again at 85 % of the steps; projections are redrawn every step when the
//! loss config says so (call counter = step + 1).

use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::config::LossConfig;
use super::image_tensor::tensor_to_image;
use super::style::StyleLoss;
use crate::config::Checker;
use crate::config::ConfigFile;
use crate::error::{Result, XylemError};
use crate::image2::Image2;
use crate::rng::Rng;

/// Settings of one 2D synthesis (the resolved config written next to its output).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Texture2dConfig {
    /// Side of the synthesised image (pixels).
    pub size: usize,
    /// Side the target photo is resized to before its statistics are taken (pixels).
    pub target_size: usize,
    /// Adam steps.
    pub steps: usize,
    pub learning_rate: f32,
    /// Standard deviation of the initial noise around the target's mean colour.
    pub init_noise: f32,
    /// Seed of the initial noise.
    pub seed: u64,
    pub loss: LossConfig,
}

impl Texture2dConfig {
    /// The defaults of `xylem texture2d` around a loss config.
    pub fn with_loss(loss: LossConfig) -> Self {
        Self {
            size: 128,
            target_size: 128,
            steps: 600,
            learning_rate: 0.02,
            init_noise: 0.1,
            seed: 1,
            loss,
        }
    }

    /// Loads and validates a config written by `xylem texture2d` (its `config.toml`).
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let cfg: Texture2dConfig = crate::config::load_toml(path)?;
        cfg.validate(&Checker::new(path))?;
        Ok(cfg)
    }

    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.count("size", self.size, 8, 2048, "an image side in pixels")?;
        check.count(
            "target_size",
            self.target_size,
            8,
            4096,
            "a target side in pixels",
        )?;
        check.count("steps", self.steps, 1, 1_000_000, "optimisation steps")?;
        check.positive(
            "learning_rate",
            self.learning_rate,
            10.0,
            "an Adam learning rate",
        )?;
        check.range("init_noise", self.init_noise, 0.0, 1.0, "a noise level")?;
        self.loss.validate(&check.nested("loss"))
    }
}

/// What a synthesis produced.
pub struct Synthesis {
    /// The target as used (resized), RGB.
    pub target: Image2,
    /// The initial noise image.
    pub initial: Image2,
    /// The optimised image (clamped to [0, 1]).
    pub result: Image2,
    /// The loss before each step.
    pub losses: Vec<f32>,
}

/// Learning rate at `step` of `steps`: cut to 30 % at 60 % and at 85 % of the run.
fn learning_rate(base: f32, step: usize, steps: usize) -> f32 {
    let t = step as f32 / steps as f32;
    base * if t < 0.6 {
        1.0
    } else if t < 0.85 {
        0.3
    } else {
        0.09
    }
}

/// Optimises an image against `target` (any RGB image; resized to `cfg.target_size`).
/// `progress(step, loss)` is called after every step.
pub fn synthesize(
    target: &Image2,
    cfg: &Texture2dConfig,
    device: &Device,
    progress: &mut dyn FnMut(usize, f32),
) -> Result<Synthesis> {
    let plain = device.clone().without_autodiff();
    let target = target
        .with_channels(3)
        .resized(cfg.target_size, cfg.target_size);
    let loss = StyleLoss::new(&cfg.loss, &plain);
    let targets = loss.targets(std::slice::from_ref(&target))?;

    let mut image = initial_image(&target, cfg, &plain); // [3, N, N]
    let initial = tensor_to_image(image.clone())?;
    let (beta1, beta2, eps) = (0.9f32, 0.999f32, 1e-8f32);
    let mut m = image.zeros_like();
    let mut v = image.zeros_like();
    let mut losses = Vec::with_capacity(cfg.steps);
    for step in 0..cfg.steps {
        let x = image.clone().autodiff().require_grad();
        let value = loss.loss_at(std::slice::from_ref(&x), &targets, &[0], step as u64 + 1)?;
        let grads = value.backward();
        let scalar = value.into_scalar::<f32>();
        if !scalar.is_finite() {
            return Err(XylemError::numeric(
                "texture2d",
                format!("the loss became {scalar} at step {step}; lower learning_rate"),
            ));
        }
        losses.push(scalar);
        let g = x
            .grad(&grads)
            .ok_or_else(|| XylemError::numeric("texture2d", "no gradient reached the image"))?;
        m = m.mul_scalar(beta1) + g.clone().mul_scalar(1.0 - beta1);
        v = v.mul_scalar(beta2) + g.square().mul_scalar(1.0 - beta2);
        let t = (step + 1) as i32;
        let m_hat = m.clone().div_scalar(1.0 - beta1.powi(t));
        let v_hat = v.clone().div_scalar(1.0 - beta2.powi(t));
        let lr = learning_rate(cfg.learning_rate, step, cfg.steps);
        image = image - m_hat.div(v_hat.sqrt().add_scalar(eps)).mul_scalar(lr);
        progress(step, scalar);
    }
    let result = tensor_to_image(image.clamp(0.0, 1.0))?;
    Ok(Synthesis {
        target,
        initial,
        result,
        losses,
    })
}

/// The target's mean colour plus seeded Gaussian noise, `[3, N, N]`.
fn initial_image(target: &Image2, cfg: &Texture2dConfig, device: &Device) -> Tensor<3> {
    let n = cfg.size;
    let means = target.channel_means();
    let mut rng = Rng::substream(cfg.seed, 0x5445_5832);
    let data: Vec<f32> = (0..3 * n * n)
        .map(|i| means[i / (n * n)] + cfg.init_noise * rng.normal())
        .collect();
    Tensor::from_data(TensorData::new(data, [3, n, n]), device)
}
