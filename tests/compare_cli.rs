//! `xylem compare` and `xylem texture2d` end to end on tiny images.

mod common;
use common::xylem;

use std::path::Path;
use std::process::Command;

use xylem::Image2;
use xylem::io::{load_rgb, save_png};

fn run(cmd: &mut Command) -> (bool, String, String) {
    let out = cmd.output().expect("run xylem");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Bands with dots (a stand-in wood face), written as a PNG.
fn write_wood(path: &Path, side: usize, phase: f32) {
    let mut img = Image2::filled(side, side, 3, 0.0);
    for r in 0..side {
        for c in 0..side {
            let band = ((c as f32 + 0.7 * r as f32) * 0.25 + phase).sin();
            let dot = if (r * 5 + c * 3) % 9 == 0 { 0.2 } else { 0.0 };
            let v = 0.6 + 0.12 * band - dot;
            img.pixel_mut(r, c).copy_from_slice(&[v + 0.1, v, v - 0.1]);
        }
    }
    save_png(&img, path).unwrap();
}

#[test]
fn compare_prints_one_json_object_and_writes_the_sheet() {
    let dir = common::scratch_dir("compare");
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    write_wood(&a, 64, 0.0);
    write_wood(&b, 32, 1.0);
    let sheet = dir.join("sheet.png");
    let compare_with_sheet = || {
        run(xylem()
            .arg("compare")
            .arg(&a)
            .arg(&b)
            .arg("--sheet")
            .arg(&sheet))
    };
    let (ok, stdout, stderr) = compare_with_sheet();
    assert!(ok, "{stderr}");
    let line = stdout.trim();
    assert!(
        line.starts_with('{') && line.ends_with('}') && !line.contains('\n'),
        "{stdout}"
    );
    for key in xylem::metrics::METRIC_NAMES {
        assert!(
            line.contains(&format!("\"{key}\": ")),
            "{key} missing: {line}"
        );
    }
    let picture = load_rgb(&sheet).unwrap();
    assert!(picture.width > 3 * 64 && picture.height > 64);
    // the sheet is not replaced without --force
    let (ok, _, stderr) = compare_with_sheet();
    assert!(!ok && stderr.contains("--force"), "{stderr}");
    // a missing file names itself
    let (ok, _, stderr) = run(xylem().arg("compare").arg(&a).arg(dir.join("nope.png")));
    assert!(!ok && stderr.contains("nope.png"), "{stderr}");
}

#[test]
fn texture2d_writes_result_target_and_config() {
    let dir = common::scratch_dir("texture2d");
    let target = dir.join("target-photo.png");
    write_wood(&target, 48, 0.0);
    let out = dir.join("out");
    let (ok, stdout, stderr) = run(xylem()
        .args(["texture2d", "--size", "32", "--steps", "3", "--target"])
        .arg(&target)
        .arg("--out")
        .arg(&out));
    assert!(ok, "{stderr}");
    assert!(stdout.contains("loss"), "{stdout}");
    for f in [
        "target.png",
        "initial.png",
        "result.png",
        "side_by_side.png",
        "loss.csv",
        "config.toml",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("loss.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    let config = std::fs::read_to_string(out.join("config.toml")).unwrap();
    assert!(
        config.contains("steps = 3") && config.contains("[loss.swd]"),
        "{config}"
    );
    // the written config reproduces the run exactly (same seeds, same result)
    let again = dir.join("again");
    let (ok, _, stderr) = run(xylem()
        .arg("texture2d")
        .arg("--target")
        .arg(&target)
        .arg("--config")
        .arg(out.join("config.toml"))
        .arg("--out")
        .arg(&again));
    assert!(ok, "{stderr}");
    assert_eq!(
        std::fs::read(out.join("result.png")).unwrap(),
        std::fs::read(again.join("result.png")).unwrap()
    );
}
