//! Reliability suite (issue 16), family "sample folders": the photos, ring images and knot
//! markers a user points `--sample` at, damaged the ways the probe damaged them: missing,
//! black, one flat colour, tiny, 1x1, not a PNG, truncated, a folder or FIFO named like a
//! photo, not square, of another size than the rest, knot marker images with stray spots.
//! Each row is a 16 px sample folder with one defect and the expected outcome: an error
//! naming the file and what is expected, or the right result. `Sample::load` is probed
//! directly (the level every command goes through); a few rows run the binary to check the
//! same defects end commands (fit, train, texture2d) cleanly before any work.

mod common;
mod reliability_support;

use std::path::Path;

use xylem::Image2;
use xylem::frame::Face;
use xylem::io::save_png;
use xylem::sample::{Needs, Sample, parse_faces};

use reliability_support::{Expect, Tally, copy_dir, error, judge_result, repo, xylem};

const PHOTOS_AND_RINGS: Needs = Needs {
    photos: true,
    arl: true,
};

fn flat(n: usize, rgb: [f32; 3]) -> Image2 {
    let mut img = Image2::filled(n, n, 3, 0.0);
    for px in img.data.chunks_exact_mut(3) {
        px.copy_from_slice(&rgb);
    }
    img
}

/// A photo-like image of `w` x `h` (brown with noise).
fn photo(w: usize, h: usize) -> Image2 {
    let mut img = Image2::filled(w, h, 3, 0.0);
    for r in 0..h {
        for c in 0..w {
            let v = 0.5 + 0.2 * xylem::rng::unit(xylem::rng::hash3(7, r as i32, c as i32, 0));
            img.pixel_mut(r, c).copy_from_slice(&[v, 0.8 * v, 0.6 * v]);
        }
    }
    img
}

/// A white marker image with one dark pixel per (row, col, grey value).
fn markers(n: usize, spots: &[(usize, usize, u8)]) -> Image2 {
    let mut img = Image2::filled(n, n, 1, 1.0);
    for &(r, c, v) in spots {
        img.pixel_mut(r, c)[0] = f32::from(v) / 255.0;
    }
    img
}

type Setup = Box<dyn Fn(&Path)>;
type Check = Box<dyn Fn(&Sample)>;

struct Row {
    name: &'static str,
    setup: Setup,
    faces: Vec<Face>,
    needs: Needs,
    expect: Expect,
    /// Checks the loaded sample when the row expects success.
    check: Option<Check>,
}

fn row(name: &'static str, setup: impl Fn(&Path) + 'static, expect: Expect) -> Row {
    Row {
        name,
        setup: Box::new(setup),
        faces: Face::ALL.to_vec(),
        needs: PHOTOS_AND_RINGS,
        expect,
        check: None,
    }
}

fn fine(
    name: &'static str,
    setup: impl Fn(&Path) + 'static,
    check: impl Fn(&Sample) + 'static,
) -> Row {
    Row {
        check: Some(Box::new(check)),
        ..row(name, setup, Expect::Fine)
    }
}

/// A row's setup that removes `file` from the sample folder.
fn remove(file: &'static str) -> impl Fn(&Path) + 'static {
    move |d| std::fs::remove_file(d.join(file)).unwrap()
}

fn save(img: &Image2, path: &Path) {
    save_png(img, path).unwrap();
}

/// All six photos of `dir`, `side` x `side`.
fn square_photos(dir: &Path, side: usize) {
    for f in Face::ALL {
        save(&photo(side, side), &dir.join(format!("{f}_col.png")));
    }
}

fn has_mkfifo() -> bool {
    std::process::Command::new("mkfifo")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn damaged_sample_folders_give_clear_errors() {
    let dir = reliability_support::scratch("rel-samples");
    let base = dir.join("base");
    reliability_support::write_tiny_sample(&base, 16);
    let mut rows = vec![
        fine(
            "a good 16 px folder",
            |_| {},
            |s| {
                assert_eq!(s.size, 16);
                assert!(s.photos.iter().all(Option::is_some));
                assert!(s.knot_markers.is_empty());
            },
        ),
        row(
            "folder missing",
            |d| std::fs::remove_dir_all(d).unwrap(),
            error(&["sample folder not found", "A_col.png"]),
        ),
        row(
            "folder is a file",
            |d| {
                std::fs::remove_dir_all(d).unwrap();
                std::fs::write(d, "not a folder").unwrap();
            },
            error(&["sample folder not found"]),
        ),
        row(
            "empty folder",
            |d| {
                std::fs::remove_dir_all(d).unwrap();
                std::fs::create_dir(d).unwrap();
            },
            error(&["A_col.png", "missing face image"]),
        ),
        row(
            "one photo missing",
            remove("C_col.png"),
            error(&["C_col.png", "missing face image"]),
        ),
        row(
            "black photo",
            |d| save(&flat(16, [0.0, 0.0, 0.0]), &d.join("B_col.png")),
            error(&["B_col.png", "black", "expected a lit photo"]),
        ),
        row(
            "one black channel",
            |d| {
                let mut img = photo(16, 16);
                for px in img.data.chunks_exact_mut(3) {
                    px[2] = 0.0;
                }
                save(&img, &d.join("D_col.png"));
            },
            error(&["D_col.png", "black"]),
        ),
        row(
            "flat grey photo",
            |d| save(&flat(16, [0.5, 0.5, 0.5]), &d.join("E_col.png")),
            error(&["E_col.png", "one flat colour"]),
        ),
        row(
            "8x8 photos",
            |d| square_photos(d, 8),
            error(&["A_col.png", "is 8x8", "at least 16x16"]),
        ),
        row(
            "1x1 photos",
            |d| square_photos(d, 1),
            error(&["A_col.png", "is 1x1", "at least 16x16"]),
        ),
        row(
            "text file named A_col.png",
            |d| std::fs::write(d.join("A_col.png"), "these are my notes\n").unwrap(),
            error(&["A_col.png", "cannot decode"]),
        ),
        row(
            "empty file named A_col.png",
            |d| std::fs::write(d.join("A_col.png"), "").unwrap(),
            error(&["A_col.png", "cannot decode"]),
        ),
        row(
            "truncated PNG",
            |d| {
                let bytes = std::fs::read(d.join("F_col.png")).unwrap();
                std::fs::write(d.join("F_col.png"), &bytes[..bytes.len() / 2]).unwrap();
            },
            error(&["F_col.png", "cannot decode"]),
        ),
        row(
            "PNG header claiming 12000x12000 in 100 bytes (reserved 432 MB)",
            |d| {
                let mut bytes = std::fs::read(d.join("A_col.png")).unwrap();
                bytes[16..20].copy_from_slice(&12000u32.to_be_bytes());
                bytes[20..24].copy_from_slice(&12000u32.to_be_bytes());
                let crc = reliability_support::crc32(&bytes[12..29]);
                bytes[29..33].copy_from_slice(&crc.to_be_bytes());
                bytes.truncate(100);
                std::fs::write(d.join("A_col.png"), bytes).unwrap();
            },
            error(&["A_col.png", "12000x12000", "truncated or damaged"]),
        ),
        row(
            "a folder named A_col.png",
            |d| {
                std::fs::remove_file(d.join("A_col.png")).unwrap();
                std::fs::create_dir(d.join("A_col.png")).unwrap();
            },
            error(&["A_col.png", "not a regular file"]),
        ),
        row(
            "not square",
            |d| save(&photo(16, 20), &d.join("A_col.png")),
            error(&["A_col.png", "16x20", "square"]),
        ),
        row(
            "one photo of another size",
            |d| save(&photo(20, 20), &d.join("F_col.png")),
            error(&["F_col.png", "20x20", "other images are 16x16"]),
        ),
        row(
            "ring images missing",
            remove("B_arl.png"),
            error(&["B_arl-unet.png", "missing ring localisation image"]),
        ),
        row(
            "ring image of another size",
            |d| save(&Image2::filled(32, 32, 1, 0.5), &d.join("C_arl.png")),
            error(&["C_arl.png", "32x32", "16x16"]),
        ),
        row(
            "knot marker with 20 stray pixels",
            |d| {
                let spots: Vec<(usize, usize, u8)> = (0..20)
                    .map(|i| ((i / 5) * 3, (i % 5) * 3, 100 + i as u8))
                    .collect();
                save(&markers(16, &spots), &d.join("C_knot.png"));
            },
            error(&["C_knot.png", "20 marker spots", "at most 8"]),
        ),
        row(
            "knot marker of another size",
            |d| save(&markers(32, &[(3, 3, 186)]), &d.join("C_knot.png")),
            error(&["C_knot.png", "32x32"]),
        ),
        row(
            "knot marker that is not a PNG",
            |d| std::fs::write(d.join("F_knot.png"), b"GIF89a").unwrap(),
            error(&["F_knot.png", "cannot decode"]),
        ),
        fine(
            "knot markers on C and F (one knot)",
            |d| {
                save(&markers(16, &[(4, 5, 186)]), &d.join("C_knot.png"));
                save(&markers(16, &[(9, 9, 186)]), &d.join("F_knot.png"));
            },
            |s| {
                let knots = s.knots();
                assert_eq!(knots.len(), 1, "{knots:?}");
                let faces: Vec<Face> = knots[0].iter().map(|m| m.face).collect();
                assert_eq!(faces, [Face::C, Face::F]);
                assert_eq!((knots[0][0].row, knots[0][0].col), (4.0, 5.0));
            },
        ),
        fine(
            "16-bit, grey and RGBA photos load as RGB",
            |d| {
                let wide = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(16, 16, |x, y| {
                    image::Rgb([20000 + (x * 900) as u16, 15000 + (y * 700) as u16, 9000])
                });
                wide.save(d.join("A_col.png")).unwrap();
                let grey = image::ImageBuffer::<image::Luma<u8>, _>::from_fn(16, 16, |x, y| {
                    image::Luma([100 + (x * 3 + y * 5) as u8])
                });
                grey.save(d.join("B_col.png")).unwrap();
                let rgba = image::ImageBuffer::<image::Rgba<u8>, _>::from_fn(16, 16, |x, y| {
                    image::Rgba([120 + x as u8, 90 + y as u8, 60, 10])
                });
                rgba.save(d.join("C_col.png")).unwrap();
            },
            |s| {
                for f in [Face::A, Face::B, Face::C] {
                    let p = s.photo(f).unwrap();
                    assert_eq!((p.width, p.channels), (16, 3));
                    assert!(p.data.iter().all(|v| (0.0..=1.0).contains(v)));
                }
                let a = s.photo(Face::A).unwrap();
                assert!((a.get(0, 0, 0) - 20000.0 / 65535.0).abs() < 1.0 / 255.0);
                let b = s.photo(Face::B).unwrap();
                assert_eq!(b.get(2, 1, 0), b.get(2, 1, 2), "grey stays grey");
            },
        ),
    ];
    // Faces left out need not exist (leave-one-face-out on a folder missing that face).
    rows.push(Row {
        faces: vec![Face::A, Face::B, Face::D, Face::E, Face::F],
        check: Some(Box::new(|s: &Sample| {
            assert!(s.photo(Face::C).is_none() && s.photo(Face::A).is_some());
        })),
        ..row("held-out face C missing", remove("C_col.png"), Expect::Fine)
    });
    rows.push(Row {
        needs: Needs {
            photos: true,
            arl: false,
        },
        check: Some(Box::new(|s: &Sample| {
            assert!(s.ring_image(Face::A).is_none())
        })),
        ..row(
            "training needs no ring images",
            |d| {
                for f in Face::ALL {
                    std::fs::remove_file(d.join(format!("{f}_arl.png"))).unwrap();
                }
            },
            Expect::Fine,
        )
    });
    rows.push(Row {
        faces: vec![],
        ..row("no faces selected", |_| {}, error(&["no faces selected"]))
    });
    if has_mkfifo() {
        rows.push(row(
            "a FIFO named A_col.png",
            |d| {
                std::fs::remove_file(d.join("A_col.png")).unwrap();
                let ok = std::process::Command::new("mkfifo")
                    .arg(d.join("A_col.png"))
                    .status()
                    .unwrap()
                    .success();
                assert!(ok);
            },
            error(&["A_col.png", "not a regular file"]),
        ));
    }

    let mut tally = Tally::default();
    for (i, r) in rows.iter().enumerate() {
        let folder = dir.join(format!("row{i}"));
        copy_dir(&base, &folder);
        (r.setup)(&folder);
        let result = Sample::load(&folder, &r.faces, r.needs);
        tally.add(judge_result(r.name, &result, &r.expect));
        if let (Ok(sample), Some(check)) = (&result, &r.check) {
            check(sample);
        }
        if let Err(e) = &result {
            let shown = folder.display().to_string();
            assert!(
                e.to_string().contains(&shown) || matches!(r.expect, Expect::Fine),
                "{}: the error does not name the folder or file: {e}",
                r.name
            );
        }
    }
    tally.print("sample folders (library)");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn face_lists_are_parsed_or_refused() {
    let mut tally = Tally::default();
    for (list, expect) in [
        ("A,B,C,D,E", Expect::Fine),
        (" c , a ,c", Expect::Fine),
        (
            "A,G",
            error(&["`faces` \"A,G\"", "\"G\" is not a face", "A..F"]),
        ),
        ("", error(&["no faces given"])),
        (",,,", error(&["no faces given"])),
        ("AB", error(&["\"AB\" is not a face"])),
        ("A;B", error(&["\"A;B\" is not a face"])),
        ("1,2", error(&["\"1\" is not a face"])),
    ] {
        let result = parse_faces(list);
        tally.add(judge_result(list, &result, &expect));
        if list == " c , a ,c" {
            assert_eq!(result.unwrap(), [Face::A, Face::C], "sorted, unique");
        }
    }
    tally.print("face lists (library)");
}

/// The same defects through the commands users run: each ends with rc 1 and one message
/// naming the file, before any output is written.
#[test]
fn commands_refuse_damaged_samples_before_working() {
    let dir = reliability_support::scratch("rel-samples-cli");
    let good = dir.join("good");
    reliability_support::write_tiny_sample(&good, 16);
    let black = dir.join("black");
    copy_dir(&good, &black);
    save(&flat(16, [0.0, 0.0, 0.0]), &black.join("D_col.png"));
    let tiny = dir.join("tiny");
    copy_dir(&good, &tiny);
    square_photos(&tiny, 1);
    let stray = dir.join("stray");
    copy_dir(&good, &stray);
    let spots: Vec<(usize, usize, u8)> = (0..12).map(|i| (i, 15 - i, 90 + 3 * i as u8)).collect();
    save(&markers(16, &spots), &stray.join("A_knot.png"));
    save(&photo(1, 1), &dir.join("one.png"));
    let nca = dir.join("tiny.toml");
    std::fs::write(&nca, reliability_support::TINY_NCA).unwrap();
    let field = repo("configs/fields/distorted.toml");

    let mut tally = Tally::default();
    // The command lines, up to `--out`.
    let os = |words: &[&dyn AsRef<std::ffi::OsStr>]| -> Vec<std::ffi::OsString> {
        words.iter().map(|w| w.as_ref().to_os_string()).collect()
    };
    let fit = |sample: &Path| os(&[&"fit", &"--sample", &sample]);
    let train = |sample: &Path| {
        os(&[
            &"train",
            &"--sample",
            &sample,
            &"--config",
            &nca,
            &"--fit",
            &field,
        ])
    };
    let texture2d = |target: &Path| os(&[&"texture2d", &"--target", &target, &"--steps", &"1"]);
    let cases: Vec<(&str, Vec<std::ffi::OsString>, Expect, &str)> = vec![
        (
            "fit on a black face",
            fit(&black),
            error(&["D_col.png", "black"]),
            "fit-black",
        ),
        (
            "fit on a knot marker with 12 spots",
            fit(&stray),
            error(&["A_knot.png", "12 marker spots"]),
            "fit-stray",
        ),
        (
            "train on 1x1 faces",
            train(&tiny),
            error(&["A_col.png", "is 1x1", "at least 16x16"]),
            "train-tiny",
        ),
        (
            "train on a black face",
            train(&black),
            error(&["D_col.png", "black"]),
            "train-black",
        ),
        (
            "texture2d on a 1x1 target",
            texture2d(&dir.join("one.png")),
            error(&["one.png", "is 1x1", "at least 16x16"]),
            "t2d-one",
        ),
        (
            "texture2d on a folder",
            texture2d(&good),
            error(&["good", "not a regular file", "expected a PNG"]),
            "t2d-folder",
        ),
        (
            "run on a missing sample",
            os(&[&"run", &"--sample", &dir.join("nothere")]),
            error(&["nothere"]),
            "run-missing",
        ),
    ];
    for (name, args, expect, out) in cases {
        let target = dir.join(out);
        let outcome =
            tally.judge_call(name, xylem().args(&args).arg("--out").arg(&target), &expect);
        assert_eq!(outcome.code, Some(1), "{name}: {}", outcome.stderr);
        // Nothing but xylem's folder marker may have been written.
        let written: Vec<String> = std::fs::read_dir(&target)
            .map(|d| {
                d.flatten()
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .filter(|n| n != ".xylem-output" && n != "sample.toml")
                    .collect()
            })
            .unwrap_or_default();
        assert!(written.is_empty(), "{name}: wrote {written:?}");
    }
    tally.print("sample folders (CLI)");
    std::fs::remove_dir_all(&dir).unwrap();
}
