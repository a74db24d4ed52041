//! The NCA unroll: deterministic seeds, slab-wise steps equal to whole steps, gradients
//! through an unroll equal to finite differences, and segment checkpointing equal to full
//! backprop.

mod common;
use common::{max_abs, max_abs_diff, random};

use burn::module::Param;
use burn::tensor::{Device, Tensor};
use xylem::Image2;
use xylem::frame::Face;
use xylem::nca::checkpoint::{Objective, unroll_gradients};
use xylem::nca::faces::face_patches;
use xylem::nca::model::{Nca, StepInputs};
use xylem::nca::region::Region;
use xylem::nca::tensors::{tensor_from, to_vec};
use xylem::nca::train::loss::{FaceLoss, MomentLoss};
use xylem::nca::unroll::{seed_state, step_in_slabs, unroll};
use xylem::nca::{ModelSpec, perception::PerceptionImpl};
use xylem::rng::Rng;

const N: usize = 6;

fn spec() -> ModelSpec {
    ModelSpec {
        hidden: 16,
        ..ModelSpec::default()
    }
}

/// A model with all three tensors random (a fresh model has w2 = 0, where the first layer
/// gets no gradient).
fn weights(spec: &ModelSpec) -> [Vec<f32>; 3] {
    let (h, i, c) = (spec.hidden, spec.inputs(), spec.state_channels);
    [
        random(h * i, 0.05, 1),
        random(h, 0.1, 2),
        random(c * h, 0.1, 3),
    ]
}

fn model(spec: &ModelSpec, w: &[Vec<f32>; 3], device: &Device) -> Nca {
    let (h, i, c) = (spec.hidden, spec.inputs(), spec.state_channels);
    let mut m = Nca::init(spec, 0, device);
    m.w1 = Param::from_tensor(tensor_from(w[0].clone(), [h, i], device));
    m.b1 = Param::from_tensor(tensor_from(w[1].clone(), [h], device));
    m.w2 = Param::from_tensor(tensor_from(w[2].clone(), [c, h], device));
    m
}

fn inputs(spec: &ModelSpec, region: &Region, device: &Device) -> StepInputs {
    let k = spec.cond_channels();
    let [x, y, z] = region.dims;
    let cond = tensor_from(random(k * x * y * z, 0.2, 9), [k, x, y, z], device);
    StepInputs::new(Some(cond), region.positions(device), spec.perception)
}

fn targets(device: &Device) -> MomentLoss {
    let mut rng = Rng::new(11);
    let faces: [Option<Image2>; 6] = std::array::from_fn(|_| {
        let data = (0..N * N * 3).map(|_| rng.uniform()).collect();
        Some(Image2::from_data(N, N, 3, data).unwrap())
    });
    MomentLoss::new(&faces, device)
}

/// A smooth objective of the final state: the stand-in style loss of its RGB faces plus
/// the mean square of the state.
fn objective(state: Tensor<4>, region: &Region, loss: &MomentLoss) -> Tensor<1> {
    let rgb = state.clone().narrow(0, 0, 3).add_scalar(0.5);
    let patches = face_patches(&rgb, region, &Face::ALL);
    loss.loss(&patches, 0) + state.square().mean().mul_scalar(0.5)
}

fn plain_objective(w: &[Vec<f32>; 3], steps: usize) -> f32 {
    let device = Device::flex();
    let spec = spec();
    let region = Region::whole(N);
    let m = model(&spec, w, &device);
    let inp = inputs(&spec, &region, &device);
    let s0 = seed_state(spec.state_channels, 0.3, &region, 5, &device);
    let s = unroll(&m, s0, &inp, steps, 1 << 20, |_| {});
    objective(s, &region, &targets(&device)).into_scalar::<f32>()
}

fn grads(w: &[Vec<f32>; 3], steps: usize, segment: usize) -> ([Vec<f32>; 3], f32) {
    let device = Device::flex();
    let ad = device.clone().autodiff();
    let spec = spec();
    let region = Region::whole(N);
    let m = model(&spec, w, &ad);
    let inp = inputs(&spec, &region, &device);
    let s0 = seed_state(spec.state_channels, 0.3, &region, 5, &device);
    let loss = targets(&device);
    let out = unroll_gradients(&m, s0, &inp, steps, segment, |s| Objective {
        total: objective(s, &region, &loss),
        terms: vec![],
    });
    let g = |id, dims: usize| -> Vec<f32> {
        match dims {
            1 => to_vec(out.grads.get::<1>(id).unwrap()).unwrap(),
            _ => to_vec(out.grads.get::<2>(id).unwrap()).unwrap(),
        }
    };
    ([g(m.w1.id, 2), g(m.b1.id, 1), g(m.w2.id, 2)], out.loss)
}

#[test]
fn unroll_is_deterministic_for_a_seed() {
    let device = Device::flex();
    let spec = spec();
    let region = Region::corner(12, N, 5);
    let w = weights(&spec);
    let run = |key: u64| {
        let m = model(&spec, &w, &device);
        let s0 = seed_state(spec.state_channels, 0.05, &region, key, &device);
        to_vec(unroll(
            &m,
            s0,
            &inputs(&spec, &region, &device),
            4,
            1 << 20,
            |_| {},
        ))
        .unwrap()
    };
    let (a, b, c) = (run(7), run(7), run(8));
    assert_eq!(a, b, "same seed, same unroll");
    assert_ne!(a, c, "another seed, another unroll");
    assert!(a.iter().all(|v| v.is_finite()));
}

#[test]
fn seed_of_a_crop_is_the_same_part_of_the_whole_seed() {
    let device = Device::flex();
    let whole = seed_state(4, 0.05, &Region::whole(8), 3, &device);
    let region = Region::corner(8, 3, 6);
    let crop = seed_state(4, 0.05, &region, 3, &device);
    let [ox, oy, oz] = region.offset;
    let part = whole.narrow(1, ox, 3).narrow(2, oy, 3).narrow(3, oz, 3);
    let (a, b) = (to_vec(crop).unwrap(), to_vec(part).unwrap());
    assert_eq!(a, b);
    assert!(a.iter().all(|v| v.abs() <= 0.05) && a.iter().any(|v| v.abs() > 0.01));
}

#[test]
fn slab_steps_equal_whole_steps() {
    let device = Device::flex();
    let spec = spec();
    let region = Region::whole(N);
    let w = weights(&spec);
    let m = model(&spec, &w, &device);
    let inp = inputs(&spec, &region, &device);
    let s0 = seed_state(spec.state_channels, 0.3, &region, 1, &device);
    let whole = to_vec(m.step(s0.clone(), &inp)).unwrap();
    // Slabs of 2 x 6 x 6 voxels: three slabs with halos.
    let slabbed = to_vec(step_in_slabs(&m, s0, &inp, 2 * N * N)).unwrap();
    let worst = max_abs_diff(&whole, &slabbed);
    assert!(worst < 1e-6, "max difference {worst}");
}

#[test]
fn conv_and_shifted_models_give_the_same_step() {
    let device = Device::flex();
    let mut spec = spec();
    let region = Region::whole(N);
    let w = weights(&spec);
    let s0 = seed_state(spec.state_channels, 0.3, &region, 1, &device);
    let mut outs = Vec::new();
    for imp in [PerceptionImpl::Shifted, PerceptionImpl::Conv] {
        spec.perception = imp;
        let m = model(&spec, &w, &device);
        outs.push(to_vec(m.step(s0.clone(), &inputs(&spec, &region, &device))).unwrap());
    }
    let worst = max_abs_diff(&outs[0], &outs[1]);
    assert!(worst < 1e-5, "max difference {worst}");
}

#[test]
fn gradients_through_three_steps_match_finite_differences() {
    let spec = spec();
    let w = weights(&spec);
    let (g, loss) = grads(&w, 3, 0);
    assert!((loss - plain_objective(&w, 3)).abs() < 1e-5 * loss.abs().max(1.0));
    let mut checked = 0;
    for (t, grad) in g.iter().enumerate() {
        // The entries with the largest gradients of each tensor, plus one fixed entry.
        let mut order: Vec<usize> = (0..grad.len()).collect();
        order.sort_by(|&a, &b| grad[b].abs().total_cmp(&grad[a].abs()));
        for &idx in order.iter().take(3).chain([grad.len() / 2].iter()) {
            let eps = 1e-2 * w[t][idx].abs().max(0.1);
            let mut plus = w.clone();
            plus[t][idx] += eps;
            let mut minus = w.clone();
            minus[t][idx] -= eps;
            let fd = (plain_objective(&plus, 3) - plain_objective(&minus, 3)) / (2.0 * eps);
            let tol = 1e-2 * grad[idx].abs().max(fd.abs()) + 5e-5;
            assert!(
                (fd - grad[idx]).abs() <= tol,
                "tensor {t} entry {idx}: autodiff {} vs finite difference {fd}",
                grad[idx]
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 12);
}

#[test]
fn segment_checkpointing_gives_full_backprop_gradients() {
    let spec = spec();
    let w = weights(&spec);
    let (full, loss_full) = grads(&w, 7, 0);
    for segment in [2, 3] {
        let (seg, loss_seg) = grads(&w, 7, segment);
        assert_eq!(loss_full, loss_seg);
        for (t, (a, b)) in full.iter().zip(&seg).enumerate() {
            let scale = max_abs(a);
            let worst = max_abs_diff(a, b);
            assert!(scale > 0.0, "tensor {t} has gradients");
            assert!(
                worst <= 1e-5 * scale,
                "segment {segment}, tensor {t}: max difference {worst} (scale {scale})"
            );
        }
    }
}
