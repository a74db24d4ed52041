//! Growth-field throughput: points per second with and without knots, on 1 and 2 threads.
//!
//!     cargo run --release --example bench_field [-- SIZE]
//!
//! Evaluates G at every voxel centre of a SIZE^3 grid (default 128) for several presets and
//! prints one line per (preset, threads) with the best of 3 runs.

use std::time::Instant;

use xylem::field::GrowthField;
use xylem::presets::load_field_preset;
use xylem::volume::Volume;

fn main() {
    let size: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(128);
    let points = (size * size * size) as f64;
    println!("growth field throughput, {size}^3 = {points} points per run, best of 3");
    for preset in ["minimal", "distorted", "knot_alive", "knots"] {
        let cfg = load_field_preset(preset).expect("preset");
        let field = GrowthField::from_config(&cfg);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let best = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    let vol = pool.install(|| Volume::from_texture(&field, size));
                    std::hint::black_box(&vol);
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            println!(
                "{preset:>10} knots={} rate_grid={} threads={threads}: {:.2} M points/s ({best:.3} s)",
                cfg.knots.len(),
                field.rates.is_some(),
                points / best / 1e6
            );
        }
    }
}
