//! The grey map M of step 2 (Mokume 5.2.3): a piecewise-linear function from normalised G to
//! the ring-image grey value, fitted together with the rate grid so that M(G) reproduces the
//! ring images. Rings may then sit at any values of G (not only integers), and the ring
//! iso-values are read off M's peaks afterwards (`ring_peaks`).
//!
//! M has evenly spaced nodes over t = (G - lo) / (hi - lo) in [0, 1] (clamped), the same
//! layout as the colour bars (`field::base_colour::bar_position`).

use crate::field::base_colour::bar_position;

/// The range of G mapped onto [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GRange {
    pub lo: f32,
    pub hi: f32,
}

impl GRange {
    /// The range of `values` widened by `margin` x its width on each side.
    pub fn of(values: &[f32], margin: f32) -> Self {
        let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let pad = margin * (hi - lo).max(1e-6);
        Self {
            lo: lo - pad,
            hi: hi + pad,
        }
    }

    /// t of a G value, unclamped.
    pub fn t(&self, g: f32) -> f32 {
        (g - self.lo) / (self.hi - self.lo)
    }

    /// G of a t value.
    pub fn g(&self, t: f32) -> f32 {
        self.lo + t * (self.hi - self.lo)
    }
}

/// M at t, and dM/dt (0 outside [0, 1] where t is clamped).
pub fn eval(map: &[f32], t: f32) -> (f32, f32) {
    let n = map.len();
    let (i, f) = bar_position(t, n);
    let value = map[i] * (1.0 - f) + map[i + 1] * f;
    let slope = if (0.0..=1.0).contains(&t) {
        (map[i + 1] - map[i]) * (n - 1) as f32
    } else {
        0.0
    };
    (value, slope)
}

/// Adds `w` x dM(t)/dM_i to `grad` for the two nodes around t.
pub(crate) fn accumulate_node_gradient(grad: &mut [f32], t: f32, w: f32) {
    let (i, f) = bar_position(t, grad.len());
    grad[i] += w * (1.0 - f);
    grad[i + 1] += w * f;
}

/// Per-node means of `targets` binned by nearest node of their t (the least-squares start of
/// M). Empty nodes take the value of the nearest filled node; with no data at all, 0.
pub(crate) fn binned_means(ts: &[f32], targets: &[f32], nodes: usize) -> Vec<f32> {
    let mut sum = vec![0.0f64; nodes];
    let mut count = vec![0usize; nodes];
    for (&t, &a) in ts.iter().zip(targets) {
        let k = (t.clamp(0.0, 1.0) * (nodes - 1) as f32).round() as usize;
        sum[k] += a as f64;
        count[k] += 1;
    }
    let filled: Vec<usize> = (0..nodes).filter(|&k| count[k] > 0).collect();
    (0..nodes)
        .map(|k| {
            let nearest = filled.iter().min_by_key(|&&j| j.abs_diff(k));
            nearest.map_or(0.0, |&j| (sum[j] / count[j] as f64) as f32)
        })
        .collect()
}
