//! Set-up shared by the NCA benchmarks (`bench_nca.rs`: burn, `bench_fused.rs`: fused):
//! their command line, the training config, synthetic training data and the timing of
//! training iterations.

use std::time::Instant;

use xylem::Image2;
use xylem::config::ConfigFile;
use xylem::frame::Face;
use xylem::nca::fit_source::{FitRecord, RampColours};
use xylem::nca::train::{TrainData, Trainer};
use xylem::nca::{FaceLoss, TrainConfig};
use xylem::presets::load_field_preset;
use xylem::rng::Rng;

/// The `i`-th command-line argument, or `default` where it is absent or does not parse.
pub fn arg<T: std::str::FromStr>(args: &[String], i: usize, default: T) -> T {
    args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default)
}

/// The arguments both benchmarks start with: MODE (default unroll), SIZE (64), STEPS (8).
pub fn mode_size_steps(args: &[String]) -> (&str, usize, usize) {
    let mode = args.first().map(String::as_str).unwrap_or("unroll");
    (mode, arg(args, 1, 64), arg(args, 2, 8))
}

/// A training config: SIZE^3 grid, CROP^3 corner crops (whole volume if CROP = SIZE),
/// STEPS steps per iteration, no pool, checkpoint segments of SEGMENT steps.
pub fn train_config(
    size: usize,
    crop: usize,
    steps: usize,
    segment: usize,
    engine: &str,
    perception: &str,
) -> TrainConfig {
    let text = format!(
        "seed = 1\n[model]\nperception = \"{perception}\"\n[volume]\nsize = {size}\ncrop = {crop}\n\
         [schedule]\niterations = 1000\nsteps = [{steps}, {steps}]\n[pool]\nsize = 0\n\
         [memory]\nsegment_steps = {segment}\n[compute]\nengine = \"{engine}\"\n"
    );
    TrainConfig::parse(&text, std::path::Path::new("<bench>")).expect("bench config")
}

/// Random face targets at SIZE^2 and the `distorted` field with a ring ramp as B and G.
pub fn train_data(size: usize) -> TrainData {
    let mut rng = Rng::new(5);
    let targets: [Option<Image2>; 6] = std::array::from_fn(|_| {
        let data = (0..size * size * 3).map(|_| rng.uniform()).collect();
        Some(Image2::from_data(size, size, 3, data).unwrap())
    });
    let fit = FitRecord {
        field: load_field_preset("distorted").unwrap(),
        base_colour: Some(RampColours {
            light: [0.7, 0.55, 0.4],
            dark: [0.4, 0.3, 0.2],
        }),
    };
    let conditioning = fit.conditioning();
    let normalisation = conditioning.normalisation([0.6, 0.45, 0.3]);
    let guides = xylem::nca::train::face_guides::phase_guides(
        conditioning.growth.as_ref(),
        &Face::ALL,
        size,
    );
    TrainData {
        faces: Face::ALL.to_vec(),
        targets,
        guides,
        fit,
        conditioning,
        normalisation,
    }
}

/// Wall and CPU seconds of a run.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    pub wall: f64,
    pub cpu: f64,
}

/// Times `f`.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Timing) {
    let (t, cpu) = (Instant::now(), cpu_seconds());
    let out = f();
    let timing = Timing {
        wall: t.elapsed().as_secs_f64(),
        cpu: cpu_seconds() - cpu,
    };
    (out, timing)
}

/// Mean wall and CPU seconds per iteration over `iters` iterations after one warm-up, and
/// the last loss.
pub fn time_iterations(trainer: &mut Trainer, loss: &dyn FaceLoss, iters: usize) -> (Timing, f32) {
    trainer.iterate(loss).unwrap(); // warm-up
    let (last, t) = timed(|| {
        let mut last = 0.0;
        for _ in 0..iters {
            last = trainer.iterate(loss).unwrap().loss;
        }
        last
    });
    let per = |s: f64| s / iters as f64;
    (
        Timing {
            wall: per(t.wall),
            cpu: per(t.cpu),
        },
        last,
    )
}

/// CPU time of all threads of this process so far, in seconds (Linux: the sum of
/// `/proc/self/task/*/schedstat`, nanoseconds). On a shared machine the wall time includes
/// waiting for a core; the CPU time does not.
pub fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return f64::NAN;
    };
    let mut ns = 0u64;
    for task in tasks.flatten() {
        let stat = std::fs::read_to_string(task.path().join("schedstat")).unwrap_or_default();
        ns += stat
            .split_whitespace()
            .next()
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0);
    }
    ns as f64 * 1e-9
}
