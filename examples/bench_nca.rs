//! NCA speed, for side-by-side figures with the PyTorch reference
//! (`../shared/bench/nca_torch.py`, same architecture).
//!
//!     cargo run --release --example bench_nca -- unroll SIZE STEPS [DEVICE] [PERCEPTION]
//!     cargo run --release --example bench_nca -- train SIZE STEPS [ITERS] [DEVICE] [PERCEPTION] [SEGMENT] [CROP]
//!
//! DEVICE is flex (default) or ndarray, PERCEPTION shifted (default) or conv, SEGMENT the
//! checkpoint segment length (0 = whole unroll on the tape, default), CROP the side of the
//! corner crops trained on (default SIZE: the whole volume, loss on all six faces).
//!
//! `unroll` runs STEPS steps of a SIZE^3 volume without gradients (weights random like a
//! trained model's, 2 conditioning channels) after one warm-up step and prints cell-updates
//! per second. `train` runs ITERS (default 3) training iterations of `nca::train::Trainer`
//! on the burn engine (`examples/bench_fused.rs` measures the fused one) (unroll, stand-in face loss + overflow, backward, gradient normalisation, Adam) after one
//! warm-up iteration and prints the mean seconds per iteration. Peak memory: run under
//! `/usr/bin/time -v` (one configuration per process). Denormals are flushed to zero as in
//! the CLI (`nca::denormals`); set `XYLEM_KEEP_DENORMALS=1` to measure without.

use std::time::Instant;

use burn::module::Param;
use xylem::Image2;
use xylem::device::DeviceKind;
use xylem::frame::Face;
use xylem::nca::fit_source::{FitRecord, RampColours};
use xylem::nca::model::{Nca, StepInputs};
use xylem::nca::perception::PerceptionImpl;
use xylem::nca::region::Region;
use xylem::nca::tensors::{tensor_from, to_vec};
use xylem::nca::train::{TrainData, Trainer};
use xylem::nca::unroll::{seed_state, unroll};
use xylem::nca::{MomentLoss, TrainConfig};
use xylem::presets::load_field_preset;
use xylem::rng::Rng;

fn arg<T: std::str::FromStr>(args: &[String], i: usize, default: T) -> T {
    args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default)
}

fn perception(name: &str) -> PerceptionImpl {
    match name {
        "conv" => PerceptionImpl::Conv,
        _ => PerceptionImpl::Shifted,
    }
}

fn main() {
    // As `xylem train` and `xylem synth` do; XYLEM_KEEP_DENORMALS=1 measures without.
    if std::env::var_os("XYLEM_KEEP_DENORMALS").is_none() {
        xylem::nca::denormals::flush_denormals_to_zero();
    }
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map(String::as_str).unwrap_or("unroll");
    let size: usize = arg(&args, 1, 64);
    let steps: usize = arg(&args, 2, 8);
    match mode {
        "unroll" => {
            let device: DeviceKind = arg(&args, 3, DeviceKind::Flex);
            let imp = perception(args.get(4).map_or("shifted", String::as_str));
            bench_unroll(size, steps, device, imp);
        }
        "train" => {
            let iters: usize = arg(&args, 3, 3);
            let device: DeviceKind = arg(&args, 4, DeviceKind::Flex);
            let imp = perception(args.get(5).map_or("shifted", String::as_str));
            let segment: usize = arg(&args, 6, 0);
            let crop: usize = arg(&args, 7, size);
            bench_train(size, steps, iters, device, imp, segment, crop);
        }
        other => panic!("unknown mode {other:?}; expected unroll or train"),
    }
}

fn bench_unroll(size: usize, steps: usize, kind: DeviceKind, imp: PerceptionImpl) {
    let device = kind.device();
    let config = quick_config(size, size, steps, imp, 0);
    let spec = &config.model;
    let mut model = Nca::init(spec, 1, &device);
    let mut rng = Rng::new(2);
    let (c, h) = (spec.state_channels, spec.hidden);
    let w2: Vec<f32> = (0..c * h).map(|_| 0.02 * rng.normal()).collect();
    model.w2 = Param::from_tensor(tensor_from(w2, [c, h], &device));
    let region = Region::whole(size);
    let cond: Vec<f32> = (0..2 * region.voxels())
        .map(|_| rng.range(-0.5, 0.5))
        .collect();
    let cond = tensor_from(cond, [2, size, size, size], &device);
    let inputs = StepInputs::new(Some(cond), region.positions(&device), imp);
    let seed = seed_state(c, 0.05, &region, 3, &device);
    let slab = config.memory.slab_voxels;
    let warm = unroll(&model, seed.clone(), &inputs, 1, slab, |_| {});
    let _ = to_vec(warm).unwrap();
    let t = Instant::now();
    let state = unroll(&model, seed, &inputs, steps, slab, |_| {});
    let values = to_vec(state).unwrap();
    let dt = t.elapsed().as_secs_f64();
    assert!(values.iter().all(|v| v.is_finite()));
    println!(
        "burn unroll size={size} steps={steps} device={} perception={imp:?} threads={} seconds={dt:.3} cell_updates_per_s={:.4e}",
        kind.name(),
        rayon::current_num_threads(),
        (size * size * size * steps) as f64 / dt
    );
}

fn quick_config(
    size: usize,
    crop: usize,
    steps: usize,
    imp: PerceptionImpl,
    segment: usize,
) -> TrainConfig {
    let text = format!(
        "seed = 1\n[model]\nperception = \"{}\"\n[volume]\nsize = {size}\ncrop = {crop}\n\
         [schedule]\niterations = 1000\nsteps = [{steps}, {steps}]\n[pool]\nsize = 0\n\
         [memory]\nsegment_steps = {segment}\n[compute]\nengine = \"burn\"\n",
        match imp {
            PerceptionImpl::Shifted => "shifted",
            PerceptionImpl::Conv => "conv",
        }
    );
    TrainConfig::parse(&text, std::path::Path::new("<bench>")).expect("bench config")
}

fn bench_train(
    size: usize,
    steps: usize,
    iters: usize,
    kind: DeviceKind,
    imp: PerceptionImpl,
    segment: usize,
    crop: usize,
) {
    let config = quick_config(size, crop, steps, imp, segment);
    let mut rng = Rng::new(5);
    let targets: [Option<Image2>; 6] = std::array::from_fn(|_| {
        let data = (0..size * size * 3).map(|_| rng.uniform()).collect();
        Some(Image2::from_data(size, size, 3, data).unwrap())
    });
    let fit = FitRecord {
        field: load_field_preset("distorted").unwrap(),
        base_colour: RampColours {
            light: [0.7, 0.55, 0.4],
            dark: [0.4, 0.3, 0.2],
        },
    };
    let conditioning = fit.conditioning();
    let normalisation = conditioning.normalisation([0.6, 0.45, 0.3]);
    let data = TrainData {
        faces: Face::ALL.to_vec(),
        targets,
        fit,
        conditioning,
        normalisation,
    };
    let loss = MomentLoss::new(&data.targets, &kind.device());
    let mut trainer = Trainer::new(&config, &data, kind).unwrap();
    trainer.iterate(&loss).unwrap(); // warm-up
    let t = Instant::now();
    let mut last = 0.0;
    for _ in 0..iters {
        last = trainer.iterate(&loss).unwrap().loss;
    }
    let dt = t.elapsed().as_secs_f64() / iters as f64;
    println!(
        "burn train size={size} crop={crop} steps={steps} segment={segment} device={} perception={imp:?} threads={} seconds_per_iter={dt:.3} loss={last:.4}",
        kind.name(),
        rayon::current_num_threads(),
    );
}
