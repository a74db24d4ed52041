//! The base colour fit (DESIGN section 5): a colour bar over normalised G, a knot colour bar
//! and per-face offsets, fitted with an L1 loss to the white-balanced face photos.
//!
//! Start: each node of a bar takes the per-channel median of the pixels nearest to it in t
//! (the exact L1 minimiser for hard bins), which is already close; Adam then refines the bars
//! with linear interpolation, a smoothness penalty on neighbouring nodes and the offsets,
//! which absorb lighting differences between the photos. The offsets are kept at zero mean
//! over the fitted faces so that the bars carry the wood's colour and the offsets only the
//! differences.

use rayon::prelude::*;

use super::adam::{Adam, cosine_lr};
use super::config::ColourFitConfig;
use super::iso_loss::{median, sign};
use super::stem_basis::REDUCE_CHUNK;
use crate::field::base_colour::bar_position;
use crate::field::{BaseColour, GrowthField, WhiteBalance};
use crate::frame::Face;
use crate::image2::Image2;

/// One photo pixel seen by the colour fit.
#[derive(Clone, Copy, Debug)]
struct ColourSample {
    face: usize,
    t: f32,
    /// Knot bar weight.
    w: f32,
    target: [f32; 3],
}

/// Fits the bars and offsets. `balanced[f]` is the white-balanced photo of face f (for the
/// faces in `faces`), `g_range` the G range the bars span.
pub(crate) fn fit_base_colour(
    field: &GrowthField,
    balanced: &[Option<Image2>; 6],
    faces: &[Face],
    g_range: [f32; 2],
    white_balance: WhiteBalance,
    cfg: &ColourFitConfig,
    mut log: impl FnMut(usize, f32),
) -> BaseColour {
    let has_knots = !field.knots.is_empty();
    let mut colour = BaseColour {
        g_range,
        bar: vec![[0.5; 3]; cfg.bar_nodes],
        knot_bar: if has_knots {
            vec![[0.5; 3]; cfg.bar_nodes]
        } else {
            Vec::new()
        },
        knot_blend: cfg.knot_blend,
        face_offsets: [[0.0; 3]; 6],
        mean_shift: [0.0; 3],
        white_balance,
    };
    let samples = colour_samples(field, balanced, faces, &colour, cfg.pixel_stride);
    if samples.is_empty() {
        return colour;
    }
    colour.bar = binned_medians(&samples, cfg.bar_nodes, |s| s.w < 0.5);
    if has_knots {
        colour.knot_bar = binned_medians(&samples, cfg.bar_nodes, |s| s.w >= 0.5);
    }
    refine(&mut colour, &samples, faces, cfg, &mut log);
    colour.mean_shift = mean_residual(&colour, &samples);
    colour
}

/// Mean of photo minus fitted colour over the samples, per channel: where the L1 fit sits
/// above the photos' mean (`BaseColour::mean_shift`). Summed in f64 in sample order, so it
/// does not depend on threads.
fn mean_residual(colour: &BaseColour, samples: &[ColourSample]) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    for s in samples {
        let pred = prediction(colour, s, bar_position(s.t, colour.bar.len()));
        for c in 0..3 {
            sum[c] += (s.target[c] - pred[c]) as f64;
        }
    }
    sum.map(|v| (v / samples.len() as f64) as f32)
}

/// The fitted colour of one sample: bars at its t (node `i`, fraction `f`, from
/// `bar_position`), blended by its knot weight, plus its face's offset.
fn prediction(colour: &BaseColour, s: &ColourSample, (i, f): (usize, f32)) -> [f32; 3] {
    let nk = colour.knot_bar.len();
    let off = colour.face_offsets[s.face];
    std::array::from_fn(|c| {
        let stem = colour.bar[i][c] * (1.0 - f) + colour.bar[i + 1][c] * f;
        let knot = if nk > 0 {
            colour.knot_bar[i][c] * (1.0 - f) + colour.knot_bar[i + 1][c] * f
        } else {
            0.0
        };
        stem * (1.0 - s.w) + knot * s.w + off[c]
    })
}

fn colour_samples(
    field: &GrowthField,
    balanced: &[Option<Image2>; 6],
    faces: &[Face],
    colour: &BaseColour,
    stride: usize,
) -> Vec<ColourSample> {
    let mut samples = Vec::new();
    for &face in faces {
        let Some(img) = &balanced[face.index()] else {
            continue;
        };
        let n = img.width;
        let rows: Vec<usize> = (0..n).step_by(stride).collect();
        let face_samples: Vec<ColourSample> = rows
            .par_iter()
            .flat_map_iter(|&r| {
                (0..n).step_by(stride).map(move |c| {
                    let s = field.sample(face.pixel_point(r, c, n));
                    let px = img.pixel(r, c);
                    ColourSample {
                        face: face.index(),
                        t: colour.normalised(s.g),
                        w: colour.knot_weight(&s),
                        target: [px[0], px[1], px[2]],
                    }
                })
            })
            .collect();
        samples.extend(face_samples);
    }
    samples
}

/// Per-node, per-channel medians of the samples selected by `keep`, binned by nearest node;
/// empty nodes copy the nearest filled node (all 0.5 if none is filled).
fn binned_medians(
    samples: &[ColourSample],
    nodes: usize,
    keep: impl Fn(&ColourSample) -> bool,
) -> Vec<[f32; 3]> {
    let mut bins: Vec<[Vec<f32>; 3]> = (0..nodes).map(|_| Default::default()).collect();
    for s in samples.iter().filter(|s| keep(s)) {
        let k = (s.t * (nodes - 1) as f32).round() as usize;
        for (bin, &v) in bins[k].iter_mut().zip(&s.target) {
            bin.push(v);
        }
    }
    let filled: Vec<usize> = (0..nodes).filter(|&k| !bins[k][0].is_empty()).collect();
    (0..nodes)
        .map(|k| match filled.iter().min_by_key(|&&j| j.abs_diff(k)) {
            Some(&j) => std::array::from_fn(|c| median(&bins[j][c])),
            None => [0.5; 3],
        })
        .collect()
}

/// Parameter layout: stem bar, knot bar, offsets, each RGB-flattened.
fn pack(colour: &BaseColour) -> Vec<f32> {
    let mut p: Vec<f32> = colour.bar.iter().flatten().copied().collect();
    p.extend(colour.knot_bar.iter().flatten());
    p.extend(colour.face_offsets.iter().flatten());
    p
}

fn unpack(colour: &mut BaseColour, p: &[f32]) {
    let (nb, nk) = (colour.bar.len() * 3, colour.knot_bar.len() * 3);
    for (node, v) in colour.bar.iter_mut().zip(p[..nb].chunks(3)) {
        node.copy_from_slice(v);
    }
    for (node, v) in colour.knot_bar.iter_mut().zip(p[nb..nb + nk].chunks(3)) {
        node.copy_from_slice(v);
    }
    for (node, v) in colour.face_offsets.iter_mut().zip(p[nb + nk..].chunks(3)) {
        node.copy_from_slice(v);
    }
}

/// The colour loss (L1 + penalties) and its gradient in the `pack` layout.
fn loss_and_gradient(
    colour: &BaseColour,
    samples: &[ColourSample],
    cfg: &ColourFitConfig,
) -> (f32, Vec<f32>) {
    let (nb, nk) = (colour.bar.len(), colour.knot_bar.len());
    let n_params = 3 * (nb + nk + 6);
    let count = (samples.len() * 3) as f32;
    // Fixed chunks summed in order: the result does not depend on thread scheduling.
    let partials: Vec<(f64, Vec<f32>)> = samples
        .par_chunks(REDUCE_CHUNK)
        .map(|chunk| {
            let (mut sum, mut grad) = (0.0f64, vec![0.0f32; n_params]);
            for s in chunk {
                let (i, f) = bar_position(s.t, nb);
                let pred = prediction(colour, s, (i, f));
                for c in 0..3 {
                    let r = pred[c] - s.target[c];
                    sum += r.abs() as f64;
                    let g = sign(r) / count;
                    grad[3 * i + c] += g * (1.0 - s.w) * (1.0 - f);
                    grad[3 * (i + 1) + c] += g * (1.0 - s.w) * f;
                    if nk > 0 {
                        grad[3 * (nb + i) + c] += g * s.w * (1.0 - f);
                        grad[3 * (nb + i + 1) + c] += g * s.w * f;
                    }
                    grad[3 * (nb + nk + s.face) + c] += g;
                }
            }
            (sum, grad)
        })
        .collect();
    let mut sum = 0.0f64;
    let mut grad = vec![0.0f32; n_params];
    for (s, g) in partials {
        sum += s;
        grad.iter_mut().zip(g).for_each(|(a, b)| *a += b);
    }
    let mut loss = (sum / count as f64) as f32;
    loss += bar_smoothness(&colour.bar, 0, &mut grad, cfg.lambda_smooth);
    loss += bar_smoothness(&colour.knot_bar, nb, &mut grad, cfg.lambda_smooth);
    for (f, off) in colour.face_offsets.iter().enumerate() {
        for c in 0..3 {
            loss += cfg.lambda_offset * off[c] * off[c] / 18.0;
            grad[3 * (nb + nk + f) + c] += cfg.lambda_offset * 2.0 * off[c] / 18.0;
        }
    }
    (loss, grad)
}

/// lambda x the mean squared difference of neighbouring nodes of one bar (whose parameters
/// start at node `start` of the packed layout); adds its gradient to `grad`.
fn bar_smoothness(bar: &[[f32; 3]], start: usize, grad: &mut [f32], lambda: f32) -> f32 {
    let len = bar.len();
    if len < 2 {
        return 0.0;
    }
    let count = ((len - 1) * 3) as f32;
    let mut sum = 0.0;
    for k in 0..len - 1 {
        for c in 0..3 {
            let d = bar[k + 1][c] - bar[k][c];
            sum += d * d;
            grad[3 * (start + k + 1) + c] += lambda * 2.0 * d / count;
            grad[3 * (start + k) + c] -= lambda * 2.0 * d / count;
        }
    }
    lambda * sum / count
}

fn refine(
    colour: &mut BaseColour,
    samples: &[ColourSample],
    faces: &[Face],
    cfg: &ColourFitConfig,
    log: &mut impl FnMut(usize, f32),
) {
    let mut params = pack(colour);
    let mut adam = Adam::new(params.len());
    let offsets_at = 3 * (colour.bar.len() + colour.knot_bar.len());
    for it in 0..=cfg.iterations {
        let (loss, grad) = loss_and_gradient(colour, samples, cfg);
        log(it, loss);
        if it == cfg.iterations {
            break;
        }
        adam.step(
            &mut params,
            &grad,
            cosine_lr(cfg.lr, it, cfg.iterations, 0.1),
        );
        centre_offsets(&mut params[offsets_at..], faces);
        unpack(colour, &params);
    }
}

/// Zero mean over the fitted faces; faces not fitted keep a zero offset.
fn centre_offsets(offsets: &mut [f32], faces: &[Face]) {
    for c in 0..3 {
        let mean = faces
            .iter()
            .map(|f| offsets[3 * f.index() + c])
            .sum::<f32>()
            / faces.len().max(1) as f32;
        for f in Face::ALL {
            let v = &mut offsets[3 * f.index() + c];
            *v = if faces.contains(&f) { *v - mean } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_colour(rng: &mut crate::rng::Rng) -> BaseColour {
        let mut bar = || -> Vec<[f32; 3]> {
            (0..6)
                .map(|_| std::array::from_fn(|_| rng.range(0.3, 0.7)))
                .collect()
        };
        let (bar, knot_bar) = (bar(), bar());
        BaseColour {
            g_range: [0.0, 1.0],
            bar,
            knot_bar,
            knot_blend: 1.0,
            face_offsets: std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-0.1, 0.1))),
            mean_shift: [0.0; 3],
            white_balance: WhiteBalance {
                face_means: [[0.5; 3]; 6],
                mean: [0.5; 3],
                grain: None,
            },
        }
    }

    #[test]
    fn colour_gradient_matches_finite_differences() {
        let mut rng = crate::rng::Rng::new(4);
        let colour = sample_colour(&mut rng);
        let samples: Vec<ColourSample> = (0..400)
            .map(|_| ColourSample {
                face: rng.below(6),
                t: rng.range(0.0, 1.0),
                w: rng.range(0.0, 1.0),
                target: std::array::from_fn(|_| rng.range(0.2, 0.8)),
            })
            .collect();
        let cfg = ColourFitConfig::default();
        let (_, grad) = loss_and_gradient(&colour, &samples, &cfg);
        let params = pack(&colour);
        for k in (0..params.len()).step_by(4) {
            let at = |delta: f32| {
                let mut p = params.clone();
                p[k] += delta;
                let mut c = colour.clone();
                unpack(&mut c, &p);
                loss_and_gradient(&c, &samples, &cfg).0 as f64
            };
            let h = 1e-3;
            let fd = ((at(h) - at(-h)) / (2.0 * h as f64)) as f32;
            assert!(
                (fd - grad[k]).abs() < 2e-3,
                "parameter {k}: {fd} vs {}",
                grad[k]
            );
        }
    }

    #[test]
    fn offsets_stay_zero_mean_over_fitted_faces() {
        let mut offsets: Vec<f32> = (0..18).map(|i| i as f32 * 0.01).collect();
        let faces = [Face::A, Face::C, Face::E];
        centre_offsets(&mut offsets, &faces);
        for c in 0..3 {
            let sum: f32 = faces.iter().map(|f| offsets[3 * f.index() + c]).sum();
            assert!(sum.abs() < 1e-6);
            assert_eq!(offsets[3 * Face::B.index() + c], 0.0);
        }
    }
}
