//! Step 2 (Mokume 5.2.3): with the pith fixed, fit the rate grid R, the grey map M and the
//! knots to
//!
//!   L = lambda_iso x L_iso + lambda_image x mean |M(t(G)) - ARL|
//!       + lambda_smooth x S(log R) + lambda_magnitude x mean (log R)^2
//!       + lambda_anchor x (squared distances of the knot marks from their strands),
//!
//! L_iso being the iso-contour loss in cube units (years / years_per_unit) and S the mean
//! squared difference of neighbouring log rates along height, azimuth and radius.
//!
//! Parameterisation (decisions):
//! - R = exp(theta): rates stay positive without a hard clamp in the optimiser (the field's
//!   own `min_rate` clamp still holds). Each theta's Adam step is scaled by its node's lever
//!   (`rate_levers`), so that a step moves rings by about `lr_rates` whether the node is one
//!   of the cube's or the first one, which also spans the distance from the pith.
//! - theta is kept at zero mean after every step. The iso-contour loss alone is smallest when
//!   all rates shrink (G flattens), and M over normalised G cannot see the overall scale, so
//!   the scale of R is fixed instead of left to drift; the mean growth speed is carried by
//!   `years_per_unit`.
//! - Gradients are analytic: G is linear in the clamped rates (`stem_basis`), M is piecewise
//!   linear, the iso loss has a sign gradient (`iso_loss`); knots use `knot_fit`.

use glam::Vec3;
use rayon::prelude::*;

use super::adam::{Adam, cosine_lr};
use super::config::{DistortionFitConfig, KnotFitConfig};
use super::contours::ContourSet;
use super::grey_map::{self, GRange};
use super::iso_loss::{iso_loss, sign};
use super::knot_fit::{KNOT_PARAMS, KnotVariants, anchor_penalty, knot_params, set_knot_params};
use super::stem_basis::StemBasis;
use crate::field::{KnotConfig, PithAxis, RateGrid};

/// What step 2 fits against.
pub struct Step2Data {
    pub iso: ContourSet,
    /// Ring-image samples: 3D points and target grey values.
    pub pixels: Vec<Vec3>,
    pub targets: Vec<f32>,
}

/// The parameters of step 2.
#[derive(Clone, Debug, PartialEq)]
pub struct Step2Params {
    /// Log rates, flat in the rate grid's order.
    pub theta: Vec<f32>,
    /// Grey map nodes over t in [0, 1].
    pub map: Vec<f32>,
    pub knots: Vec<KnotConfig>,
}

/// The loss and its parts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LossParts {
    pub total: f32,
    /// Iso-contour loss in cube units (before lambda).
    pub iso: f32,
    /// Mean absolute ring-image error (before lambda).
    pub image: f32,
    /// Penalties (weighted): smoothness and magnitude of the log rates, knot anchors.
    pub smooth: f32,
}

/// Gradients of the total loss.
pub struct Step2Gradient {
    pub theta: Vec<f32>,
    pub map: Vec<f32>,
    pub knots: Vec<f32>,
}

/// The fixed parts of the step-2 problem.
pub struct Step2 {
    pub pith: PithAxis,
    pub years_per_unit: f32,
    /// Layout (dims, ranges, min_rate) of the fitted grid; its rates are ignored.
    pub layout: RateGrid,
    pub range: GRange,
    pub cfg: DistortionFitConfig,
    iso_basis: StemBasis,
    pixel_basis: StemBasis,
    data: Step2Data,
    /// Per knot, the marked points its strand is held near, and the penalty's weight.
    anchors: Vec<Vec<Vec3>>,
    lambda_anchor: f32,
}

impl Step2 {
    /// Precomputes the stem bases of the contour points and pixels. `range` maps G (years)
    /// onto the grey map.
    pub fn new(
        pith: PithAxis,
        years_per_unit: f32,
        layout: RateGrid,
        range: GRange,
        cfg: DistortionFitConfig,
        data: Step2Data,
    ) -> Self {
        let iso_basis = StemBasis::new(&layout, &pith, &data.iso.points);
        let pixel_basis = StemBasis::new(&layout, &pith, &data.pixels);
        Self {
            pith,
            years_per_unit,
            layout,
            range,
            cfg,
            iso_basis,
            pixel_basis,
            data,
            anchors: Vec::new(),
            lambda_anchor: 0.0,
        }
    }

    /// Holds knot i's strand near `anchors[i]` with weight `lambda` (`knot_fit::anchor_penalty`).
    pub(crate) fn with_knot_anchors(mut self, anchors: Vec<Vec<Vec3>>, lambda: f32) -> Self {
        self.anchors = anchors;
        self.lambda_anchor = lambda;
        self
    }

    pub fn data(&self) -> &Step2Data {
        &self.data
    }

    /// Raw rates of log rates.
    pub fn rates(theta: &[f32]) -> Vec<f32> {
        theta.iter().map(|t| t.exp()).collect()
    }

    /// G (years) and its derivatives at the points of one basis.
    fn field_values(
        &self,
        basis: &StemBasis,
        points: &[Vec3],
        clamped: &[f32],
        knots: &Option<KnotVariants>,
    ) -> PointValues {
        let ypu = self.years_per_unit;
        let stems: Vec<f32> = basis.integrals(clamped).iter().map(|i| ypu * i).collect();
        let Some(kv) = knots else {
            return PointValues {
                g: stems,
                d_stem: Vec::new(),
                d_knots: Vec::new(),
            };
        };
        let np = kv.n_params();
        let stride = self.cfg.knot_gradient_stride;
        let rows: Vec<(f32, f32, Vec<f32>)> = points
            .par_iter()
            .zip(&stems)
            .enumerate()
            .map(|(i, (&p, &stem))| {
                let mut d = vec![0.0; if i % stride == 0 { np } else { 0 }];
                let (g, ds) = kv.eval(p, stem, ypu, &mut d);
                // Every stride-th point stands for the points it skipped.
                d.iter_mut().for_each(|x| *x *= stride as f32);
                d.resize(np, 0.0);
                (g, ds, d)
            })
            .collect();
        let mut out = PointValues {
            g: Vec::with_capacity(rows.len()),
            d_stem: Vec::with_capacity(rows.len()),
            d_knots: Vec::with_capacity(rows.len() * np),
        };
        for (g, ds, d) in rows {
            out.g.push(g);
            out.d_stem.push(ds);
            out.d_knots.extend(d);
        }
        out
    }

    /// The loss at `params` and, with `want_grad`, its gradient.
    pub fn evaluate(
        &self,
        params: &Step2Params,
        want_grad: bool,
    ) -> (LossParts, Option<Step2Gradient>) {
        let min_rate = self.layout.min_rate;
        let rates = Self::rates(&params.theta);
        let clamped: Vec<f32> = rates.iter().map(|r| r.max(min_rate)).collect();
        let knots =
            (!params.knots.is_empty()).then(|| KnotVariants::new(&params.knots, self.pith.dir));
        let iso_v = self.field_values(&self.iso_basis, &self.data.iso.points, &clamped, &knots);
        let pix_v = self.field_values(&self.pixel_basis, &self.data.pixels, &clamped, &knots);

        let ypu = self.years_per_unit;
        let mut d_iso = vec![0.0; iso_v.g.len()];
        let iso = iso_loss(&self.data.iso, &iso_v.g, Some(&mut d_iso)) / ypu;
        let (image, d_pix, d_map) = self.image_loss(&params.map, &pix_v.g);
        let c = &self.cfg;
        let (penalty, d_penalty, mut knots_grad) = self.penalties(params);
        let parts = LossParts {
            total: c.lambda_iso * iso + c.lambda_image * image + penalty,
            iso,
            image,
            smooth: penalty,
        };
        if !want_grad {
            return (parts, None);
        }
        // dL/dG per point, then chained through the knot union to the stem time.
        let w_iso: Vec<f32> = d_iso.iter().map(|d| c.lambda_iso * d / ypu).collect();
        let w_pix: Vec<f32> = d_pix.iter().map(|d| c.lambda_image * d).collect();
        let stem_w = |w: &[f32], v: &PointValues| -> Vec<f32> {
            if v.d_stem.is_empty() {
                w.iter().map(|x| x * ypu).collect()
            } else {
                w.iter().zip(&v.d_stem).map(|(x, s)| x * s * ypu).collect()
            }
        };
        let n = params.theta.len();
        let g_iso = self.iso_basis.gradient(&stem_w(&w_iso, &iso_v), n);
        let g_pix = self.pixel_basis.gradient(&stem_w(&w_pix, &pix_v), n);
        let theta = (0..n)
            .map(|e| {
                let through_clamp = if rates[e] > min_rate { rates[e] } else { 0.0 };
                (g_iso[e] + g_pix[e]) * through_clamp + d_penalty[e]
            })
            .collect();
        let map = d_map.iter().map(|d| c.lambda_image * d).collect();
        add_knot_gradient(&mut knots_grad, &w_iso, &iso_v);
        add_knot_gradient(&mut knots_grad, &w_pix, &pix_v);
        let grad = Step2Gradient {
            theta,
            map,
            knots: knots_grad,
        };
        (parts, Some(grad))
    }

    /// The weighted penalties (smoothness and magnitude of the log rates, knot anchors), their
    /// gradient in theta and their gradient in the knot parameters.
    fn penalties(&self, params: &Step2Params) -> (f32, Vec<f32>, Vec<f32>) {
        let c = &self.cfg;
        let (smooth, d_smooth) = smoothness(&params.theta, &self.layout);
        let count = params.theta.len().max(1) as f32;
        let magnitude = params.theta.iter().map(|t| t * t).sum::<f32>() / count;
        let mut penalty = c.lambda_smooth * smooth + c.lambda_magnitude * magnitude;
        let d_theta = params
            .theta
            .iter()
            .zip(&d_smooth)
            .map(|(t, ds)| c.lambda_smooth * ds + c.lambda_magnitude * 2.0 * t / count)
            .collect();
        let mut d_knots = vec![0.0; params.knots.len() * KNOT_PARAMS];
        for ((knot, marks), g) in params
            .knots
            .iter()
            .zip(&self.anchors)
            .zip(d_knots.chunks_mut(KNOT_PARAMS))
        {
            let (p, d) = anchor_penalty(knot, marks);
            penalty += self.lambda_anchor * p;
            g.iter_mut()
                .zip(d)
                .for_each(|(g, d)| *g = self.lambda_anchor * d);
        }
        (penalty, d_theta, d_knots)
    }

    /// mean |M(t(G)) - target|, dL/dG per pixel and dL/dM.
    fn image_loss(&self, map: &[f32], g: &[f32]) -> (f32, Vec<f32>, Vec<f32>) {
        let targets = &self.data.targets;
        let count = targets.len().max(1) as f32;
        let span = self.range.hi - self.range.lo;
        let mut d_g = vec![0.0; g.len()];
        let mut d_map = vec![0.0; map.len()];
        let mut sum = 0.0f64;
        for (i, (&gi, &target)) in g.iter().zip(targets).enumerate() {
            let t = self.range.t(gi);
            let (m, slope) = grey_map::eval(map, t);
            let r = m - target;
            sum += r.abs() as f64;
            let s = sign(r) / count;
            d_g[i] = s * slope / span;
            grey_map::accumulate_node_gradient(&mut d_map, t, s);
        }
        ((sum / count as f64) as f32, d_g, d_map)
    }

    /// Adam on all parameters for `iterations` steps (learning rates decaying by a cosine to
    /// a tenth), calling `log` before each step (and once after the last) with the iteration
    /// and the loss. Returns the final parameters and their loss.
    pub fn fit(
        &self,
        start: Step2Params,
        iterations: usize,
        knot_cfg: &KnotFitConfig,
        mut log: impl FnMut(usize, &LossParts),
    ) -> (Step2Params, LossParts) {
        let levers = rate_levers(&self.layout);
        let mut params = start;
        let mut adam_theta = Adam::shared(params.theta.len());
        let mut adam_map = Adam::new(params.map.len());
        let mut knot_vec: Vec<f32> = params.knots.iter().flat_map(knot_params).collect();
        let mut adam_knots = Adam::new(knot_vec.len());
        let mut last = LossParts::default();
        for it in 0..=iterations {
            let want_grad = it < iterations;
            let (parts, grad) = self.evaluate(&params, want_grad);
            log(it, &parts);
            last = parts;
            let Some(grad) = grad else { break };
            let lr = |base: f32| cosine_lr(base, it, iterations, 0.1);
            let lr_shift = lr(self.cfg.lr_rates);
            adam_theta.step_scaled(&mut params.theta, &grad.theta, |e| lr_shift / levers[e]);
            let mean = params.theta.iter().sum::<f32>() / params.theta.len() as f32;
            params.theta.iter_mut().for_each(|t| *t -= mean);
            adam_map.step(&mut params.map, &grad.map, lr(self.cfg.lr_map));
            if knot_cfg.fit && !knot_vec.is_empty() {
                adam_knots.step(&mut knot_vec, &grad.knots, lr(knot_cfg.lr));
                for (k, p) in params.knots.iter_mut().zip(knot_vec.chunks(KNOT_PARAMS)) {
                    set_knot_params(k, p, knot_cfg.fit_speed);
                }
                knot_vec = params.knots.iter().flat_map(knot_params).collect();
            }
        }
        (params, last)
    }
}

/// How far (cube units) the stem time over years_per_unit moves per unit change of each
/// relative rate: the width of radius its radial node governs. The first node also governs
/// everything from the pith to the grid's first radius (`field::rate_grid`), which for a
/// pith 20 units away is 200 times more than an inner node.
fn rate_levers(layout: &RateGrid) -> Vec<f32> {
    let [r0, r1] = layout.radius_range;
    let dr = (r1 - r0) / (layout.n_r - 1) as f32;
    (0..layout.rates.len())
        .map(|e| match e % layout.n_r {
            0 => r0 + 0.5 * dr,
            _ => dr,
        })
        .collect()
}

/// Adds sum_p w_p x dG_p/dknot parameter to `grad` (nothing without knots).
fn add_knot_gradient(grad: &mut [f32], w: &[f32], values: &PointValues) {
    if values.d_knots.is_empty() {
        return;
    }
    let np = grad.len();
    for (row, &wp) in values.d_knots.chunks(np).zip(w) {
        grad.iter_mut().zip(row).for_each(|(k, d)| *k += wp * d);
    }
}

struct PointValues {
    g: Vec<f32>,
    /// dG/dstem per point (empty: 1 everywhere, no knots).
    d_stem: Vec<f32>,
    /// dG/dknot parameter, row-major [point][parameter] (empty without knots).
    d_knots: Vec<f32>,
}

/// Mean squared difference of neighbouring log rates along each grid axis (azimuth wraps
/// around when the grid covers the full circle), and its gradient.
pub fn smoothness(theta: &[f32], layout: &RateGrid) -> (f32, Vec<f32>) {
    let (nh, na, nr) = (layout.n_h, layout.n_a, layout.n_r);
    let idx = |h: usize, a: usize, r: usize| (h * na + a) * nr + r;
    let periodic = layout.azimuth_range.is_none();
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for h in 0..nh {
        for a in 0..na {
            for r in 0..nr {
                if h + 1 < nh {
                    pairs.push((idx(h, a, r), idx(h + 1, a, r)));
                }
                if a + 1 < na || (periodic && na > 2) {
                    pairs.push((idx(h, a, r), idx(h, (a + 1) % na, r)));
                }
                if r + 1 < nr {
                    pairs.push((idx(h, a, r), idx(h, a, r + 1)));
                }
            }
        }
    }
    let count = pairs.len().max(1) as f32;
    let mut grad = vec![0.0; theta.len()];
    let mut sum = 0.0;
    for (i, j) in pairs {
        let d = theta[i] - theta[j];
        sum += d * d;
        grad[i] += 2.0 * d / count;
        grad[j] -= 2.0 * d / count;
    }
    (sum / count, grad)
}
