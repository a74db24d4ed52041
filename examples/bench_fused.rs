//! Speed of the fused NCA kernels (`nca::fused`), for side-by-side figures with burn
//! (`examples/bench_nca.rs`) and the PyTorch reference (`../shared/bench/nca_torch.py`).
//!
//!     cargo run --release --example bench_fused -- unroll SIZE STEPS [ISA]
//!     cargo run --release --example bench_fused -- train SIZE STEPS [ITERS] [SEGMENT] [CROP]
//!
//! ISA is best (default), avx512, avx2 or portable. `unroll` runs STEPS steps of a SIZE^3
//! volume (weights random like a trained model's, 2 conditioning channels) after one
//! warm-up step and prints cell-updates per second and GFLOP/s (2 (H I + C H) = 21 760 FLOP
//! per cell-update for the two layers; perception not counted). `train` runs ITERS
//! (default 3) iterations of the real `nca::train::Trainer` on the fused engine (unroll,
//! stand-in face loss + overflow in burn, fused backward, gradient normalisation, Adam)
//! after one warm-up iteration, exactly like `bench_nca train` does on the burn engine, and
//! prints the mean seconds per iteration. SEGMENT: checkpoint segment length (0 = keep every
//! state, default); CROP: side of the corner crops (default SIZE: whole volume, six faces).
//! Denormals are flushed to zero as in the CLI. Threads: rayon's default
//! (RAYON_NUM_THREADS to change). Peak memory: run under `/usr/bin/time -v`.

#[path = "common/nca_bench.rs"]
mod nca_bench;

use nca_bench::{arg, mode_size_steps, time_iterations, timed, train_config, train_data};
use xylem::device::DeviceKind;
use xylem::nca::MomentLoss;
use xylem::nca::fused::{FixedInputs, Isa, MlpWeights, Stepper};
use xylem::nca::region::Region;
use xylem::nca::train::Trainer;
use xylem::rng::Rng;

fn main() {
    xylem::nca::denormals::flush_denormals_to_zero();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mode, size, steps) = mode_size_steps(&args);
    match mode {
        "unroll" => {
            let isa: Isa = args
                .get(3)
                .map_or_else(Isa::best, |s| s.parse().expect("instruction set"));
            bench_unroll(size, steps, isa);
        }
        "train" => {
            let iters: usize = arg(&args, 3, 3);
            let segment: usize = arg(&args, 4, 0);
            let crop: usize = arg(&args, 5, size);
            bench_train(size, steps, iters, segment, crop);
        }
        other => panic!("unknown mode {other:?}; expected unroll or train"),
    }
}

/// Random weights of the default architecture (12 state, 2 conditioning, 128 hidden).
fn weights(rng: &mut Rng) -> MlpWeights {
    let (c, h, i) = (12, 128, 73);
    let std1 = 0.2 * (2.0 / (h + i) as f32).sqrt();
    MlpWeights {
        state: c,
        hidden: h,
        inputs: i,
        w1: (0..h * i).map(|_| std1 * rng.normal()).collect(),
        b1: (0..h).map(|_| 0.01 * rng.normal()).collect(),
        w2: (0..c * h).map(|_| 0.02 * rng.normal()).collect(),
    }
}

fn bench_unroll(size: usize, steps: usize, isa: Isa) {
    let mut rng = Rng::new(2);
    let w = weights(&mut rng);
    let region = Region::whole(size);
    let n = region.voxels();
    let cond: Vec<f32> = (0..2 * n).map(|_| rng.range(-0.5, 0.5)).collect();
    let fixed = FixedInputs::new(&region, cond, 2).expect("inputs");
    let st = Stepper::new(isa, &w, &fixed).expect("stepper");
    let seed: Vec<f32> = (0..12 * n).map(|_| rng.range(-0.05, 0.05)).collect();
    let warm = st.unroll(seed.clone(), 1, |_| {});
    assert!(warm.iter().all(|v| v.is_finite()));
    let (state, t) = timed(|| st.unroll(seed, steps, |_| {}));
    assert!(state.iter().all(|v| v.is_finite()));
    let updates = (n * steps) as f64;
    let flops = 2.0 * (w.hidden * w.inputs + w.state * w.hidden) as f64;
    println!(
        "fused unroll size={size} steps={steps} isa={isa} threads={} cpu_seconds={:.3} seconds={:.3} cell_updates_per_cpu_s={:.4e} cell_updates_per_s={:.4e} gflops_per_cpu_s={:.1} gflops={:.1}",
        rayon::current_num_threads(),
        t.cpu,
        t.wall,
        updates / t.cpu,
        updates / t.wall,
        updates * flops / t.cpu / 1e9,
        updates * flops / t.wall / 1e9
    );
}

fn bench_train(size: usize, steps: usize, iters: usize, segment: usize, crop: usize) {
    let config = train_config(size, crop, steps, segment, "fused", "shifted");
    let data = train_data(size);
    let kind = DeviceKind::Flex;
    let loss = MomentLoss::new(&data.targets, &kind.device());
    let mut trainer = Trainer::new(&config, &data, kind).unwrap();
    let (t, last) = time_iterations(&mut trainer, &loss, iters);
    println!(
        "fused train size={size} crop={crop} steps={steps} segment={segment} isa={} threads={} cpu_seconds_per_iter={:.3} seconds_per_iter={:.3} loss={last:.4}",
        trainer.isa,
        rayon::current_num_threads(),
        t.cpu,
        t.wall,
    );
}
