//! Speed of the fused NCA kernels (`nca::fused`), for side-by-side figures with burn
//! (`examples/bench_nca.rs`) and the PyTorch reference (`../shared/bench/nca_torch.py`).
//!
//!     cargo run --release --example bench_fused -- unroll SIZE STEPS [ISA]
//!
//! ISA is best (default), avx512, avx2 or portable. `unroll` runs STEPS steps of a SIZE^3
//! volume (weights random like a trained model's, 2 conditioning channels) after one
//! warm-up step and prints cell-updates per second. Denormals are flushed to zero as in the
//! CLI. Threads: rayon's default (RAYON_NUM_THREADS to change).

use std::time::Instant;

use xylem::nca::fused::{FixedInputs, Isa, MlpWeights, Stepper};
use xylem::nca::region::Region;
use xylem::rng::Rng;

fn arg<T: std::str::FromStr>(args: &[String], i: usize, default: T) -> T {
    args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default)
}

fn main() {
    xylem::nca::denormals::flush_denormals_to_zero();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map(String::as_str).unwrap_or("unroll");
    let size: usize = arg(&args, 1, 64);
    let steps: usize = arg(&args, 2, 8);
    let isa: Isa = args
        .get(3)
        .map_or_else(Isa::best, |s| s.parse().expect("instruction set"));
    match mode {
        "unroll" => bench_unroll(size, steps, isa),
        other => panic!("unknown mode {other:?}; expected unroll"),
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
    let t = Instant::now();
    let state = st.unroll(seed, steps, |_| {});
    let dt = t.elapsed().as_secs_f64();
    assert!(state.iter().all(|v| v.is_finite()));
    println!(
        "fused unroll size={size} steps={steps} isa={isa} threads={} seconds={dt:.3} cell_updates_per_s={:.4e}",
        rayon::current_num_threads(),
        (n * steps) as f64 / dt
    );
}
