//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

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

/// A fresh scratch folder for one test (removed first if a previous run left it).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("xylem-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
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
