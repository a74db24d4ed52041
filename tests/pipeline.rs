//! `xylem demo` and `xylem run` end to end with a tiny NCA: every stage writes its outputs,
//! the metrics table compares the right references, a re-run skips finished stages, and a
//! leave-one-face-out run on real data reports the held-out face, and a folder of photos alone
//! runs with predicted ring images.

use std::path::{Path, PathBuf};

mod common;
use common::{mokume_dir, run_ok_said, scratch, xylem};

use xylem::report::MetricsTable;

/// A 16^3 NCA trained for 3 iterations on whole faces (the smallest the style loss accepts).
fn tiny_nca(dir: &Path) -> PathBuf {
    let path = dir.join("tiny_nca.toml");
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(
        &path,
        "seed = 2\n[model]\nhidden = 8\n[volume]\nsize = 16\ncrop = 16\n[schedule]\n\
         iterations = 3\nsteps = [2, 3]\n[pool]\nsize = 0\n",
    )
    .unwrap();
    path
}

/// (method, image) pairs of a run's metrics table.
fn metric_rows(run: &Path) -> Vec<(String, String)> {
    let table = MetricsTable::read(&run.join("metrics.csv")).unwrap();
    assert_eq!(&table.header[..2], ["method", "image"]);
    for row in &table.rows {
        for v in &row[2..] {
            let x: f32 = v.parse().unwrap_or_else(|_| panic!("{v} in {row:?}"));
            assert!(x.is_finite(), "{row:?}");
        }
    }
    table
        .rows
        .iter()
        .map(|r| (r[0].clone(), r[1].clone()))
        .collect()
}

#[test]
fn demo_runs_every_stage_and_resumes_by_skipping_finished_ones() {
    let dir = scratch("demo");
    let nca = tiny_nca(&dir);
    let run = dir.join("run");
    let demo = || {
        let mut cmd = xylem();
        cmd.args(["demo", "--size", "96", "--synth-steps", "2", "--nca-config"])
            .arg(&nca)
            .arg("--out")
            .arg(&run);
        cmd
    };
    let log = run_ok_said(&mut demo());
    assert!(
        log.contains("== fit\n") && log.contains("== train\n"),
        "{log}"
    );
    for f in [
        "sample/truth/cut1.png",
        "fit/fit.toml",
        "train/model.bpk",
        "synth/volume.npy",
        "sheet.png",
        "unfolded.png",
        "renders/cubes.png",
        "renders/bowls.png",
        "renders/turntable_nca.png",
        "report/index.html",
    ] {
        assert!(run.join(f).is_file(), "{f} missing");
    }
    // A synthetic sample is judged on its hidden cuts; the procedural model is its truth.
    let rows = metric_rows(&run);
    for method in ["nca", "base colour"] {
        for cut in ["cut1", "cut2"] {
            assert!(
                rows.contains(&(method.to_string(), cut.to_string())),
                "{rows:?}"
            );
        }
    }
    assert!(rows.iter().all(|(m, _)| m != "procedural"), "{rows:?}");
    let sheet = image::open(run.join("sheet.png")).unwrap();
    assert!(sheet.width() > 5 * 160 && sheet.height() > 8 * 160);
    let html = std::fs::read_to_string(run.join("report/index.html")).unwrap();
    assert!(
        html.contains("../sheet.png") && html.contains("<table"),
        "{html}"
    );

    let before = std::fs::metadata(run.join("train/model.bpk"))
        .unwrap()
        .modified()
        .unwrap();
    let log = run_ok_said(&mut demo());
    for stage in ["fit", "train", "synth"] {
        assert!(
            log.contains(&format!("== {stage} (done, skipped)")),
            "{stage}: {log}"
        );
    }
    let after = std::fs::metadata(run.join("train/model.bpk"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after, "the trained model was rewritten");

    // A stage without its completion marker (killed after its first file) is redone.
    std::fs::remove_file(run.join("synth/.done")).unwrap();
    let log = run_ok_said(&mut demo());
    assert!(log.contains("== synth\n"), "{log}");
    assert!(run.join("synth/.done").is_file());

    // Other options on the same folder are refused, naming what changed, and nothing
    // is rewritten.
    let out = xylem()
        .args(["demo", "--size", "96", "--synth-steps", "3", "--nca-config"])
        .arg(&nca)
        .arg("--out")
        .arg(&run)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("run.toml") && err.contains("synth_steps: was 2, now 3"),
        "{err}"
    );
    let again = std::fs::metadata(run.join("train/model.bpk"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, again, "the trained model was rewritten");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_on_real_data_reports_the_held_out_face() {
    let Some(data) = mokume_dir() else { return };
    let dir = scratch("run-cn03");
    let nca = tiny_nca(&dir);
    let run = dir.join("run");
    let output = xylem()
        .args([
            "run",
            "--json",
            "--faces",
            "A,B,C,D,E",
            "--synth-steps",
            "2",
            "--image-size",
            "64",
        ])
        .arg("--sample")
        .arg(data.join("CN03"))
        .arg("--nca-config")
        .arg(&nca)
        .arg("--out")
        .arg(&run)
        .output()
        .expect("run xylem");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // --json: stdout is one summary object with every stage and the NCA's metrics.
    let summary = String::from_utf8_lossy(&output.stdout);
    assert_eq!(summary.lines().count(), 1, "{summary}");
    assert!(summary.starts_with("{\"command\": \"run\""), "{summary}");
    for stage in [
        "fit", "train", "synth", "sheet", "renders", "metrics", "report",
    ] {
        assert!(
            summary.contains(&format!("{{\"stage\": \"{stage}\", \"seconds\": ")),
            "{stage}: {summary}"
        );
    }
    assert!(
        summary.contains("\"image\": \"F (held out)\", \"ring_ncc\": "),
        "{summary}"
    );
    let rows = metric_rows(&run);
    for method in ["nca", "base colour", "procedural"] {
        assert!(
            rows.contains(&(method.to_string(), "F (held out)".to_string())),
            "{rows:?}"
        );
    }
    assert_eq!(
        rows.len(),
        3,
        "only the held-out face is a fair reference: {rows:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 13: a folder of the six photos of H11 alone (and its knot markers) runs through the
/// whole pipeline, the ring images predicted from the photos.
#[test]
fn run_on_photos_alone_predicts_the_ring_images() {
    let Some(data) = mokume_dir() else { return };
    let dir = scratch("run-h11-photos");
    let photos = common::photos_only(&data.join("H11"), "run-h11-photos-only");
    let nca = tiny_nca(&dir);
    let run = dir.join("run");
    let said = run_ok_said(
        xylem()
            .args([
                "run",
                "--synth-steps",
                "2",
                "--image-size",
                "64",
                "--sample",
            ])
            .arg(&photos)
            .arg("--nca-config")
            .arg(&nca)
            .arg("--out")
            .arg(&run),
    );
    assert!(
        said.contains("ring images predicted from the photos for faces A,B,C,D,E,F"),
        "{said}"
    );
    for file in [
        "fit/fit.toml",
        "sheet.png",
        "metrics.csv",
        "report/index.html",
    ] {
        assert!(run.join(file).is_file(), "{file}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
