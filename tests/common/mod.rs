//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The real Mokume data folder: `XYLEM_MOKUME_DIR`, or `../shared/data/mokume` beside the
/// checkout. CI has it; a missing folder fails the test (set XYLEM_SKIP_REAL_DATA=1 to skip
/// explicitly on a machine without the data).
pub fn mokume_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("XYLEM_MOKUME_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mokume"));
    if dir.join("CN03").is_dir() && dir.join("H11").is_dir() {
        return Some(dir);
    }
    if std::env::var_os("XYLEM_SKIP_REAL_DATA").is_some() {
        eprintln!(
            "skipping: no Mokume data at {} (XYLEM_SKIP_REAL_DATA set)",
            dir.display()
        );
        return None;
    }
    panic!(
        "Mokume data not found at {}; set XYLEM_MOKUME_DIR (or XYLEM_SKIP_REAL_DATA=1 to skip)",
        dir.display()
    );
}

/// A scratch folder for one test: removed first if an earlier run left it, and removed again
/// when the guard is dropped, so a failing (panicking) test does not leak it either. Set
/// `XYLEM_KEEP_SCRATCH=1` to keep the folders for a look after a failure. Not created; it
/// derefs to its `Path`.
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::env::var_os("XYLEM_KEEP_SCRATCH").is_none() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A fresh scratch folder for one test, named after the test process and `name`.
pub fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("xylem-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    Scratch(dir)
}

/// [`scratch`], created.
pub fn scratch_dir(name: &str) -> Scratch {
    let dir = scratch(name);
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    dir
}

/// The `xylem` binary built for these tests.
pub fn xylem() -> Command {
    Command::new(env!("CARGO_BIN_EXE_xylem"))
}

/// A path inside the repository.
pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs `cmd`, which must succeed; returns its stdout.
pub fn run_ok(cmd: &mut Command) -> String {
    run_ok_split(cmd).0
}

/// Runs `cmd`, which must succeed; returns its stdout and its stderr.
pub fn run_ok_split(cmd: &mut Command) -> (String, String) {
    let out = cmd.output().expect("run xylem");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "xylem failed: {stderr}");
    (String::from_utf8_lossy(&out.stdout).into_owned(), stderr)
}

/// Runs `cmd`, which must succeed; returns what it said (stdout, then stderr).
pub fn run_ok_said(cmd: &mut Command) -> String {
    let out = cmd.output().expect("run xylem");
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "xylem failed: {said}");
    said
}

/// Asserts that `text` (an error message, a page) contains every one of `parts`, naming the
/// first one missing.
pub fn assert_names(text: &str, parts: &[&str]) {
    for part in parts {
        assert!(text.contains(part), "does not name {part:?}:\n{text}");
    }
}

/// Runs `cmd`, which must fail; returns its stderr.
pub fn run_err(cmd: &mut Command) -> String {
    let out = cmd.output().expect("run xylem");
    assert!(!out.status.success(), "xylem should have failed");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A scratch folder holding only the face photos and knot markers of the sample in `from`
/// (a cube that comes without ring images).
pub fn photos_only(from: &Path, name: &str) -> Scratch {
    let dir = scratch(name);
    std::fs::create_dir_all(&dir).unwrap();
    for face in ["A", "B", "C", "D", "E", "F"] {
        for file in [format!("{face}_col.png"), format!("{face}_knot.png")] {
            if from.join(&file).is_file() {
                std::fs::copy(from.join(&file), dir.join(&file)).unwrap();
            }
        }
    }
    dir
}

/// `n` seeded normal values times `scale`.
pub fn random(n: usize, scale: f32, seed: u64) -> Vec<f32> {
    let mut rng = xylem::rng::Rng::new(seed);
    (0..n).map(|_| scale * rng.normal()).collect()
}

/// A Python interpreter that can `import module` (an independent reader such as `openvdb`,
/// `vtk` or `mitsuba`), tried in order: `XYLEM_PYTHON_<MODULE>` (upper case), Debian's
/// `/usr/bin/python3`, `python3` on the PATH, the venv `.ci/run` makes (`XYLEM_VENV`).
/// When none can, the test is skipped with a message, unless `XYLEM_EXTERNAL_READERS=required`
/// (set by `.ci/run`, which installs them), in which case it fails.
pub fn python_with(module: &str) -> Option<PathBuf> {
    let mut candidates: Vec<PathBuf> = Vec::new();
    if let Some(p) = std::env::var_os(format!("XYLEM_PYTHON_{}", module.to_ascii_uppercase())) {
        candidates.push(PathBuf::from(p));
    }
    if let Some(venv) = std::env::var_os("XYLEM_VENV") {
        candidates.push(PathBuf::from(venv).join("bin/python3"));
    }
    candidates.push(PathBuf::from("/usr/bin/python3"));
    candidates.push(PathBuf::from("python3"));
    for python in candidates {
        let ok = std::process::Command::new(&python)
            .args(["-c", &format!("import {module}")])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        if ok {
            return Some(python);
        }
    }
    if std::env::var("XYLEM_EXTERNAL_READERS").as_deref() == Ok("required") {
        panic!("no Python with `{module}` found, and XYLEM_EXTERNAL_READERS=required");
    }
    eprintln!("skipping: no Python with `{module}` (set XYLEM_EXTERNAL_READERS=required to fail)");
    None
}

/// Runs `python -c script args..`, panicking with its stderr when it fails; returns stdout.
pub fn run_python(python: &std::path::Path, script: &str, args: &[&str]) -> String {
    let out = std::process::Command::new(python)
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("start python");
    assert!(
        out.status.success(),
        "python failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Trains on `data` with the moment loss on the flex CPU device into the folder `out`
/// (prepared as an output folder), silently; `config_source` is what the model records as
/// its config's origin.
pub fn train_with_moments(
    out: &Path,
    cfg: &xylem::nca::TrainConfig,
    config_source: &str,
    data: &xylem::nca::train::TrainData,
    options: &xylem::nca::train::session::TrainOptions,
) -> xylem::Result<xylem::nca::train::session::TrainOutcome> {
    let kind = xylem::device::DeviceKind::Flex;
    let loss = xylem::nca::MomentLoss::new(&data.targets, &kind.device());
    let dir = xylem::io::OutputDir::prepare(out)?;
    xylem::nca::train::session::run_training(
        &dir,
        cfg,
        config_source,
        data,
        kind,
        &loss,
        options,
        &mut |_| {},
    )
}

/// The largest absolute value of a list (0 for an empty one).
pub fn max_abs(values: &[f32]) -> f32 {
    values.iter().map(|v| v.abs()).fold(0.0f32, f32::max)
}

/// The largest absolute difference between two equally long lists of values.
pub fn max_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len(), "compared lists differ in length");
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f32, f32::max)
}

/// A fitted base colour for tests: a flat two-node bar at 0.5 over G in [0, 20], photos of
/// mean colour `mean` on every face, no face offsets, no mean shift, no grain shading
/// (callers change what they test).
pub fn flat_base_colour(mean: [f32; 3]) -> xylem::field::BaseColour {
    xylem::field::BaseColour {
        g_range: [0.0, 20.0],
        bar: vec![[0.5; 3], [0.5; 3]],
        knot_bar: vec![],
        knot_blend: 1.0,
        face_offsets: [[0.0; 3]; 6],
        mean_shift: [0.0; 3],
        white_balance: xylem::field::WhiteBalance {
            face_means: [mean; 6],
            mean,
            grain: None,
        },
    }
}
