//! Reliability suite (issue 16), family "CLI": bad flag values typed at the binary: sizes of
//! 0, 1, non-square or absurd, unroll steps of 0 or 100000, unknown presets, species,
//! views, formats and devices, bad face lists, bad plane strings, conflicting flags. The
//! probe saw `xylem run --image-size 0` run fit, train and synthesis and then panic; every
//! row here must end at once with one message naming the flag (or file) and what it
//! accepts, exit code 1 or 2, and nothing written. The binary is what is probed, each call
//! under a 30 s limit and checked for panics.

mod common;
mod reliability_support;

use reliability_support::{Expect, Tally, error, repo, run, run_judged, xylem};

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

/// The rows of one command: `command` followed by each case's own words.
fn rows_of(command: &str, cases: Vec<(&str, Expect)>) -> Vec<Row> {
    cases
        .into_iter()
        .map(|(words, expect)| row(&format!("{command} {words}"), expect))
        .collect()
}

/// The rows, by command; `$D` is replaced by the scratch folder, `$R` by the repository.
fn rows() -> Vec<Row> {
    [
        rows_of(
            "field --out $D/o",
            vec![
                // Sizes.
                ("--preset minimal --size 0", error(&["--size", "N in 2..=8192"])),
                ("--preset minimal --size 1", error(&["--size", "2..=8192"])),
                ("--preset minimal --size 3x4", error(&["--size", "square"])),
                ("--preset minimal --size abc", error(&["--size", "N or NxN"])),
                (
                    "--preset minimal --size 99999999999999999999",
                    error(&["--size", "N or NxN"]),
                ),
                // Unknown names, conflicting flags.
                (
                    "--preset bogus --size 8",
                    error(&["--preset \"bogus\"", "unknown field preset", "minimal"]),
                ),
                (
                    "--preset minimal --config $D/x.toml --size 8",
                    error(&["--preset", "cannot be used with", "--config"]),
                ),
                (
                    "--json --preset minimal --size 8",
                    error(&["--json", "has no summary", "run, fit, train, compare"]),
                ),
            ],
        ),
        rows_of(
            "sample --out $D/o",
            vec![
                ("--preset oak --size 0", error(&["--size", "2..=8192"])),
                (
                    "--preset teak --size 16",
                    error(&["\"teak\"", "unknown species preset", "chestnut"]),
                ),
            ],
        ),
        rows_of(
            "procedural --preset oak --size 8 --out $D/o",
            vec![
                ("--volume-size 0", error(&["--volume-size", "2..=1024"])),
                ("--volume-size 100000", error(&["--volume-size", "2..=1024"])),
                ("--fibre-direction", error(&["--volume-size"])),
            ],
        ),
        rows_of(
            "gallery --out $D/o",
            vec![
                ("--size 8", error(&["--size", "16..=4096"])),
                (
                    "--species oak,teak --size 16",
                    error(&["--species \"teak\"", "oak, chestnut"]),
                ),
            ],
        ),
        rows_of(
            "demo --out $D/o",
            vec![
                ("--size 8", error(&["--size", "16..=2048"])),
                ("--synth-steps 0", error(&["--synth-steps", "1..=2048"])),
            ],
        ),
        rows_of(
            "render --field $R/configs/fields/minimal.toml --out $D/o.png",
            vec![
                ("--size 0x5", error(&["--size \"0x5\"", "1..=16384"])),
                ("--size 16x0", error(&["--size \"16x0\""])),
                ("--size 100000", error(&["--size \"100000\"", "1..=16384"])),
                ("--size 8 --view spin", error(&["--view", "cube", "turntable"])),
                ("--volume $D/v.npy --size 8", error(&["cannot be used with"])),
                (
                    "--mesh $D/nothere.obj --size 8",
                    error(&["nothere.obj", "not found", ".obj"]),
                ),
            ],
        ),
        rows_of(
            "export --volume $D/v.npy",
            vec![
                (
                    "--format mitsuba --image-size 0x0 --out $D/scene",
                    error(&["--image-size \"0x0\""]),
                ),
                (
                    "--out $D/e.xyz",
                    error(&["e.xyz", "cannot tell the format", ".npy, .vol, .nrrd or .vdb"]),
                ),
                (
                    "--format tiff --out $D/e.npy",
                    error(&["format \"tiff\"", "npy, vol, nrrd, vdb or mitsuba"]),
                ),
                (
                    "--values bogus --out $D/e.npy",
                    error(&["--values", "colour", "data"]),
                ),
                (
                    "--field $R/configs/fields/minimal.toml --out $D/e.nrrd",
                    error(&["--field and --fibre", ".vdb"]),
                ),
            ],
        ),
        rows_of(
            "synth --model $D/none --out $D/o",
            vec![
                ("--size 0", error(&["--size", "4..=1024"])),
                ("--size 5000", error(&["--size", "4..=1024"])),
                ("--size 3x3", error(&["--size", "4..=1024"])),
                ("--steps 0", error(&["--steps", "1..=2048"])),
                ("--steps 100000", error(&["--steps", "1..=2048"])),
                ("--device gpu", error(&["--device \"gpu\"", "flex", "ndarray"])),
                ("--engine turbo", error(&["engine \"turbo\"", "fused", "burn"])),
                // No model in the folder.
                ("", error(&["none", "no model.bpk here", "xylem train"])),
            ],
        ),
        rows_of(
            "run --sample $D/S --out $D/o",
            vec![
                ("--image-size 0", error(&["--image-size", "16..=2048"])),
                ("--image-size 100000", error(&["--image-size", "16..=2048"])),
                ("--synth-steps 0", error(&["--synth-steps", "1..=2048"])),
                ("--synth-steps 5000", error(&["--synth-steps", "1..=2048"])),
                ("--nca-preset huge", error(&["--nca-preset", "quick", "quality"])),
                // Face lists.
                (
                    "--faces A,G",
                    error(&["--faces \"A,G\"", "\"G\" is not a face", "A..F"]),
                ),
                ("--faces ''", error(&["--faces \"\"", "no faces given"])),
                ("--faces ,,,", error(&["no faces given"])),
            ],
        ),
        rows_of(
            "fit --sample $D/S --out $D/o",
            vec![
                ("--faces Z", error(&["--faces \"Z\"", "not a face"])),
                ("--faces A;B", error(&["\"A;B\" is not a face"])),
                ("--config $D/nothere.toml", error(&["nothere.toml", "No such file"])),
            ],
        ),
        rows_of(
            "train --sample $D/S",
            vec![
                (
                    "--out $D/o --faces AB --config $D/tiny.toml --fit $R/configs/fields/distorted.toml",
                    error(&["--faces \"AB\"", "not a face"]),
                ),
                (
                    "--out $D/o --fit $R/configs/fields/distorted.toml",
                    error(&["--config is required"]),
                ),
                ("--out $D/o --config $D/tiny.toml", error(&["--fit is required"])),
                ("--out $D/empty --resume", error(&["--resume", "holds no checkpoint"])),
            ],
        ),
        rows_of(
            "texture2d --target $D/S/A_col.png --out $D/o",
            vec![
                ("--size 8", error(&["--size", "16..=4096"])),
                ("--target-size 0 --steps 1", error(&["target_size", "[8, 4096]"])),
                ("--steps 0", error(&["`steps` = 0", "[1, 1000000]"])),
                ("--steps 100000000", error(&["`steps` = 100000000"])),
                ("--lr nan --steps 1", error(&["learning_rate", "NaN"])),
                ("--lr 1e9 --steps 1", error(&["learning_rate", "<= 10"])),
                (
                    "--seed 99999999999999999999999",
                    error(&["--seed", "too large"]),
                ),
            ],
        ),
        rows_of(
            "mesh-bowl --out $D/b.obj",
            vec![
                ("--segments 0", error(&["--segments 0", "3..=4096"])),
                ("--segments 100000000", error(&["--segments 100000000", "3..=4096"])),
            ],
        ),
        // Plane strings.
        rows_of(
            "slice --field $R/configs/fields/minimal.toml --size 8 --out $D/o.png --plane",
            vec![
                ("cut3", error(&["--plane \"cut3\"", "cut1, cut2, a face A..F"])),
                ("g", error(&["--plane \"g\"", "three ';'-separated vectors"])),
                ("'1,2;3'", error(&["three ';'-separated vectors"])),
                ("'0,0,0;1,0,0;2,0,0'", error(&["u and v are parallel or zero"])),
                ("'0,0,0;1e-20,0,0;0,1e-20,0'", error(&["parallel or zero"])),
                (
                    "'nan,0,0;1,0,0;0,1,0'",
                    error(&["\"nan,0,0\" is not three comma-separated finite numbers"]),
                ),
                ("'0,0;1,0,0;0,1,0'", error(&["\"0,0\" is not three"])),
                ("''", error(&["--plane"])),
            ],
        ),
        // Accepted spellings mean the same.
        rows_of(
            "slice --field $R/configs/fields/minimal.toml",
            vec![
                ("--plane ' CUT1 ' --size 8x8 --out $D/ok1.png", Expect::Fine),
                ("--plane a --size 8 --out $D/ok2.png", Expect::Fine),
                (
                    "--plane '-0.5,0.5,0.5;1,0,0;0,-1,0' --size 8 --out $D/ok3.png",
                    Expect::Fine,
                ),
            ],
        ),
        // Other commands: unknown names, missing inputs.
        rows_of(
            "report --run",
            vec![
                ("$D/nothere", error(&["nothere", "run folder not found"])),
                ("$D/S", error(&["holds no run outputs", "xylem run"])),
            ],
        ),
        vec![
            row("completions tcsh", error(&["tcsh", "bash", "zsh"])),
            row(
                "frobnicate",
                error(&["unrecognized subcommand 'frobnicate'"]),
            ),
            row(
                "compare $D/S/A_col.png $D/nothere.png",
                error(&["nothere.png", "file not found"]),
            ),
        ],
    ]
    .into_iter()
    .flatten()
    .collect()
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
        let outcome = tally.judge_call(&name, xylem().args(&args), &row.expect);
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
        run_judged(
            "run --species teak",
            xylem()
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
                .arg(dir.join("R")),
            &error(&["--species", "teak", "oak"]),
        );
        assert!(
            !dir.join("R/fit").exists(),
            "the fit ran before the species was checked"
        );
    }

    /// `xylem demo --species teak` says `--preset "teak"`.
    #[test]
    fn demo_names_the_species_flag() {
        let dir = reliability_support::scratch("rel-cli-demo");
        run_judged(
            "demo --species teak",
            xylem()
                .args(["demo", "--species", "teak", "--size", "16", "--out"])
                .arg(dir.join("d")),
            &error(&["--species", "teak"]),
        );
    }

    /// A plane with edges of 1e30 cube units passes the parallel check (the cross product
    /// overflows to inf) and slices to an all-black image with exit code 0.
    #[test]
    fn huge_plane_vectors_are_refused() {
        let dir = reliability_support::scratch("rel-cli-plane");
        run_judged(
            "slice with 1e30 plane edges",
            xylem()
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
                .arg(dir.join("p.png")),
            &error(&["--plane"]),
        );
    }

    /// `xylem compare one.png one.png` on 1x1 images: "style target 0: is 1x1 ..." names
    /// no file.
    #[test]
    fn compare_names_a_too_small_image() {
        let dir = reliability_support::scratch("rel-cli-compare");
        let one = dir.join("one.png");
        xylem::io::save_png(&xylem::Image2::filled(1, 1, 3, 0.5), &one).unwrap();
        run_judged(
            "compare 1x1 images",
            xylem().arg("compare").arg(&one).arg(&one),
            &error(&["one.png", "1x1"]),
        );
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
        run_judged(
            "train --fit FIFO",
            xylem()
                .arg("train")
                .arg("--sample")
                .arg(dir.join("S"))
                .arg("--config")
                .arg(dir.join("tiny.toml"))
                .arg("--fit")
                .arg(&fifo)
                .arg("--out")
                .arg(dir.join("T")),
            &error(&["fit.toml", "not a regular file"]),
        );
    }
}
