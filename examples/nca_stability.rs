//! Does a trained NCA hold its texture past its training horizon? (issue 12)
//!
//!     cargo run --release --example nca_stability -- MODEL_DIR [SIZE] [STEPS...] [--out DIR]
//!
//! Unrolls the model in MODEL_DIR (written by `xylem train`) once over a SIZE^3 volume
//! (default: its training grid) from its seed, and at each step count (default 24 90 256)
//! prints the value range of the colour volume (nothing is clamped) and the share of values
//! outside [0, 1]; then the mean absolute difference, in 8-bit levels, between the cut1 and
//! cut2 images of consecutive step counts. With `--out DIR` it also writes
//! DIR/cut1_STEPS.png, cut2_STEPS.png and C_STEPS.png (face C) for each step count.

use xylem::device::DeviceKind;
use xylem::frame::Plane;
use xylem::nca::config::Engine;
use xylem::nca::model_dir::TrainedModel;
use xylem::nca::synth::{SynthOptions, ValueRange, synthesise_at};
use xylem::slice::slice_plane;

fn main() -> xylem::Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let out = args.iter().position(|a| a == "--out").map(|i| {
        let dir = std::path::PathBuf::from(args.get(i + 1).expect("--out DIR"));
        args.drain(i..i + 2);
        dir
    });
    let dir = std::path::PathBuf::from(args.first().expect("usage: MODEL_DIR [SIZE] [STEPS...]"));
    let device = DeviceKind::Flex.device();
    let trained = TrainedModel::load(&dir, &device)?;
    let size = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(trained.meta.grid);
    let mut at: Vec<usize> = args.iter().skip(2).filter_map(|s| s.parse().ok()).collect();
    if at.is_empty() {
        at = vec![24, 90, 256];
    }
    let options = SynthOptions {
        size,
        steps: 0,
        seed: trained.meta.seed,
        slab_voxels: 1 << 18,
        engine: Engine::Fused,
    };
    let start = std::time::Instant::now();
    let volumes = synthesise_at(&trained, &options, &at, |_| {})?;
    println!("{size}^3, {:.1} s", start.elapsed().as_secs_f64());
    let cuts: Vec<[xylem::Image2; 2]> = volumes
        .iter()
        .map(|v| [Plane::cut1(), Plane::cut2()].map(|p| slice_plane(v, &p, size, size)))
        .collect();
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir).map_err(|e| xylem::XylemError::io(dir, e))?;
        for (steps, (v, [c1, c2])) in at.iter().zip(volumes.iter().zip(&cuts)) {
            let face = xylem::slice::slice_face(v, xylem::Face::C, size);
            for (name, img) in [("cut1", c1), ("cut2", c2), ("C", &face)] {
                xylem::io::save_png(img, &dir.join(format!("{name}_{steps}.png")))?;
            }
        }
    }
    for (steps, v) in at.iter().zip(&volumes) {
        println!("steps {steps:4}: values in {}", ValueRange::of(&v.data));
    }
    for i in 1..at.len() {
        let mad = |k: usize| {
            let (a, b) = (&cuts[i - 1][k], &cuts[i][k]);
            255.0
                * a.data
                    .iter()
                    .zip(&b.data)
                    .map(|(x, y)| (x - y).abs())
                    .sum::<f32>()
                / a.data.len() as f32
        };
        println!(
            "cuts {} vs {} steps: mean |difference| cut1 {:.2}, cut2 {:.2} levels of 255",
            at[i - 1],
            at[i],
            mad(0),
            mad(1)
        );
    }
    Ok(())
}
