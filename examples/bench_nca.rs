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

#[path = "common/nca_bench.rs"]
mod nca_bench;

use burn::module::Param;
use nca_bench::{arg, mode_size_steps, time_iterations, timed, train_config, train_data};
use xylem::device::DeviceKind;
use xylem::nca::MomentLoss;
use xylem::nca::model::{Nca, StepInputs};
use xylem::nca::perception::PerceptionImpl;
use xylem::nca::region::Region;
use xylem::nca::tensors::{tensor_from, to_vec};
use xylem::nca::train::Trainer;
use xylem::nca::unroll::{seed_state, unroll};
use xylem::rng::Rng;

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
    let (mode, size, steps) = mode_size_steps(&args);
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
    let config = train_config(size, size, steps, 0, "burn", perception_name(imp));
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
    let (values, t) = timed(|| to_vec(unroll(&model, seed, &inputs, steps, slab, |_| {})).unwrap());
    assert!(values.iter().all(|v| v.is_finite()));
    let updates = (size * size * size * steps) as f64;
    println!(
        "burn unroll size={size} steps={steps} device={} perception={imp:?} threads={} cpu_seconds={:.3} seconds={:.3} cell_updates_per_cpu_s={:.4e} cell_updates_per_s={:.4e}",
        kind.name(),
        rayon::current_num_threads(),
        t.cpu,
        t.wall,
        updates / t.cpu,
        updates / t.wall
    );
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
    let config = train_config(size, crop, steps, segment, "burn", perception_name(imp));
    let data = train_data(size);
    let loss = MomentLoss::new(&data.targets, &kind.device());
    let mut trainer = Trainer::new(&config, &data, kind).unwrap();
    let (t, last) = time_iterations(&mut trainer, &loss, iters);
    println!(
        "burn train size={size} crop={crop} steps={steps} segment={segment} device={} perception={imp:?} threads={} cpu_seconds_per_iter={:.3} seconds_per_iter={:.3} loss={last:.4}",
        kind.name(),
        rayon::current_num_threads(),
        t.cpu,
        t.wall,
    );
}

fn perception_name(imp: PerceptionImpl) -> &'static str {
    match imp {
        PerceptionImpl::Shifted => "shifted",
        PerceptionImpl::Conv => "conv",
    }
}
