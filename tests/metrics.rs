//! Comparison metrics: an image against itself is perfect; a mirrored copy loses ring and
//! grain alignment but keeps its texture distance; sizes and JSON; the real photos.

mod common;

use burn::tensor::Device;
use xylem::Image2;
use xylem::io::load_rgb;
use xylem::loss::LossConfig;
use xylem::metrics::lab::srgb_to_lab;
use xylem::metrics::{Comparer, METRIC_NAMES, Metrics};

fn comparer() -> Comparer {
    Comparer::new(&LossConfig::default_config(), &Device::flex())
}

/// Diagonal wavy bands with dark dots along them: a stand-in wood face.
fn wood(w: usize, h: usize, phase: f32) -> Image2 {
    let mut img = Image2::filled(w, h, 3, 0.0);
    for r in 0..h {
        for c in 0..w {
            let s = c as f32 + 0.7 * r as f32 + 4.0 * (r as f32 * 0.09).sin();
            let band = (s * 0.18 + phase).sin();
            let pore = if band > 0.6 && (r * 5 + c * 3) % 7 == 0 {
                0.25
            } else {
                0.0
            };
            let v = 0.62 + 0.1 * band - pore;
            img.pixel_mut(r, c)
                .copy_from_slice(&[v + 0.12, v + 0.02, v - 0.1]);
        }
    }
    img
}

fn mirrored(img: &Image2) -> Image2 {
    let mut out = img.clone();
    for r in 0..img.height {
        for c in 0..img.width {
            out.pixel_mut(r, c)
                .copy_from_slice(img.pixel(r, img.width - 1 - c));
        }
    }
    out
}

#[test]
fn an_image_against_itself_is_perfect() {
    let img = wood(96, 96, 0.0);
    let m = comparer().compare(&img, &img).unwrap();
    assert!((m.ring_ncc - 1.0).abs() < 1e-5, "{m:?}");
    assert!((m.orient - 1.0).abs() < 1e-5, "{m:?}");
    for v in [m.swd, m.swd_l, m.swd_chroma, m.de_mean, m.de_std, m.style] {
        assert!(v.abs() < 1e-5, "{m:?}");
    }
}

#[test]
fn a_mirrored_copy_loses_alignment_but_not_texture() {
    let img = wood(128, 128, 0.0);
    let c = comparer();
    let m = c.compare(&img, &mirrored(&img)).unwrap();
    // the same wood shifted by a ring phase: what "same texture" looks like in numbers
    let shifted = c.compare(&img, &wood(128, 128, 2.0)).unwrap();
    assert!(m.ring_ncc < 0.5, "mirrored ring_ncc {}", m.ring_ncc);
    assert!(
        m.orient < 0.0,
        "diagonal grain mirrored crosses the original: orient {}",
        m.orient
    );
    assert!(
        m.swd < 1e-5 && m.swd_l < 1e-5 && m.swd_chroma < 1e-5,
        "{m:?}"
    );
    assert!(m.de_mean < 1e-3 && m.de_std < 1e-3, "{m:?}");
    assert!(shifted.swd > m.swd, "{shifted:?}");
}

#[test]
fn metrics_separate_texture_colour_and_direction() {
    let img = wood(96, 96, 0.0);
    let c = comparer();
    // colour only: a uniform shift towards red keeps lightness patches, changes chroma
    let mut reddish = img.clone();
    for px in reddish.data.chunks_exact_mut(3) {
        px[0] = (px[0] + 0.08).min(1.0);
        px[2] = (px[2] - 0.05).max(0.0);
    }
    let m = c.compare(&img, &reddish).unwrap();
    assert!(m.de_mean > 3.0, "{m:?}");
    assert!(m.swd_chroma > 3.0 * m.swd_l, "{m:?}");
    assert!(m.ring_ncc > 0.95 && m.orient > 0.95, "{m:?}");
    // a flat image of the same mean colour: no texture, no rings
    let means = img.channel_means();
    let mut flat = Image2::filled(96, 96, 3, 0.0);
    for px in flat.data.chunks_exact_mut(3) {
        px.copy_from_slice(&means);
    }
    let m = c.compare(&img, &flat).unwrap();
    assert!(m.swd_l > 0.02 && m.de_std > 2.0, "{m:?}");
    assert!(m.ring_ncc.abs() < 1e-3 && m.orient.abs() < 1e-3, "{m:?}");
}

#[test]
fn sizes_are_matched_or_refused_and_json_names_every_metric() {
    let img = wood(96, 96, 0.0);
    let c = comparer();
    let m = c.compare(&img, &img.resized(48, 48)).unwrap();
    assert!(m.ring_ncc > 0.9, "a downscaled copy keeps its rings: {m:?}");
    let err = c.compare(&img, &wood(96, 64, 0.0)).unwrap_err();
    assert!(err.to_string().contains("aspect ratio"), "{err}");
    let json = m.to_json();
    for name in METRIC_NAMES {
        assert!(json.contains(&format!("\"{name}\": ")), "{json}");
    }
    let nan = Metrics {
        style: f32::NAN,
        ..m
    };
    assert!(nan.to_json().contains("\"style\": null"));
}

#[test]
fn lab_conversion_matches_reference_values() {
    // sRGB white, mid grey 0.5 and pure red (reference values of the CIE formulas, D65)
    let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 0.05);
    assert!(close(srgb_to_lab([1.0, 1.0, 1.0]), [100.0, 0.0, 0.0]));
    assert!(
        close(srgb_to_lab([0.5, 0.5, 0.5]), [53.39, 0.0, 0.0]),
        "{:?}",
        srgb_to_lab([0.5; 3])
    );
    assert!(
        close(srgb_to_lab([1.0, 0.0, 0.0]), [53.24, 80.09, 67.2]),
        "{:?}",
        srgb_to_lab([1.0, 0.0, 0.0])
    );
}

#[test]
fn real_photos_same_wood_scores_closer_than_the_other_cube() {
    let Some(dir) = common::mokume_dir() else {
        return;
    };
    let load =
        |cube: &str, face: &str| load_rgb(&dir.join(cube).join(format!("{face}_col.png"))).unwrap();
    let c = comparer();
    for (cube, other) in [("CN03", "H11"), ("H11", "CN03")] {
        let reference = load(cube, "A").crop(0, 0, 128, 128).unwrap();
        let same = c
            .compare(
                &reference,
                &load(cube, "A").crop(128, 128, 128, 128).unwrap(),
            )
            .unwrap();
        let mirrored_same = c.compare(&reference, &mirrored(&reference)).unwrap();
        let foreign = c
            .compare(
                &reference,
                &load(other, "A").crop(64, 64, 128, 128).unwrap(),
            )
            .unwrap();
        eprintln!(
            "{cube}: same photo {same:?}\n  mirrored {mirrored_same:?}\n  {other} A {foreign:?}"
        );
        assert!(
            same.swd < foreign.swd,
            "swd: {} vs {}",
            same.swd,
            foreign.swd
        );
        assert!(
            same.de_mean < foreign.de_mean,
            "dE_mean: {} vs {}",
            same.de_mean,
            foreign.de_mean
        );
        assert!(
            same.style < foreign.style,
            "style: {} vs {}",
            same.style,
            foreign.style
        );
        assert!(mirrored_same.swd < 1e-5);
        assert!(
            mirrored_same.ring_ncc < 0.9,
            "mirrored ring_ncc {}",
            mirrored_same.ring_ncc
        );
    }
}
