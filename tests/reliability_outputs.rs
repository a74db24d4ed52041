//! Reliability suite (issue 16), family "output paths": where the probe lost user files
//! (`xylem report --out notes.md` replaced a user's notes with HTML; `--out
//! RUN/metrics.csv` destroyed a run's metrics). Every command that writes is pointed at an
//! existing file without `--force`, at a file where a folder is expected, and at a folder
//! of the user's that xylem did not write; the expected outcome is a clear error naming
//! the path and what to do, with the user's file byte for byte unchanged and nothing added
//! beside it. The rows with `--force`, an empty folder or xylem's own folder check the
//! right result. The binary is what is probed.

mod common;
mod reliability_support;

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use reliability_support::{Expect, Tally, error, repo, xylem};
use xylem::config::ConfigFile;

const PRECIOUS: &[u8] = b"my notes, not to be lost\n";

/// Every file under `dir` with its bytes (sorted), to compare before and after a call.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                out.extend(snapshot(&path));
            } else {
                out.push((path.clone(), std::fs::read(&path).unwrap_or_default()));
            }
        }
    }
    out.sort();
    out
}

fn os(parts: &[&dyn AsRef<std::ffi::OsStr>]) -> Vec<OsString> {
    parts.iter().map(|p| p.as_ref().to_os_string()).collect()
}

struct Setup {
    dir: reliability_support::Scratch,
    field: PathBuf,
    sample: PathBuf,
    nca: PathBuf,
    volume: PathBuf,
    run: PathBuf,
    model: PathBuf,
    png: PathBuf,
}

fn setup(name: &str) -> Setup {
    let dir = reliability_support::scratch(name);
    let (sample, nca) = reliability_support::tiny_sample_and_nca(&dir.join("inputs"), 16);
    let volume = dir.join("inputs/v.npy");
    xylem::io::npy::write_npy(&volume, &[4, 4, 4, 3], &[0.5; 192]).unwrap();
    // A run folder as `xylem report` reads it: a sheet and a metrics table.
    let run_dir = dir.join("inputs/RUN");
    std::fs::create_dir_all(&run_dir).unwrap();
    xylem::io::save_png(
        &xylem::Image2::filled(8, 8, 3, 0.5),
        &run_dir.join("sheet.png"),
    )
    .unwrap();
    std::fs::write(
        run_dir.join("metrics.csv"),
        "method,image,ring_ncc\nnca,A,0.5\n",
    )
    .unwrap();
    let (_, _) = reliability_support::tiny_model(&dir.join("inputs/m"));
    Setup {
        field: repo("configs/fields/minimal.toml"),
        sample,
        nca,
        volume,
        run: run_dir,
        model: dir.join("inputs/m/model"),
        png: dir.join("inputs/S/A_col.png"),
        dir,
    }
}

/// The commands that write one file, with `out` as that file.
fn single_file_commands(s: &Setup, out: &Path) -> Vec<(&'static str, Vec<OsString>)> {
    vec![
        (
            "slice",
            os(&[
                &"slice", &"--plane", &"cut1", &"--size", &"8", &"--field", &s.field, &"--out",
                &out,
            ]),
        ),
        (
            "render",
            os(&[
                &"render", &"--size", &"8", &"--field", &s.field, &"--out", &out,
            ]),
        ),
        (
            "export .npy",
            os(&[
                &"export",
                &"--volume",
                &s.volume,
                &"--format",
                &"npy",
                &"--out",
                &out,
            ]),
        ),
        (
            "export .vol",
            os(&[
                &"export",
                &"--volume",
                &s.volume,
                &"--format",
                &"vol",
                &"--out",
                &out,
            ]),
        ),
        (
            "export .nrrd",
            os(&[
                &"export",
                &"--volume",
                &s.volume,
                &"--format",
                &"nrrd",
                &"--out",
                &out,
            ]),
        ),
        (
            "export .vdb",
            os(&[
                &"export",
                &"--volume",
                &s.volume,
                &"--format",
                &"vdb",
                &"--out",
                &out,
            ]),
        ),
        (
            "compare --sheet",
            os(&[&"compare", &s.png, &s.png, &"--sheet", &out]),
        ),
        ("mesh-bowl", os(&[&"mesh-bowl", &"--out", &out])),
    ]
}

/// The commands that write a folder, with `out` as that folder.
fn folder_commands(s: &Setup, out: &Path) -> Vec<(&'static str, Vec<OsString>)> {
    vec![
        (
            "field",
            os(&[
                &"field",
                &"--preset",
                &"minimal",
                &"--size",
                &"8",
                &"--out",
                &out,
            ]),
        ),
        (
            "sample",
            os(&[
                &"sample",
                &"--preset",
                &"oak",
                &"--size",
                &"16",
                &"--out",
                &out,
            ]),
        ),
        (
            "procedural",
            os(&[
                &"procedural",
                &"--preset",
                &"oak",
                &"--size",
                &"8",
                &"--out",
                &out,
            ]),
        ),
        ("fit", os(&[&"fit", &"--sample", &s.sample, &"--out", &out])),
        (
            "train",
            os(&[
                &"train",
                &"--sample",
                &s.sample,
                &"--config",
                &s.nca,
                &"--fit",
                &s.field,
                &"--out",
                &out,
            ]),
        ),
        (
            "synth",
            os(&[
                &"synth", &"--model", &s.model, &"--steps", &"2", &"--size", &"8", &"--out", &out,
            ]),
        ),
        (
            "run",
            os(&[
                &"run",
                &"--sample",
                &s.sample,
                &"--nca-config",
                &s.nca,
                &"--out",
                &out,
            ]),
        ),
        (
            "gallery",
            os(&[
                &"gallery",
                &"--species",
                &"oak",
                &"--size",
                &"16",
                &"--out",
                &out,
            ]),
        ),
        (
            "texture2d",
            os(&[
                &"texture2d",
                &"--target",
                &s.png,
                &"--steps",
                &"1",
                &"--size",
                &"16",
                &"--out",
                &out,
            ]),
        ),
        (
            "export --format mitsuba",
            os(&[
                &"export",
                &"--volume",
                &s.volume,
                &"--format",
                &"mitsuba",
                &"--out",
                &out,
            ]),
        ),
        ("demo", os(&[&"demo", &"--size", &"16", &"--out", &out])),
    ]
}

/// The arguments of the command called `name` in `commands`.
fn command_named(commands: Vec<(&'static str, Vec<OsString>)>, name: &str) -> Vec<OsString> {
    commands.into_iter().find(|(n, _)| *n == name).unwrap().1
}

#[test]
fn user_files_are_never_replaced_or_written_into() {
    let s = setup("rel-outputs");
    let user = s.dir.join("user");
    let mut tally = Tally::default();

    // 1. An existing file without --force.
    let existing = |name: &str| {
        std::fs::create_dir_all(&user).unwrap();
        let path = user.join(name);
        std::fs::write(&path, PRECIOUS).unwrap();
        path
    };
    for (name, _) in single_file_commands(&s, Path::new("x")) {
        let file_name = match name {
            "export .npy" => "mine.npy",
            "export .vol" => "mine.vol",
            "export .nrrd" => "mine.nrrd",
            "export .vdb" => "mine.vdb",
            "mesh-bowl" => "mine.obj",
            _ => "mine.png",
        };
        let target = existing(file_name);
        let before = snapshot(&user);
        let args = command_named(single_file_commands(&s, &target), name);
        tally.judge_call(
            &format!("{name} onto an existing file"),
            xylem().args(&args),
            &error(&[file_name, "file exists", "--force"]),
        );
        assert_eq!(snapshot(&user), before, "{name} touched the user's folder");
        // With --force the file is replaced by a real output.
        tally.judge_call(
            &format!("{name} --force"),
            xylem().args(&args).arg("--force"),
            &Expect::Fine,
        );
        assert_ne!(std::fs::read(&target).unwrap(), PRECIOUS, "{name} --force");
        std::fs::remove_dir_all(&user).unwrap();
    }

    // 2. report --out: only a new (or forced) HTML file.
    let notes = existing("notes.md");
    let metrics_before = std::fs::read(s.run.join("metrics.csv")).unwrap();
    for (label, out, expect) in [
        (
            "report --out notes.md (replaced it with HTML)",
            notes.clone(),
            error(&["--out", "notes.md", "expected an .html or .htm file"]),
        ),
        (
            "report --out RUN/metrics.csv (destroyed the metrics)",
            s.run.join("metrics.csv"),
            error(&["metrics.csv", "expected an .html or .htm file"]),
        ),
        (
            "report --out onto an existing .html",
            existing("page.html"),
            error(&["page.html", "file exists", "--force"]),
        ),
    ] {
        let before = snapshot(&user);
        tally.judge_call(
            label,
            xylem()
                .arg("report")
                .arg("--run")
                .arg(&s.run)
                .arg("--out")
                .arg(&out),
            &expect,
        );
        assert_eq!(snapshot(&user), before, "{label}");
    }
    assert_eq!(
        std::fs::read(s.run.join("metrics.csv")).unwrap(),
        metrics_before
    );
    assert_eq!(std::fs::read(&notes).unwrap(), PRECIOUS);
    tally.judge_call(
        "report --out page.html --force",
        xylem()
            .arg("report")
            .arg("--run")
            .arg(&s.run)
            .arg("--out")
            .arg(user.join("page.html"))
            .arg("--force"),
        &Expect::Fine,
    );
    let html = std::fs::read_to_string(user.join("page.html")).unwrap();
    assert!(
        html.contains("<html") || html.contains("<!DOCTYPE"),
        "{html}"
    );
    std::fs::remove_dir_all(&user).unwrap();

    // 3. A file where a folder is expected, and 4. a folder of the user's.
    for (name, _) in folder_commands(&s, Path::new("x")) {
        let file = existing("plain-file");
        let before = snapshot(&user);
        let args = command_named(folder_commands(&s, &file), name);
        tally.judge_call(
            &format!("{name} --out onto a file"),
            xylem().args(&args),
            &error(&["plain-file", "must be a folder", "existing file"]),
        );
        assert_eq!(snapshot(&user), before, "{name}");
        std::fs::remove_file(&file).unwrap();

        let folder = user.join("photos");
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("notes.txt"), PRECIOUS).unwrap();
        let before = snapshot(&user);
        let args = command_named(folder_commands(&s, &folder), name);
        tally.judge_call(
            &format!("{name} --out into the user's folder"),
            xylem().args(&args),
            &error(&["photos", "not empty", "not written by xylem", "new --out"]),
        );
        assert_eq!(
            snapshot(&user),
            before,
            "{name} wrote into the user's folder"
        );
        std::fs::remove_dir_all(&user).unwrap();
    }

    // 5. Under a file: the folder cannot be made.
    let file = existing("plain-file");
    tally.judge_call(
        "field --out under a file",
        xylem()
            .args(["field", "--preset", "minimal", "--size", "8", "--out"])
            .arg(file.join("sub")),
        &error(&["plain-file/sub"]),
    );
    assert_eq!(std::fs::read(&file).unwrap(), PRECIOUS);
    std::fs::remove_dir_all(&user).unwrap();
    tally.print("output paths");
    std::fs::remove_dir_all(&s.dir).unwrap();
}

/// Folders xylem may write into: new, empty, or its own; re-runs replace what they wrote
/// and drop what a previous call wrote but this one did not.
#[test]
fn xylem_folders_are_reused_cleanly() {
    let dir = reliability_support::scratch("rel-outputs-own");
    let mut tally = Tally::default();
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    tally.judge_call(
        "field into an empty folder",
        xylem()
            .args(["field", "--preset", "minimal", "--size", "8", "--out"])
            .arg(&empty),
        &Expect::Fine,
    );
    assert!(empty.join("faces/A.png").is_file() && empty.join(".xylem-output").is_file());
    tally.judge_call(
        "field again into its own folder",
        xylem()
            .args(["field", "--preset", "knots", "--size", "8", "--out"])
            .arg(&empty),
        &Expect::Fine,
    );
    let copy = xylem::field::FieldConfig::load(&empty.join("config.toml")).unwrap();
    assert!(!copy.knots.is_empty(), "the config copy is the new one");

    // A procedural re-run without --volume-size drops the earlier call's volume (it kept
    // the previous species' volume.npy beside the new images).
    let wood = dir.join("wood");
    tally.judge_call(
        "procedural with a volume",
        xylem()
            .args([
                "procedural",
                "--preset",
                "oak",
                "--size",
                "8",
                "--volume-size",
                "4",
                "--out",
            ])
            .arg(&wood),
        &Expect::Fine,
    );
    assert!(wood.join("volume.npy").is_file());
    tally.judge_call(
        "procedural again without",
        xylem()
            .args(["procedural", "--preset", "maple", "--size", "8", "--out"])
            .arg(&wood),
        &Expect::Fine,
    );
    assert!(
        !wood.join("volume.npy").exists(),
        "the oak volume was kept beside maple"
    );

    // Temporary files of a dead process are removed; a live one's are kept.
    let dead = wood.join(".volume.npy.999999999.tmp");
    let live = wood.join(format!(".volume.npy.{}.tmp", std::process::id()));
    std::fs::write(&dead, b"half").unwrap();
    std::fs::write(&live, b"half").unwrap();
    tally.judge_call(
        "procedural with stale temporary files",
        xylem()
            .args(["procedural", "--preset", "maple", "--size", "8", "--out"])
            .arg(&wood),
        &Expect::Fine,
    );
    assert!(!dead.exists(), "a dead process's temporary file was kept");
    assert!(
        live.exists(),
        "a running process's temporary file was removed"
    );
    tally.print("output paths (xylem's folders)");
    std::fs::remove_dir_all(&dir).unwrap();
}
