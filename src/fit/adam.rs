//! Adam (Kingma and Ba 2015) over a flat parameter vector: the fit's parameters (pith axis,
//! log rates, grey map, knots, colour bars) are plain `Vec<f32>` with gradients computed
//! analytically, so a few lines replace an autodiff framework here.

/// Adam state for one parameter vector.
#[derive(Clone, Debug)]
pub struct Adam {
    m: Vec<f32>,
    v: Vec<f32>,
    t: i32,
    beta1: f32,
    beta2: f32,
    eps: f32,
    /// One second moment for all parameters (their mean squared gradient) instead of one
    /// each: parameters with small gradients then take small steps (see `shared`).
    shared: bool,
}

impl Adam {
    /// State for `n` parameters with the usual betas (0.9, 0.999).
    pub fn new(n: usize) -> Self {
        Self {
            m: vec![0.0; n],
            v: vec![0.0; n],
            t: 0,
            beta1: 0.9,
            beta2: 0.999,
            eps: 1e-8,
            shared: false,
        }
    }

    /// Adam whose second moment is shared by all parameters. Plain Adam moves every parameter
    /// by about the step size whatever its gradient, so a parameter that only a handful of
    /// noisy data points touch wanders as fast as a well-determined one; with a shared second
    /// moment each parameter's step is proportional to its own gradient (momentum SGD with
    /// a step normalised by the whole gradient's RMS).
    pub fn shared(n: usize) -> Self {
        Self {
            shared: true,
            ..Self::new(n)
        }
    }

    /// One step of size `lr` against `grad`.
    pub fn step(&mut self, params: &mut [f32], grad: &[f32], lr: f32) {
        self.step_scaled(params, grad, |_| lr);
    }

    /// One step with a per-parameter step size `lr(i)`.
    pub(crate) fn step_scaled(
        &mut self,
        params: &mut [f32],
        grad: &[f32],
        lr: impl Fn(usize) -> f32,
    ) {
        assert_eq!(params.len(), self.m.len(), "Adam parameter count");
        self.t += 1;
        let c1 = 1.0 - self.beta1.powi(self.t);
        let c2 = 1.0 - self.beta2.powi(self.t);
        let mean_sq = grad.iter().map(|g| g * g).sum::<f32>() / grad.len().max(1) as f32;
        for i in 0..params.len() {
            let g = grad[i];
            self.m[i] = self.beta1 * self.m[i] + (1.0 - self.beta1) * g;
            let sq = if self.shared { mean_sq } else { g * g };
            self.v[i] = self.beta2 * self.v[i] + (1.0 - self.beta2) * sq;
            let m_hat = self.m[i] / c1;
            let v_hat = self.v[i] / c2;
            params[i] -= lr(i) * m_hat / (v_hat.sqrt() + self.eps);
        }
    }
}

/// Cosine decay from `lr` to `lr * floor` over `total` steps (step in 0..total).
pub(crate) fn cosine_lr(lr: f32, step: usize, total: usize, floor: f32) -> f32 {
    let x = step as f32 / total.max(1) as f32;
    let w = 0.5 * (1.0 + (std::f32::consts::PI * x.min(1.0)).cos());
    lr * (floor + (1.0 - floor) * w)
}
