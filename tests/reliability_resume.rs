//! Reliability suite (issue 16), family "kill and resume": a run folder left by a process
//! killed at a bad moment, or re-run with other inputs. The probe saw a killed synthesis
//! taken as done (the faces, cuts and model.toml never written), a resumed training learn
//! other photos, and re-runs with other faces or configs keep the old model. Each row
//! copies one finished tiny run (32 px sample, 8^3 NCA, two iterations: a few seconds),
//! damages it as a kill at that moment would (a stage's outputs without its completion
//! marker, a checkpoint mid-rename, stale temporary files) or changes the inputs, runs
//! `xylem run` or `xylem train --resume` again and checks the stage is redone (not
//! reused), the training continues to the same result, or the re-run is refused naming
//! what changed.

mod common;
mod reliability_support;

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use reliability_support::{
    Expect, FAST_FIT, Outcome, TINY_NCA, Tally, copy_tree, error, judge_run, run, xylem,
};

struct Inputs {
    dir: reliability_support::Scratch,
    sample: PathBuf,
    nca: PathBuf,
    fit: PathBuf,
}

fn inputs(name: &str) -> Inputs {
    let dir = reliability_support::scratch(name);
    let (sample, nca) = reliability_support::tiny_sample_and_nca(&dir, 32);
    let fit = dir.join("fit.toml");
    std::fs::write(&fit, FAST_FIT).unwrap();
    Inputs {
        dir,
        sample,
        nca,
        fit,
    }
}

/// `xylem run` on the tiny inputs into `out`, with `extra` flags.
fn run_args(i: &Inputs, out: &Path, extra: &[&str]) -> Vec<OsString> {
    let mut args: Vec<OsString> = vec![
        "run".into(),
        "--sample".into(),
        i.sample.clone().into(),
        "--nca-config".into(),
        i.nca.clone().into(),
        "--fit-config".into(),
        i.fit.clone().into(),
        "--synth-steps".into(),
        "2".into(),
        "--image-size".into(),
        "16".into(),
        "--out".into(),
        out.into(),
    ];
    // Face F held out: the metrics stage compares one reference instead of six (seconds).
    if !extra.contains(&"--faces") {
        args.extend(["--faces".into(), "A,B,C,D,E".into()]);
    }
    args.extend(extra.iter().map(OsString::from));
    args
}

fn stage_log(outcome: &Outcome) -> Vec<String> {
    outcome
        .stderr
        .lines()
        .filter(|l| l.starts_with("== "))
        .map(str::to_string)
        .collect()
}

fn modified(path: &Path) -> std::time::SystemTime {
    std::fs::metadata(path).unwrap().modified().unwrap()
}

/// The synth stage's outputs (all written before its marker).
const SYNTH_OUTPUTS: [&str; 6] = [
    "synth/volume.npy",
    "synth/faces/A.png",
    "synth/cuts/cut1.png",
    "synth/cuts/cut2.png",
    "synth/unfolded.png",
    "synth/model.toml",
];

type Damage = Box<dyn Fn(&Path)>;

fn remove(paths: &'static [&'static str]) -> Damage {
    Box::new(move |run: &Path| {
        for p in paths {
            let path = run.join(p);
            if path.is_dir() {
                std::fs::remove_dir_all(&path).unwrap();
            } else {
                std::fs::remove_file(&path).unwrap();
            }
        }
    })
}

#[test]
fn killed_stages_are_redone_and_changed_inputs_refused() {
    let i = inputs("rel-resume-run");
    let base = i.dir.join("base");
    let first = run(xylem().args(run_args(&i, &base, &[])));
    assert!(first.ok(), "the tiny run failed:\n{}", first.stderr);
    for f in SYNTH_OUTPUTS.iter().chain(&[
        "fit/fit.toml",
        "fit/.done",
        "synth/.done",
        "train/model.bpk",
        "report/index.html",
    ]) {
        assert!(base.join(f).is_file(), "{f} missing after the tiny run");
    }
    let mut tally = Tally::default();

    // Re-running the finished folder reuses every stage and rewrites no model.
    let again = i.dir.join("again");
    copy_tree(&base, &again);
    let before = modified(&again.join("train/model.bpk"));
    let outcome = run(xylem().args(run_args(&i, &again, &[])));
    tally.add(judge_run("a finished run, re-run", &outcome, &Expect::Fine));
    let log = stage_log(&outcome);
    for stage in ["fit", "train", "synth"] {
        assert!(
            log.contains(&format!("== {stage} (done, skipped)")),
            "{log:?}"
        );
    }
    assert_eq!(modified(&again.join("train/model.bpk")), before);

    // Kills: outputs without their completion marker are redone, not reused. Several
    // kills share one folder (each re-run of `xylem run` takes seconds); each is a row.
    struct Kill {
        name: &'static str,
        damage: Damage,
        /// The stage line the re-run must print.
        redone: &'static str,
    }
    let kill = |name, damage, redone| Kill {
        name,
        damage,
        redone,
    };
    let scenarios: Vec<Vec<Kill>> = vec![
        vec![
            kill(
                "fit killed after fit.toml, before its marker",
                remove(&["fit/.done"]),
                "== fit",
            ),
            kill(
                "synth killed just after volume.npy (was taken as done)",
                remove(&[
                    "synth/.done",
                    "synth/faces",
                    "synth/cuts",
                    "synth/unfolded.png",
                    "synth/model.toml",
                ]),
                "== synth",
            ),
        ],
        vec![
            kill(
                "fit killed half way (no fit.toml)",
                remove(&["fit/.done", "fit/fit.toml", "fit/sheet.png"]),
                "== fit",
            ),
            kill(
                "train killed while saving a checkpoint (checkpoint.tmp left)",
                Box::new(|run: &Path| {
                    remove(&[
                        "train/.done",
                        "train/model.bpk",
                        "train/loss.png",
                        "train/loss.csv",
                    ])(run);
                    copy_tree(
                        &run.join("train/checkpoint"),
                        &run.join("train/checkpoint.tmp"),
                    );
                    std::fs::remove_file(run.join("train/checkpoint.tmp/pool.npy")).unwrap();
                }),
                "== train (resuming)",
            ),
            kill(
                "a killed synth's temporary file (.volume.npy.PID.tmp)",
                Box::new(|run: &Path| {
                    remove(&["synth/.done"])(run);
                    std::fs::write(run.join("synth/.volume.npy.999999999.tmp"), [0u8; 4096])
                        .unwrap();
                }),
                "== synth",
            ),
        ],
        vec![
            kill(
                "train killed inside the checkpoint rename (only checkpoint.old)",
                Box::new(|run: &Path| {
                    remove(&["train/.done", "train/model.bpk", "train/loss.png"])(run);
                    std::fs::rename(
                        run.join("train/checkpoint"),
                        run.join("train/checkpoint.old"),
                    )
                    .unwrap();
                }),
                "== train (resuming)",
            ),
            kill(
                "synth killed before its marker",
                remove(&["synth/.done"]),
                "== synth",
            ),
        ],
    ];
    let reference_log = std::fs::read(base.join("train/loss.csv")).unwrap();
    let reference_weights = weights(&base.join("train"));
    for (k, kills) in scenarios.iter().enumerate() {
        let folder = i.dir.join(format!("kill{k}"));
        copy_tree(&base, &folder);
        for kill in kills {
            (kill.damage)(&folder);
        }
        let outcome = run(xylem().args(run_args(&i, &folder, &[])));
        let log = stage_log(&outcome);
        for kill in kills {
            tally.add(judge_run(kill.name, &outcome, &Expect::Fine));
            assert!(
                log.iter().any(|l| l == kill.redone),
                "{}: {log:?}",
                kill.name
            );
        }
        for f in SYNTH_OUTPUTS.iter().chain(&[
            "fit/fit.toml",
            "fit/.done",
            "synth/.done",
            "train/loss.png",
        ]) {
            assert!(
                folder.join(f).is_file(),
                "scenario {k}: {f} missing after the re-run"
            );
        }
        let leftovers: Vec<_> = std::fs::read_dir(folder.join("synth"))
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "scenario {k}: {leftovers:?} kept");
        // A resumed training ends where the uninterrupted one did.
        assert!(
            std::fs::read(folder.join("train/loss.csv")).unwrap() == reference_log,
            "scenario {k}: the loss log differs from the uninterrupted run's"
        );
        assert!(
            weights(&folder.join("train")) == reference_weights,
            "scenario {k}: the weights differ from the uninterrupted run's"
        );
    }

    // Other inputs on a finished folder are refused, naming what changed; nothing is
    // rewritten.
    // The same folder with one pixel of one photo changed.
    let other_sample = i.dir.join("S2");
    copy_tree(&i.sample, &other_sample);
    let mut photo = xylem::io::load_rgb(&other_sample.join("A_col.png")).unwrap();
    photo.pixel_mut(3, 3)[0] = 1.0 - photo.get(3, 3, 0);
    xylem::io::save_png(&photo, &other_sample.join("A_col.png")).unwrap();
    let other_nca = i.dir.join("other.toml");
    std::fs::write(&other_nca, TINY_NCA.replace("seed = 2", "seed = 3")).unwrap();
    let changes: Vec<(&str, Vec<OsString>, Expect)> = vec![
        (
            "re-run with other faces (kept the six-face model)",
            run_args(&i, &base, &["--faces", "A,B,C,D"]),
            error(&[
                "run.toml",
                "faces: was A,B,C,D,E, now A,B,C,D",
                "another --out",
            ]),
        ),
        (
            "re-run with another NCA config (was ignored)",
            {
                let mut a = run_args(&i, &base, &[]);
                a[4] = other_nca.clone().into();
                a
            },
            error(&["run.toml", "nca_config"]),
        ),
        (
            "re-run on other photos (scored the old model)",
            {
                let mut a = run_args(&i, &base, &[]);
                a[2] = other_sample.clone().into();
                a
            },
            error(&["run.toml", "sample"]),
        ),
        (
            "re-run with other synthesis steps",
            {
                let mut a = run_args(&i, &base, &[]);
                a[8] = "3".into();
                a
            },
            error(&["run.toml", "synth_steps: was 2, now 3"]),
        ),
    ];
    let before = reliability_support_snapshot(&base);
    for (name, args, expect) in &changes {
        let outcome = run(xylem().args(args));
        tally.add(judge_run(name, &outcome, expect));
        assert!(stage_log(&outcome).is_empty(), "{name} started a stage");
    }
    assert_eq!(
        reliability_support_snapshot(&base),
        before,
        "a refused re-run wrote"
    );

    // A first call with a mistyped sample leaves no record that blocks the corrected one
    // (it recorded the wrong sample and refused the right one).
    let folder = i.dir.join("typo");
    let mut typo = run_args(&i, &folder, &[]);
    typo[2] = i.dir.join("nothere").into();
    tally.judge_call(
        "run with a mistyped --sample",
        xylem().args(&typo),
        &error(&["nothere", "sample folder not found"]),
    );
    tally.judge_call(
        "the corrected run into the same folder",
        xylem().args(run_args(&i, &folder, &[])),
        &Expect::Fine,
    );
    tally.print("kill and resume (xylem run)");
    std::fs::remove_dir_all(&i.dir).unwrap();
}

/// The trained weights of a model folder as numbers (the file also holds parameter ids,
/// which differ between two trainings started apart).
fn weights(model: &Path) -> Vec<f32> {
    let meta = xylem::nca::model_dir::ModelMeta::load(model).unwrap();
    let device = xylem::device::DeviceKind::Flex.device();
    let nca =
        xylem::nca::model_dir::load_weights(&meta.spec, &model.join("model.bpk"), &device).unwrap();
    let mut v = xylem::nca::tensors::to_vec(nca.w1.val()).unwrap();
    v.extend(xylem::nca::tensors::to_vec(nca.b1.val()).unwrap());
    v.extend(xylem::nca::tensors::to_vec(nca.w2.val()).unwrap());
    v
}

/// Files and sizes under `dir` (to see that a refused call wrote nothing).
fn reliability_support_snapshot(dir: &Path) -> Vec<(PathBuf, u64)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            out.extend(reliability_support_snapshot(&path));
        } else {
            let meta = std::fs::metadata(&path).unwrap();
            out.push((path, meta.len()));
        }
    }
    out.sort();
    out
}

/// `xylem train` killed after its first iteration (`--stop-after`, which stops without a
/// final checkpoint as a kill would) resumes to the same log and weights; `--resume` with
/// other photos or other options is refused.
#[test]
fn killed_training_resumes_exactly_or_refuses() {
    let i = inputs("rel-resume-train");
    let config = i.dir.join("every.toml");
    std::fs::write(
        &config,
        TINY_NCA.replace("iterations = 2", "iterations = 3") + "[checkpoint]\nevery = 1\n",
    )
    .unwrap();
    let field = reliability_support::repo("configs/fields/distorted.toml");
    let train = |sample: &Path, out: &Path, extra: &[&str]| {
        let mut args: Vec<OsString> = vec![
            "train".into(),
            "--sample".into(),
            sample.into(),
            "--out".into(),
            out.into(),
        ];
        args.extend(extra.iter().map(OsString::from));
        args
    };
    let fresh = |out: &Path, extra: &[&str]| {
        let mut args = train(&i.sample, out, extra);
        args.extend([
            "--config".into(),
            config.clone().into(),
            "--fit".into(),
            field.clone().into(),
        ]);
        args
    };
    let mut tally = Tally::default();
    let whole = i.dir.join("whole");
    tally.judge_call(
        "an uninterrupted training",
        xylem().args(fresh(&whole, &[])),
        &Expect::Fine,
    );

    let killed = i.dir.join("killed");
    tally.judge_call(
        "a training killed after one iteration",
        xylem().args(fresh(&killed, &["--stop-after", "1"])),
        &Expect::Fine,
    );
    assert!(
        !killed.join("model.bpk").exists(),
        "a killed training wrote its model"
    );
    tally.judge_call(
        "the same training started again without --resume",
        xylem().args(fresh(&killed, &[])),
        &error(&["already holds a training run", "--resume"]),
    );
    tally.judge_call(
        "--resume with --faces",
        xylem().args(train(&i.sample, &killed, &["--resume", "--faces", "A,B"])),
        &error(&[
            "--resume continues with the run's own",
            "drop --config, --fit and --faces",
        ]),
    );
    let other_sample = i.dir.join("S2");
    reliability_support::write_tiny_sample(&other_sample, 16);
    tally.judge_call(
        "--resume on other photos (trained on them)",
        xylem().args(train(&other_sample, &killed, &["--resume"])),
        &error(&["sample.toml", "sample: was"]),
    );
    tally.judge_call(
        "--resume after the kill",
        xylem().args(train(&i.sample, &killed, &["--resume"])),
        &Expect::Fine,
    );
    assert!(
        std::fs::read(killed.join("loss.csv")).unwrap()
            == std::fs::read(whole.join("loss.csv")).unwrap(),
        "the resumed training's loss log differs from the uninterrupted one's"
    );
    assert!(
        weights(&killed) == weights(&whole),
        "the resumed training's weights differ from the uninterrupted one's"
    );
    // Resuming a finished training changes nothing.
    tally.judge_call(
        "--resume of a finished training",
        xylem().args(train(&i.sample, &whole, &["--resume"])),
        &Expect::Fine,
    );
    assert!(weights(&killed) == weights(&whole));
    tally.print("kill and resume (xylem train)");
    std::fs::remove_dir_all(&i.dir).unwrap();
}

/// Training writes model.bpk, then model.toml (with the weights' hash and the iteration
/// count), loss.csv and loss.png, then the stage's marker; a kill between them (no marker)
/// must not be taken as a finished stage: the re-run resumes and writes the rest.
#[test]
fn training_killed_between_its_last_writes_is_finished() {
    let i = inputs("rel-resume-train-marker");
    let base = i.dir.join("R");
    assert!(run(xylem().args(run_args(&i, &base, &[]))).ok());
    // As a kill just after model.bpk leaves it: model.toml as written at the start.
    let meta = std::fs::read_to_string(base.join("train/model.toml")).unwrap();
    let start = reliability_support::set(
        &reliability_support::set(&meta, "weights_hash", None),
        "iterations",
        Some("0"),
    );
    std::fs::write(base.join("train/model.toml"), start).unwrap();
    for f in [
        "train/.done",
        "train/loss.png",
        "train/loss.csv",
        "synth/.done",
    ] {
        std::fs::remove_file(base.join(f)).unwrap();
    }
    let outcome = run(xylem().args(run_args(&i, &base, &[])));
    assert!(outcome.ok(), "{}", outcome.stderr);
    let log = stage_log(&outcome);
    assert!(
        !log.contains(&"== train (done, skipped)".to_string()),
        "{log:?}"
    );
    assert!(base.join("train/loss.png").is_file() && base.join("train/loss.csv").is_file());
    let meta = xylem::nca::model_dir::ModelMeta::load(&base.join("train")).unwrap();
    assert_eq!(meta.iterations, 2);
    assert!(meta.weights_hash.is_some());
    std::fs::remove_dir_all(&i.dir).unwrap();
}
