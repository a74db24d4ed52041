//! The pipeline end to end with a tiny NCA, through the library (`xylem::pipeline`): every
//! stage of the demo writes its outputs, the metrics table compares the right references, a
//! re-run skips finished stages, and a folder of photos alone runs with predicted ring images;
//! through the binary: a leave-one-face-out `xylem run --json` on real data reports the
//! held-out face.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

mod common;
use common::{mokume_dir, scratch, xylem};

use xylem::Face;
use xylem::device::DeviceKind;
use xylem::nca::config::Engine;
use xylem::pipeline::{
    Counter, DemoOptions, NcaSource, Quiet, Reporter, RunLayout, RunOptions, demo, run,
};
use xylem::report::MetricsTable;
use xylem::rings::RingSource;

/// A reporter that keeps every line said or noted, one per line.
#[derive(Default)]
struct Recorder(RefCell<String>);

impl Recorder {
    fn take(&self) -> String {
        self.0.take()
    }
}

impl Reporter for Recorder {
    fn counter(&self, _: &str, _: u64) -> Box<dyn Counter> {
        Box::new(Quiet)
    }
    fn say(&self, line: &str) {
        self.0.borrow_mut().push_str(&format!("{line}\n"));
    }
    fn note(&self, line: &str) {
        self.say(line);
    }
}

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

/// The demo on a 96 px chestnut sample with the tiny NCA, unrolled `synth_steps` steps.
fn tiny_demo(nca: &Path, synth_steps: usize) -> DemoOptions {
    DemoOptions {
        species: "chestnut".into(),
        size: 96,
        nca_config: Some(nca.to_path_buf()),
        synth_steps,
        device: DeviceKind::Flex,
        engine: Engine::Fused,
    }
}

#[test]
fn demo_runs_every_stage_and_resumes_by_skipping_finished_ones() {
    let dir = scratch("demo");
    let nca = tiny_nca(&dir);
    let layout = RunLayout::new(dir.join("run"));
    let run_dir = layout.root();
    let log = Recorder::default();
    demo(&layout, &tiny_demo(&nca, 2), &log).unwrap();
    let said = log.take();
    assert!(
        said.contains("== fit\n") && said.contains("== train\n"),
        "{said}"
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
        assert!(run_dir.join(f).is_file(), "{f} missing");
    }
    // A synthetic sample is judged on its hidden cuts; the procedural model is its truth.
    let rows = metric_rows(run_dir);
    for method in ["nca", "base colour"] {
        for cut in ["cut1", "cut2"] {
            assert!(
                rows.contains(&(method.to_string(), cut.to_string())),
                "{rows:?}"
            );
        }
    }
    assert!(rows.iter().all(|(m, _)| m != "procedural"), "{rows:?}");
    let sheet = image::open(layout.sheet()).unwrap();
    assert!(sheet.width() > 5 * 160 && sheet.height() > 8 * 160);
    let html = std::fs::read_to_string(layout.report_page()).unwrap();
    assert!(
        html.contains("../sheet.png") && html.contains("<table"),
        "{html}"
    );

    let modified = || {
        std::fs::metadata(run_dir.join("train/model.bpk"))
            .unwrap()
            .modified()
            .unwrap()
    };
    let before = modified();
    demo(&layout, &tiny_demo(&nca, 2), &log).unwrap();
    let said = log.take();
    for stage in ["fit", "train", "synth"] {
        assert!(
            said.contains(&format!("== {stage} (done, skipped)")),
            "{stage}: {said}"
        );
    }
    assert_eq!(before, modified(), "the trained model was rewritten");

    // A stage without its completion marker (killed after its first file) is redone.
    std::fs::remove_file(run_dir.join("synth/.done")).unwrap();
    demo(&layout, &tiny_demo(&nca, 2), &log).unwrap();
    let said = log.take();
    assert!(said.contains("== synth\n"), "{said}");
    assert!(run_dir.join("synth/.done").is_file());

    // Other options on the same folder are refused, naming what changed, and nothing
    // is rewritten.
    let err = demo(&layout, &tiny_demo(&nca, 3), &log)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("run.toml") && err.contains("synth_steps: was 2, now 3"),
        "{err}"
    );
    assert_eq!(before, modified(), "the trained model was rewritten");
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
}

/// Issue 13: a folder of the six photos of H11 alone (and its knot markers) runs through the
/// whole pipeline, the ring images predicted from the photos.
#[test]
fn run_on_photos_alone_predicts_the_ring_images() {
    let Some(data) = mokume_dir() else { return };
    let dir = scratch("run-h11-photos");
    let photos = common::photos_only(&data.join("H11"), "run-h11-photos-only");
    let nca = tiny_nca(&dir);
    let layout = RunLayout::new(dir.join("run"));
    let options = RunOptions {
        sample: photos.to_path_buf(),
        faces: Face::ALL.to_vec(),
        nca: NcaSource::File(nca),
        fit_config: None,
        rings: RingSource::Auto,
        species: "chestnut".into(),
        synth_steps: 2,
        image_size: 64,
        device: DeviceKind::Flex,
        engine: Engine::Fused,
    };
    let log = Recorder::default();
    run(&layout, &options, &log).unwrap();
    let said = log.take();
    assert!(
        said.contains("ring images predicted from the photos for faces A,B,C,D,E,F"),
        "{said}"
    );
    for file in [
        layout.fit_file(),
        layout.sheet(),
        layout.metrics(),
        layout.report_page(),
    ] {
        assert!(file.is_file(), "{}", file.display());
    }
}
