//! How lightness and chroma go together on a solid texture's faces against the photos: the
//! measure behind the NCA study's "pink and green speckle" (docs/DESIGN.md, issue 12).
//!
//! In wood the dark pixels (pores, latewood) are darker *and* browner: on CN03's photos the
//! darkest 10 % are yellower than the brighter half and lightness correlates with the
//! yellow-blue axis at about -0.46. A texture whose dark pixels are grey-blue instead shows
//! the pink/green cast even when every single-axis colour statistic matches.
//!
//! ```text
//! cargo run --release --example colour_coupling -- SAMPLE_DIR RUN_DIR [RUN_DIR ...]
//! ```
//! prints, per folder (the sample's photos `X_col.png` first, then each run's
//! `synth/faces/X.png`), the mean over the six faces at 128 px of: the yellow-blue and
//! red-green shift of the darkest 10 % against the brighter half, and corr(L, yb).

use std::path::{Path, PathBuf};

use xylem::Image2;
use xylem::frame::Face;
use xylem::io::load_rgb;
use xylem::series::pearson;

const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// Lightness, red-green and yellow-blue of every pixel.
fn opponent(img: &Image2) -> [Vec<f32>; 3] {
    let (s2, s6) = (std::f32::consts::FRAC_1_SQRT_2, 1.0 / 6f32.sqrt());
    let mut out = [Vec::new(), Vec::new(), Vec::new()];
    for px in img.data.chunks_exact(3) {
        out[0].push(px.iter().zip(LUMA).map(|(v, w)| v * w).sum());
        out[1].push(s2 * (px[0] - px[1]));
        out[2].push(s6 * (px[0] + px[1] - 2.0 * px[2]));
    }
    out
}

fn mean(v: impl Iterator<Item = f32>) -> f32 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n.max(1) as f32
}

/// (yb shift, rg shift, corr(L, yb)) of one face.
fn coupling(img: &Image2) -> [f32; 3] {
    let [l, rg, yb] = opponent(&img.resized(128, 128));
    let mut sorted = l.clone();
    sorted.sort_by(f32::total_cmp);
    let dark = sorted[sorted.len() / 10];
    let median = sorted[sorted.len() / 2];
    let shift = |c: &[f32]| {
        let d = mean(
            l.iter()
                .zip(c)
                .filter(|(x, _)| **x <= dark)
                .map(|(_, v)| *v),
        );
        let b = mean(
            l.iter()
                .zip(c)
                .filter(|(x, _)| **x >= median)
                .map(|(_, v)| *v),
        );
        d - b
    };
    [shift(&yb), shift(&rg), pearson(&l, &yb)]
}

fn report(name: &str, faces: &[PathBuf]) -> xylem::Result<()> {
    let mut total = [0.0f32; 3];
    for path in faces {
        let c = coupling(&load_rgb(path)?);
        total
            .iter_mut()
            .zip(c)
            .for_each(|(t, v)| *t += v / faces.len() as f32);
    }
    println!(
        "{name:<40} dark yb {:+.4}  dark rg {:+.4}  corr(L, yb) {:+.3}",
        total[0], total[1], total[2]
    );
    Ok(())
}

fn main() -> xylem::Result<()> {
    let args: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    let Some((sample, runs)) = args.split_first() else {
        eprintln!("usage: colour_coupling SAMPLE_DIR RUN_DIR [RUN_DIR ...]");
        std::process::exit(2);
    };
    let photos: Vec<PathBuf> = Face::ALL
        .iter()
        .map(|f| sample.join(format!("{f}_col.png")))
        .collect();
    report(&format!("photos {}", name_of(sample)), &photos)?;
    for run in runs {
        let faces: Vec<PathBuf> = Face::ALL
            .iter()
            .map(|f| run.join(format!("synth/faces/{f}.png")))
            .collect();
        report(&name_of(run), &faces)?;
    }
    Ok(())
}

fn name_of(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
