//! Helpers shared by the reliability suite (`tests/reliability_*.rs`, issue 16): running the
//! binary under a time limit, judging an outcome (a clear error naming what it should, or
//! success, never a panic or a hang), tiny inputs, and the per-family outcome tally.
#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use xylem::config::ConfigFile;

/// No single xylem call of the suite may take longer (the "hang").
pub const TIME_LIMIT: Duration = Duration::from_secs(30);

/// What a finished xylem process left.
#[derive(Debug)]
pub struct Outcome {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

impl Outcome {
    pub fn ok(&self) -> bool {
        self.code == Some(0)
    }
}

/// Runs `cmd` with stdin closed, killing it (and failing) after [`TIME_LIMIT`].
pub fn run(cmd: &mut Command) -> Outcome {
    let started = Instant::now();
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .env("RUST_BACKTRACE", "1")
        .spawn()
        .expect("start xylem");
    // Drain the pipes on threads so a chatty child never blocks on a full pipe.
    let mut out_pipe = child.stdout.take().expect("stdout");
    let mut err_pipe = child.stderr.take().expect("stderr");
    let out_thread = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out_pipe.read_to_string(&mut s);
        s
    });
    let err_thread = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err_pipe.read_to_string(&mut s);
        s
    });
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for xylem") {
            break status;
        }
        if started.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("hang: {cmd:?} ran for more than {TIME_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let outcome = Outcome {
        code: status.code(),
        stdout: out_thread.join().expect("stdout thread"),
        stderr: err_thread.join().expect("stderr thread"),
        seconds: started.elapsed().as_secs_f64(),
    };
    assert!(
        !outcome.stderr.contains("panicked at") && !outcome.stderr.contains("RUST_BACKTRACE"),
        "panic in {cmd:?}:\n{}",
        outcome.stderr
    );
    assert!(
        status.code().is_some(),
        "{cmd:?} was killed by a signal ({status:?}):\n{}",
        outcome.stderr
    );
    outcome
}

/// The expected end of one row of a table.
#[derive(Clone, Debug)]
pub enum Expect {
    /// Fails, and the message holds every one of these substrings.
    Error(Vec<String>),
    /// Succeeds (the row checks the result itself).
    Fine,
}

/// An error naming all of `parts`.
pub fn error(parts: &[&str]) -> Expect {
    Expect::Error(parts.iter().map(|s| s.to_string()).collect())
}

/// Checks a message against the expectation; returns the tally entry.
pub fn judge(row: &str, ok: bool, message: &str, expect: &Expect) -> Verdict {
    match expect {
        Expect::Error(parts) => {
            assert!(
                !ok,
                "{row}: expected an error, but it succeeded:\n{message}"
            );
            for p in parts {
                assert!(
                    message.contains(p.as_str()),
                    "{row}: the error does not name {p:?}:\n{message}"
                );
            }
            assert!(
                message.lines().count() <= 12,
                "{row}: the error is not short and clear:\n{message}"
            );
            Verdict::ClearError
        }
        Expect::Fine => {
            assert!(ok, "{row}: expected success, got:\n{message}");
            Verdict::RightResult
        }
    }
}

/// Judges a process outcome: the message is stderr on failure.
pub fn judge_run(row: &str, outcome: &Outcome, expect: &Expect) -> Verdict {
    let text = if outcome.ok() {
        &outcome.stdout
    } else {
        &outcome.stderr
    };
    // The command line names settings by their flags only: a library-style `name` would mean
    // a library error reached the user unrendered (once, a wrapped error's cause did).
    for name in xylem::error::SETTINGS {
        assert!(
            !outcome.stderr.contains(&format!("`{name}`")),
            "{row}: the message names the setting `{name}` instead of its flag:\n{}",
            outcome.stderr
        );
    }
    judge(row, outcome.ok(), text, expect)
}

/// Runs `cmd` and judges it as the row `row`.
pub fn run_judged(row: &str, cmd: &mut Command, expect: &Expect) -> (Outcome, Verdict) {
    let outcome = run(cmd);
    let verdict = judge_run(row, &outcome, expect);
    (outcome, verdict)
}

/// Judges a library result.
pub fn judge_result<T>(row: &str, result: &xylem::Result<T>, expect: &Expect) -> Verdict {
    match result {
        Ok(_) => judge(row, true, "", expect),
        Err(e) => judge(row, false, &e.to_string(), expect),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    ClearError,
    RightResult,
}

/// Counts a family's rows by outcome and prints them (`cargo test -- --nocapture` shows the
/// lines the closing note's table is made from).
#[derive(Default)]
pub struct Tally {
    pub clear_errors: usize,
    pub right_results: usize,
}

impl Tally {
    pub fn add(&mut self, v: Verdict) {
        match v {
            Verdict::ClearError => self.clear_errors += 1,
            Verdict::RightResult => self.right_results += 1,
        }
    }

    /// Runs `cmd`, judges it as the row `row` and counts it; returns the outcome.
    pub fn judge_call(&mut self, row: &str, cmd: &mut Command, expect: &Expect) -> Outcome {
        let (outcome, verdict) = run_judged(row, cmd, expect);
        self.add(verdict);
        outcome
    }

    pub fn total(&self) -> usize {
        self.clear_errors + self.right_results
    }

    pub fn print(&self, family: &str) {
        println!(
            "reliability {family}: {} cases, {} clear errors, {} right results",
            self.total(),
            self.clear_errors,
            self.right_results
        );
    }
}

#[allow(unused_imports)]
pub use crate::common::{Scratch, repo, xylem};

/// A fresh, existing scratch folder (`common::scratch`, created; removed when dropped).
pub fn scratch(name: &str) -> Scratch {
    crate::common::scratch_dir(name)
}

/// Six `n` x `n` face photos of brown wood with rings and pixel noise, and their exact ring
/// images (`X_arl.png`): a sample folder `Sample::load` and the fit accept.
pub fn write_tiny_sample(dir: &Path, n: usize) {
    use xylem::field::{GrowthField, ring_intensity};
    use xylem::frame::Face;
    use xylem::io::save_png;
    use xylem::presets::load_field_preset;
    use xylem::slice::slice_face;

    std::fs::create_dir_all(dir).expect("sample folder");
    let field = GrowthField::from_config(&load_field_preset("distorted").expect("preset"));
    for face in Face::ALL {
        let g = slice_face(&field, face, n);
        let mut photo = xylem::Image2::filled(n, n, 3, 0.0);
        let mut rings = xylem::Image2::filled(n, n, 1, 0.0);
        for r in 0..n {
            for c in 0..n {
                let ring = ring_intensity(g.get(r, c, 0));
                let h = xylem::rng::hash3(face.index() as u64, r as i32, c as i32, 0);
                let light = 0.75 - 0.35 * ring + 0.15 * (xylem::rng::unit(h) - 0.5);
                photo
                    .pixel_mut(r, c)
                    .copy_from_slice(&[light, 0.8 * light, 0.55 * light]);
                rings.pixel_mut(r, c)[0] = ring;
            }
        }
        save_png(&photo, &dir.join(format!("{face}_col.png"))).expect("photo");
        save_png(&rings, &dir.join(format!("{face}_arl.png"))).expect("ring image");
    }
}

/// A tiny NCA training config: an 8^3 grid, two iterations of 2-3 steps, the moment loss.
/// The inputs most CLI probes need under `dir`: a tiny sample `S` ([`write_tiny_sample`],
/// `n` px) and the tiny NCA config `tiny.toml` ([`TINY_NCA`]); returns their paths.
pub fn tiny_sample_and_nca(dir: &Path, n: usize) -> (PathBuf, PathBuf) {
    let (sample, nca) = (dir.join("S"), dir.join("tiny.toml"));
    write_tiny_sample(&sample, n);
    std::fs::write(&nca, TINY_NCA).unwrap();
    (sample, nca)
}

pub const TINY_NCA: &str = "seed = 2\n[model]\nhidden = 8\n[volume]\nsize = 8\ncrop = 8\n\
    [schedule]\niterations = 2\nsteps = [2, 3]\n[pool]\nsize = 0\n[loss]\nface = \"moments\"\n";

/// A fast fit config for 32 px samples (few iterations, small contours kept).
pub const FAST_FIT: &str = "[contours]\nborder = 1\nmin_pixels = 4\n[pith]\niterations = 20\n\
    refine = 1\n[distortion]\niterations = 20\ntrial_iterations = 0\n[colour]\n\
    iterations = 10\nbar_nodes = 16\n";

/// `base` (TOML text) with the value at `path` (dotted keys, `name[i]` for an element of an
/// array of tables) replaced by `value`, a TOML value written as text (`"[1, 2]"`,
/// `"\"x\""`, `"nan"`); `value` `None` removes the key. Comments are lost, values kept.
pub fn set(base: &str, path: &str, value: Option<&str>) -> String {
    let mut doc: toml::Table = toml::from_str(base).expect("base TOML parses");
    let parts: Vec<&str> = path.split('.').collect();
    let (last, parents) = parts.split_last().expect("a key");
    let mut table = &mut doc;
    for part in parents {
        let (name, index) = split_index(part);
        let entry = table
            .entry(name.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let entry = match index {
            Some(i) => &mut entry.as_array_mut().expect("an array of tables")[i],
            None => entry,
        };
        table = entry.as_table_mut().expect("a table on the path");
    }
    match value {
        Some(v) => {
            let parsed: toml::Table =
                toml::from_str(&format!("v = {v}")).expect("the new value parses");
            table.insert(last.to_string(), parsed["v"].clone());
        }
        None => {
            table.remove(*last);
        }
    }
    toml::to_string(&doc).expect("TOML serialises")
}

fn split_index(part: &str) -> (&str, Option<usize>) {
    match part.strip_suffix(']').and_then(|p| p.split_once('[')) {
        Some((name, i)) => (name, Some(i.parse().expect("an index"))),
        None => (part, None),
    }
}

/// The training data of the tiny config on a sample folder, with the `distorted` field
/// as the fit (ring-ramp base colour from the photos).
pub fn tiny_data(sample_dir: &Path, cfg: &xylem::nca::TrainConfig) -> xylem::nca::train::TrainData {
    use xylem::frame::Face;
    use xylem::sample::{Needs, Sample};
    let needs = Needs {
        photos: true,
        arl: false,
    };
    let sample = Sample::load(sample_dir, &Face::ALL, needs).expect("tiny sample");
    let fit = xylem::nca::fit_source::load_fit(
        &repo("configs/fields/distorted.toml"),
        xylem::nca::train::targets::photo_mean(&sample),
    )
    .expect("distorted field as the fit");
    xylem::nca::train::TrainData::prepare(&sample, fit, cfg)
}

/// Trains the tiny config (8^3 grid, two iterations, the moment loss) on a fresh 16 px
/// sample `dir/sample` into `dir/model` (with its checkpoint); about a second.
pub fn tiny_model(dir: &Path) -> (PathBuf, xylem::nca::TrainConfig) {
    use xylem::nca::train::session::TrainOptions;
    let sample_dir = dir.join("sample");
    write_tiny_sample(&sample_dir, 16);
    let cfg = xylem::nca::TrainConfig::parse(TINY_NCA, Path::new("<tiny>")).expect("tiny config");
    let data = tiny_data(&sample_dir, &cfg);
    let model = dir.join("model");
    crate::common::train_with_moments(&model, &cfg, "tiny", &data, &TrainOptions::default())
        .expect("tiny training");
    (sample_dir, cfg)
}

/// Copies the regular files of `from` into `to` (created).
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create the copy");
    for entry in std::fs::read_dir(from).expect("read the folder") {
        let path = entry.expect("folder entry").path();
        if path.is_file() {
            std::fs::copy(&path, to.join(path.file_name().expect("a name"))).expect("copy");
        }
    }
}

/// Copies `from` into `to` with all its subfolders.
pub fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create the copy");
    for entry in std::fs::read_dir(from).expect("read the folder") {
        let path = entry.expect("folder entry").path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).expect("copy");
        }
    }
}

/// CRC-32 (IEEE) of PNG chunks, so crafted PNG edits keep valid checksums and reach the decoder.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}
