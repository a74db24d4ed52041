//! Procedural wood throughput: points per second per species preset on 1 and 2 threads, and
//! the time of a 256^3 RGB volume of the oak preset on 2 threads.
//!
//!     cargo run --release --example bench_procedural [-- SIZE [VOLUME]]
//!
//! Evaluates the model's RGB at every voxel centre of a SIZE^3 grid (default 96) for every
//! preset, best of 3 runs, then one VOLUME^3 oak volume (default 256) on 2 threads, best of 2.
//! Besides wall time it prints the process CPU time of each run (Linux `/proc/self/stat`,
//! 100 ticks per second), which shows how much of a wall time was waiting for a busy core.

use std::time::Instant;

use xylem::presets::{SPECIES_PRESETS, load_species_preset};
use xylem::procedural::ProceduralWood;
use xylem::volume::Volume;

/// Process CPU time (user + system) in seconds, if the platform reports it.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses and may contain spaces).
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Best wall time of `runs` evaluations and the CPU time of that run.
fn best_of(runs: usize, threads: usize, model: &ProceduralWood, size: usize) -> (f64, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    (0..runs)
        .map(|_| {
            let cpu = cpu_seconds().unwrap_or(f64::NAN);
            let t = Instant::now();
            let vol = pool.install(|| Volume::from_texture(model, size));
            std::hint::black_box(&vol);
            let wall = t.elapsed().as_secs_f64();
            (wall, cpu_seconds().unwrap_or(f64::NAN) - cpu)
        })
        .fold(
            (f64::INFINITY, f64::NAN),
            |a, b| if b.0 < a.0 { b } else { a },
        )
}

fn main() {
    let mut args = std::env::args().skip(1).map(|s| s.parse::<usize>().ok());
    let size = args.next().flatten().unwrap_or(96);
    let volume = args.next().flatten().unwrap_or(256);
    let points = (size * size * size) as f64;
    println!("procedural wood throughput, {size}^3 = {points} points per run, best of 3");
    for (name, _) in SPECIES_PRESETS {
        let t = Instant::now();
        let model = ProceduralWood::new(&load_species_preset(name).expect("preset"));
        let build = t.elapsed().as_secs_f64();
        for threads in [1, 2] {
            let (secs, cpu) = best_of(3, threads, &model, size);
            println!(
                "{name:>9} threads={threads}: {:6.2} M points/s ({secs:.3} s wall, {cpu:.2} s CPU, \
                 {:.0} ns CPU per point; model built in {build:.3} s)",
                points / secs / 1e6,
                cpu / points * 1e9
            );
        }
    }
    let oak = ProceduralWood::new(&load_species_preset("oak").expect("oak"));
    let (secs, cpu) = best_of(2, 2, &oak, volume);
    println!(
        "oak {volume}^3 RGB volume on 2 threads: {secs:.2} s wall, {cpu:.2} s CPU ({:.2} M points/s)",
        (volume * volume * volume) as f64 / secs / 1e6
    );
}
