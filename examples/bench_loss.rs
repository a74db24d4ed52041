//! Style-loss cost: forward + backward for six generated faces (64^2, 128^2) and for 24
//! patches of 32^2 (the NCA's corner crops) against the six white-balanced
//! CN03 face photos (targets at 256 px), on flex and ndarray, with fixed and with redrawn
//! projections; plus the one-off target computation. Also times `Comparer::compare` on two
//! 256 px photos.
//!
//!     XYLEM_MOKUME_DIR=/work/shared/data/mokume cargo run --release --example bench_loss [-- ROUNDS [flex|ndarray]]
//!
//! Reports the median and best of ROUNDS (default 5) timed rounds after one warm-up, with
//! the process CPU time over the timed rounds (the machine is shared; see BENCHMARKS.md).

use std::path::PathBuf;
use std::time::Instant;

use burn::tensor::{Device, Distribution, Tensor};
use xylem::Image2;
use xylem::device::DeviceKind;
use xylem::io::load_rgb;
use xylem::loss::{LossConfig, StyleLoss};
use xylem::metrics::Comparer;

/// Process CPU time (user + system) in seconds, from /proc/self/stat.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map(|(_, rest)| rest.split_whitespace().collect())
        .unwrap_or_default();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn faces() -> Vec<Image2> {
    let dir = std::env::var_os("XYLEM_MOKUME_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/data/mokume"));
    ["A", "B", "C", "D", "E", "F"]
        .iter()
        .map(|f| {
            let path = dir.join("CN03").join(format!("{f}_col.png"));
            load_rgb(&path)
                .expect("CN03 face (set XYLEM_MOKUME_DIR)")
                .white_balanced()
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `count` generated `size`^2 images, image i paired with target i % 6 (the NCA's corner
/// crops: 8 corners x 3 faces = 24 patches of six targets).
fn bench(
    kind: DeviceKind,
    redraw: bool,
    (count, size): (usize, usize),
    rounds: usize,
    faces: &[Image2],
) {
    let mut cfg = LossConfig::default_config();
    cfg.swd.redraw = redraw;
    let device = kind.device();
    let loss = StyleLoss::new(&cfg, &device);
    let t = Instant::now();
    let targets = loss.targets(faces).expect("targets");
    let target_s = t.elapsed().as_secs_f64();
    let ad = device.clone().autodiff();
    let pairs: Vec<usize> = (0..count).map(|i| i % 6).collect();
    let mut times = Vec::new();
    let cpu0 = cpu_seconds();
    for round in 0..=rounds {
        let generated: Vec<Tensor<3>> = (0..count)
            .map(|_| {
                Tensor::<3>::random([3, size, size], Distribution::Uniform(0.3, 0.7), &ad)
                    .require_grad()
            })
            .collect();
        let t = Instant::now();
        let value = loss
            .loss_at(&generated, &targets, &pairs, round as u64 + 1)
            .expect("loss");
        let grads = value.backward();
        let g = generated[0].grad(&grads).expect("gradient");
        std::hint::black_box(g.into_data());
        if round > 0 {
            times.push(t.elapsed().as_secs_f64());
        } else {
            // the warm-up round's CPU time is not counted
        }
    }
    let cpu = cpu_seconds() - cpu0;
    println!(
        "{:>8} redraw={:<5} {count:>2} x {size}^2: forward+backward median {:.3} s, best {:.3} s (CPU {:.3} s/round incl. warm-up share); targets (six 256^2) {:.3} s",
        kind.name(),
        redraw,
        median(times.clone()),
        times.iter().copied().fold(f64::INFINITY, f64::min),
        cpu / (rounds + 1) as f64,
        target_s,
    );
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let faces = faces();
    let cfg = LossConfig::default_config();
    println!(
        "style loss: {} octaves, {} features per layer, {} projections per layer; {rounds} rounds",
        cfg.octaves,
        cfg.features_per_layer(),
        cfg.swd.projections
    );
    let kinds: Vec<DeviceKind> = match std::env::args().nth(2) {
        Some(name) => vec![name.parse().expect("flex or ndarray")],
        None => vec![DeviceKind::Flex, DeviceKind::Ndarray],
    };
    for kind in kinds {
        for redraw in [false, true] {
            for shape in [(6, 64), (6, 128), (24, 32)] {
                bench(kind, redraw, shape, rounds, &faces);
            }
        }
    }
    let comparer = Comparer::new(&cfg, &Device::flex());
    let t = Instant::now();
    let m = comparer.compare(&faces[0], &faces[2]).expect("compare");
    println!(
        "compare (two 256^2 images, all metrics): {:.3} s  {}",
        t.elapsed().as_secs_f64(),
        m.to_json()
    );
}
