//! Reliability suite (issue 16), family "CLI": bad flag values typed at the binary: sizes of
//! 0, 1, non-square or absurd, unroll steps of 0 or 100000, unknown presets, species,
//! views, formats and devices, bad face lists, bad plane strings, conflicting flags. The
//! probe saw `xylem run --image-size 0` run fit, train and synthesis and then panic; every
//! row here must end at once with one message naming the flag (or file) and what it
//! accepts, exit code 1 or 2, and nothing written. The binary is what is probed, each call
//! under a 30 s limit and checked for panics.

mod common;
mod reliability_support;

use reliability_support::{Expect, Tally, error, judge_run, repo, run, xylem};

struct Row {
    args: Vec<String>,
    expect: Expect,
}

fn row(args: &str, expect: Expect) -> Row {
    Row {
        args: shell_words(args),
        expect,
    }
}

/// Splits on spaces; `'...'` keeps a word with spaces or semicolons together (`''` is an
/// empty word).
fn shell_words(s: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut current = String::new();
    let (mut quoted, mut in_word) = (false, false);
    for ch in s.chars() {
        match ch {
            '\'' => {
                quoted = !quoted;
                in_word = true;
            }
            ' ' if !quoted => {
                if in_word {
                    words.push(std::mem::take(&mut current));
                }
                in_word = false;
            }
            _ => {
                current.push(ch);
                in_word = true;
            }
        }
    }
    if in_word {
        words.push(current);
    }
    words
}

/// The rows; `$D` is replaced by the scratch folder, `$R` by the repository.
fn rows() -> Vec<Row> {
    vec![
        // Sizes.
        row(
            "field --preset minimal --size 0 --out $D/o",
            error(&["--size", "N in 2..=8192"]),
        ),
        row(
            "field --preset minimal --size 1 --out $D/o",
            error(&["--size", "2..=8192"]),
        ),
        row(
            "field --preset minimal --size 3x4 --out $D/o",
            error(&["--size", "square"]),
        ),
        row(
            "field --preset minimal --size abc --out $D/o",
            error(&["--size", "N or NxN"]),
        ),
        row(
            "field --preset minimal --size 99999999999999999999 --out $D/o",
            error(&["--size", "N or NxN"]),
        ),
        row(
            "sample --preset oak --size 0 --out $D/o",
            error(&["--size", "2..=8192"]),
        ),
        row(
            "procedural --preset oak --size 8 --volume-size 0 --out $D/o",
            error(&["--volume-size", "2..=1024"]),
        ),
        row(
            "procedural --preset oak --size 8 --volume-size 100000 --out $D/o",
            error(&["--volume-size", "2..=1024"]),
        ),
        row(
            "procedural --preset oak --size 8 --fibre-direction --out $D/o",
            error(&["--volume-size"]),
        ),
        row(
            "gallery --size 8 --out $D/o",
            error(&["--size", "16..=4096"]),
        ),
        row("demo --size 8 --out $D/o", error(&["--size", "16..=2048"])),
        row(
            "render --field $R/configs/fields/minimal.toml --size 0x5 --out $D/o.png",
            error(&["--size \"0x5\"", "1..=16384"]),
        ),
        row(
            "render --field $R/configs/fields/minimal.toml --size 16x0 --out $D/o.png",
            error(&["--size \"16x0\""]),
        ),
        row(
            "render --field $R/configs/fields/minimal.toml --size 100000 --out $D/o.png",
            error(&["--size \"100000\"", "1..=16384"]),
        ),
        row(
            "export --volume $D/v.npy --format mitsuba --image-size 0x0 --out $D/scene",
            error(&["--image-size \"0x0\""]),
        ),
        row(
            "synth --model $D/none --size 0 --out $D/o",
            error(&["--size", "4..=1024"]),
        ),
        row(
            "synth --model $D/none --size 5000 --out $D/o",
            error(&["--size", "4..=1024"]),
        ),
        row(
            "synth --model $D/none --size 3x3 --out $D/o",
            error(&["--size", "4..=1024"]),
        ),
        row(
            "run --sample $D/S --out $D/o --image-size 0",
            error(&["--image-size", "16..=2048"]),
        ),
        row(
            "run --sample $D/S --out $D/o --image-size 100000",
            error(&["--image-size", "16..=2048"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --size 8 --out $D/o",
            error(&["--size", "16..=4096"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --target-size 0 --steps 1 --out $D/o",
            error(&["target_size", "[8, 4096]"]),
        ),
        row(
            "mesh-bowl --segments 0 --out $D/b.obj",
            error(&["--segments 0", "3..=4096"]),
        ),
        row(
            "mesh-bowl --segments 100000000 --out $D/b.obj",
            error(&["--segments 100000000", "3..=4096"]),
        ),
        // Steps and numbers.
        row(
            "synth --model $D/none --steps 0 --out $D/o",
            error(&["--steps", "1..=2048"]),
        ),
        row(
            "synth --model $D/none --steps 100000 --out $D/o",
            error(&["--steps", "1..=2048"]),
        ),
        row(
            "run --sample $D/S --out $D/o --synth-steps 0",
            error(&["--synth-steps", "1..=2048"]),
        ),
        row(
            "run --sample $D/S --out $D/o --synth-steps 5000",
            error(&["--synth-steps", "1..=2048"]),
        ),
        row(
            "demo --synth-steps 0 --out $D/o",
            error(&["--synth-steps", "1..=2048"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --steps 0 --out $D/o",
            error(&["`steps` = 0", "[1, 1000000]"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --steps 100000000 --out $D/o",
            error(&["`steps` = 100000000"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --lr nan --steps 1 --out $D/o",
            error(&["learning_rate", "NaN"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --lr 1e9 --steps 1 --out $D/o",
            error(&["learning_rate", "<= 10"]),
        ),
        row(
            "texture2d --target $D/S/A_col.png --seed 99999999999999999999999 --out $D/o",
            error(&["--seed", "too large"]),
        ),
        // Unknown names.
        row(
            "field --preset bogus --size 8 --out $D/o",
            error(&["--preset \"bogus\"", "unknown field preset", "minimal"]),
        ),
        row(
            "sample --preset teak --size 16 --out $D/o",
            error(&["\"teak\"", "unknown species preset", "chestnut"]),
        ),
        row(
            "gallery --species oak,teak --size 16 --out $D/o",
            error(&["--species \"teak\"", "oak, chestnut"]),
        ),
        row(
            "run --sample $D/S --out $D/o --nca-preset huge",
            error(&["--nca-preset", "quick", "quality"]),
        ),
        row(
            "render --field $R/configs/fields/minimal.toml --size 8 --view spin --out $D/o.png",
            error(&["--view", "cube", "turntable"]),
        ),
        row(
            "export --volume $D/v.npy --out $D/e.xyz",
            error(&[
                "e.xyz",
                "cannot tell the format",
                ".npy, .vol, .nrrd or .vdb",
            ]),
        ),
        row(
            "export --volume $D/v.npy --format tiff --out $D/e.npy",
            error(&["format \"tiff\"", "npy, vol, nrrd, vdb or mitsuba"]),
        ),
        row(
            "export --volume $D/v.npy --values bogus --out $D/e.npy",
            error(&["--values", "colour", "data"]),
        ),
        row(
            "synth --model $D/none --device gpu --out $D/o",
            error(&["--device \"gpu\"", "flex", "ndarray"]),
        ),
        row(
            "synth --model $D/none --engine turbo --out $D/o",
            error(&["engine \"turbo\"", "fused", "burn"]),
        ),
        row("completions tcsh", error(&["tcsh", "bash", "zsh"])),
        row(
            "frobnicate",
            error(&["unrecognized subcommand 'frobnicate'"]),
        ),
        // Face lists.
        row(
            "run --sample $D/S --out $D/o --faces A,G",
            error(&["--faces \"A,G\"", "\"G\" is not a face", "A..F"]),
        ),
        row(
            "run --sample $D/S --out $D/o --faces ''",
            error(&["--faces \"\"", "no faces given"]),
        ),
        row(
            "run --sample $D/S --out $D/o --faces ,,,",
            error(&["no faces given"]),
        ),
        row(
            "fit --sample $D/S --out $D/o --faces Z",
            error(&["--faces \"Z\"", "not a face"]),
        ),
        row(
            "fit --sample $D/S --out $D/o --faces A;B",
            error(&["\"A;B\" is not a face"]),
        ),
        row(
            "train --sample $D/S --out $D/o --faces AB --config $D/tiny.toml --fit $R/configs/fields/distorted.toml",
            error(&["--faces \"AB\"", "not a face"]),
        ),
        // Plane strings.
        row(
            "slice --field $R/configs/fields/minimal.toml --plane cut3 --size 8 --out $D/o.png",
            error(&["--plane \"cut3\"", "cut1, cut2, a face A..F"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane g --size 8 --out $D/o.png",
            error(&["--plane \"g\"", "three ';'-separated vectors"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '1,2;3' --size 8 --out $D/o.png",
            error(&["three ';'-separated vectors"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '0,0,0;1,0,0;2,0,0' --size 8 --out $D/o.png",
            error(&["u and v are parallel or zero"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '0,0,0;1e-20,0,0;0,1e-20,0' --size 8 --out $D/o.png",
            error(&["parallel or zero"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane 'nan,0,0;1,0,0;0,1,0' --size 8 --out $D/o.png",
            error(&["\"nan,0,0\" is not three comma-separated finite numbers"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '0,0;1,0,0;0,1,0' --size 8 --out $D/o.png",
            error(&["\"0,0\" is not three"]),
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '' --size 8 --out $D/o.png",
            error(&["--plane"]),
        ),
        // Missing and conflicting inputs.
        row(
            "synth --model $D/none --out $D/o",
            error(&["none", "no model.bpk here", "xylem train"]),
        ),
        row(
            "train --sample $D/S --out $D/o --fit $R/configs/fields/distorted.toml",
            error(&["--config is required"]),
        ),
        row(
            "train --sample $D/S --out $D/o --config $D/tiny.toml",
            error(&["--fit is required"]),
        ),
        row(
            "train --sample $D/S --out $D/empty --resume",
            error(&["--resume", "holds no checkpoint"]),
        ),
        row(
            "field --preset minimal --config $D/x.toml --size 8 --out $D/o",
            error(&["--preset", "cannot be used with", "--config"]),
        ),
        row(
            "render --field $R/configs/fields/minimal.toml --volume $D/v.npy --size 8 --out $D/o.png",
            error(&["cannot be used with"]),
        ),
        row(
            "render --field $R/configs/fields/minimal.toml --mesh $D/nothere.obj --size 8 --out $D/o.png",
            error(&["nothere.obj", "not found", ".obj"]),
        ),
        row(
            "export --volume $D/v.npy --field $R/configs/fields/minimal.toml --out $D/e.nrrd",
            error(&["--field and --fibre", ".vdb"]),
        ),
        row(
            "fit --sample $D/S --out $D/o --config $D/nothere.toml",
            error(&["nothere.toml", "No such file"]),
        ),
        row(
            "compare $D/S/A_col.png $D/nothere.png",
            error(&["nothere.png", "file not found"]),
        ),
        row(
            "report --run $D/nothere",
            error(&["nothere", "run folder not found"]),
        ),
        row(
            "report --run $D/S",
            error(&["holds no run outputs", "xylem run"]),
        ),
        row(
            "field --json --preset minimal --size 8 --out $D/o",
            error(&["--json", "has no summary", "run, fit, train, compare"]),
        ),
        // Accepted spellings mean the same.
        row(
            "slice --field $R/configs/fields/minimal.toml --plane ' CUT1 ' --size 8x8 --out $D/ok1.png",
            Expect::Fine,
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane a --size 8 --out $D/ok2.png",
            Expect::Fine,
        ),
        row(
            "slice --field $R/configs/fields/minimal.toml --plane '-0.5,0.5,0.5;1,0,0;0,-1,0' --size 8 --out $D/ok3.png",
            Expect::Fine,
        ),
    ]
}

/// Files under `dir` (recursively) other than xylem's folder marker.
fn files_in(dir: &std::path::Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files = Vec::new();
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(files_in(&path));
        } else if entry.file_name() != ".xylem-output" {
            files.push(path.display().to_string());
        }
    }
    files
}

#[test]
fn bad_flag_values_are_refused_naming_the_flag() {
    let dir = reliability_support::scratch("rel-cli");
    reliability_support::tiny_sample_and_nca(&dir, 16);
    xylem::io::npy::write_npy(&dir.join("v.npy"), &[2, 2, 2, 3], &[0.5; 24]).unwrap();
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let d = dir.display().to_string();
    let r = repo("").display().to_string();
    let r = r.trim_end_matches('/');
    let mut tally = Tally::default();
    for row in rows() {
        let args: Vec<String> = row
            .args
            .iter()
            .map(|a| a.replace("$D", &d).replace("$R", r))
            .collect();
        let name = args.join(" ");
        let outcome = run(xylem().args(&args));
        tally.add(judge_run(&name, &outcome, &row.expect));
        if matches!(row.expect, Expect::Error(_)) {
            assert!(
                matches!(outcome.code, Some(1) | Some(2)),
                "{name}: exit code {:?}",
                outcome.code
            );
            assert!(
                outcome.seconds < 10.0,
                "{name}: refused only after {:.1} s",
                outcome.seconds
            );
            assert!(!dir.join("o.png").exists(), "{name} wrote output");
            // A command may have made its (empty, marked) output folder before refusing.
            let written = files_in(&dir.join("o"));
            assert!(written.is_empty(), "{name} wrote {written:?}");
            let _ = std::fs::remove_dir_all(dir.join("o"));
        }
    }
    // The accepted spellings: cut1 in any case and with spaces, 8x8 = 8, face a = A.
    let ok1 = xylem::io::load_rgb(&dir.join("ok1.png")).unwrap();
    assert_eq!((ok1.width, ok1.height), (8, 8));
    let face = xylem::io::load_rgb(&dir.join("ok2.png")).unwrap();
    let plane = xylem::io::load_rgb(&dir.join("ok3.png")).unwrap();
    assert_eq!(
        face, plane,
        "face A is the plane (-0.5, 0.5, 0.5; 1, 0, 0; 0, -1, 0)"
    );
    tally.print("CLI flags");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bugs of the commands themselves (in `src/cli/`, `src/frame/plane.rs`, the error printer)
/// that this suite found and that were then fixed; each test states the right behaviour.
mod cli_bugs_found_by_the_suite {
    use super::*;

    /// `xylem run --species teak` on a sample without `truth/` runs fit, training and
    /// synthesis before it looks the species up, and then names `--preset`.
    #[test]
    fn run_checks_species_before_the_stages() {
        let dir = reliability_support::scratch("rel-cli-species");
        let (sample, _) = reliability_support::tiny_sample_and_nca(&dir, 32);
        std::fs::write(dir.join("fit.toml"), reliability_support::FAST_FIT).unwrap();
        let outcome = run(xylem()
            .args([
                "run",
                "--species",
                "teak",
                "--synth-steps",
                "2",
                "--image-size",
                "16",
            ])
            .arg("--sample")
            .arg(&sample)
            .arg("--nca-config")
            .arg(dir.join("tiny.toml"))
            .arg("--fit-config")
            .arg(dir.join("fit.toml"))
            .arg("--out")
            .arg(dir.join("R")));
        judge_run(
            "run --species teak",
            &outcome,
            &error(&["--species", "teak", "oak"]),
        );
        assert!(
            !dir.join("R/fit").exists(),
            "the fit ran before the species was checked"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `xylem demo --species teak` says `--preset "teak"`.
    #[test]
    fn demo_names_the_species_flag() {
        let dir = reliability_support::scratch("rel-cli-demo");
        let outcome = run(xylem()
            .args(["demo", "--species", "teak", "--size", "16", "--out"])
            .arg(dir.join("d")));
        judge_run(
            "demo --species teak",
            &outcome,
            &error(&["--species", "teak"]),
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A plane with edges of 1e30 cube units passes the parallel check (the cross product
    /// overflows to inf) and slices to an all-black image with exit code 0.
    #[test]
    fn huge_plane_vectors_are_refused() {
        let dir = reliability_support::scratch("rel-cli-plane");
        let outcome = run(xylem()
            .args([
                "slice",
                "--plane",
                "0,0,0;1e30,0,0;0,1e30,0",
                "--size",
                "8",
                "--field",
            ])
            .arg(repo("configs/fields/minimal.toml"))
            .arg("--out")
            .arg(dir.join("p.png")));
        judge_run(
            "slice with 1e30 plane edges",
            &outcome,
            &error(&["--plane"]),
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `xylem compare one.png one.png` on 1x1 images: "style target 0: is 1x1 ..." names
    /// no file.
    #[test]
    fn compare_names_a_too_small_image() {
        let dir = reliability_support::scratch("rel-cli-compare");
        let one = dir.join("one.png");
        xylem::io::save_png(&xylem::Image2::filled(1, 1, 3, 0.5), &one).unwrap();
        let outcome = run(xylem().arg("compare").arg(&one).arg(&one));
        judge_run("compare 1x1 images", &outcome, &error(&["one.png", "1x1"]));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// An I/O error prints the OS message twice: "x.toml: No such file or directory (os
    /// error 2): No such file or directory (os error 2)".
    #[test]
    fn io_errors_say_it_once() {
        let dir = reliability_support::scratch("rel-cli-io");
        let outcome = run(xylem()
            .args(["field", "--size", "8", "--config"])
            .arg(dir.join("missing.toml"))
            .arg("--out")
            .arg(dir.join("f")));
        assert_eq!(
            outcome.stderr.matches("No such file").count(),
            1,
            "{}",
            outcome.stderr
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `xylem train --fit FIFO` blocks forever reading it.
    #[test]
    fn train_refuses_a_fifo_as_the_fit() {
        let dir = reliability_support::scratch("rel-cli-fifo");
        reliability_support::tiny_sample_and_nca(&dir, 16);
        let fifo = dir.join("fit.toml");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return;
        }
        let outcome = run(xylem()
            .arg("train")
            .arg("--sample")
            .arg(dir.join("S"))
            .arg("--config")
            .arg(dir.join("tiny.toml"))
            .arg("--fit")
            .arg(&fifo)
            .arg("--out")
            .arg(dir.join("T")));
        judge_run(
            "train --fit FIFO",
            &outcome,
            &error(&["fit.toml", "not a regular file"]),
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
