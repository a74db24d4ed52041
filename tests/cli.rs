//! The `xylem` binary end to end on tiny sizes: outputs, config copies, errors.

use std::path::Path;

mod common;
use common::{assert_names, repo, run_err, run_ok, scratch, scratch_dir, xylem};
use xylem::config::ConfigFile;

#[test]
fn field_writes_faces_cuts_cross_and_config() {
    let out = scratch("field");
    run_ok(
        xylem()
            .args(["field", "--size", "16", "--out"])
            .arg(&out)
            .arg("--config")
            .arg(repo("configs/fields/minimal.toml")),
    );
    face_images(&out, 16);
    for f in ["cuts/cut1.png", "cuts/cut2.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let cross = image::open(out.join("unfolded.png")).unwrap();
    assert_eq!((cross.width(), cross.height()), (64, 48));
    // The copied config reproduces the field.
    let copy = xylem::field::FieldConfig::load(&out.join("config.toml")).unwrap();
    let original = xylem::field::FieldConfig::load(&repo("configs/fields/minimal.toml")).unwrap();
    assert_eq!(copy, original);
    // Re-running into its own output folder is allowed (files are replaced atomically).
    run_ok(
        xylem()
            .args(["field", "--preset", "knots", "--size", "8", "--out"])
            .arg(&out),
    );
}

#[test]
fn slice_writes_one_image_and_refuses_to_overwrite() {
    let dir = scratch_dir("slice");
    let png = dir.join("cut.png");
    let field = repo("configs/fields/knot_dead.toml");
    let args = |plane: &str| {
        let mut c = xylem();
        c.args(["slice", "--plane", plane, "--size", "12", "--field"])
            .arg(&field)
            .arg("--out")
            .arg(&png);
        c
    };
    run_ok(&mut args("cut2"));
    assert_eq!(image::open(&png).unwrap().width(), 12);
    let err = run_err(&mut args("-0.5,0,0.5;1,0,0;0,0,-1"));
    assert!(err.contains("--force"), "{err}");
    run_ok(args("-0.5,0,0.5;1,0,0;0,0,-1").arg("--force"));
    let err = run_err(&mut args("diagonal"));
    assert!(err.contains("cut1"), "{err}");
}

#[test]
fn bad_inputs_give_clear_errors() {
    let dir = scratch_dir("bad");
    let cfg = dir.join("bad.toml");
    std::fs::write(&cfg, "[pith]\norigin = [0.0, 0.0, -2.5]\ndirection = [0.0, 1.0, 0.1]\n[growth]\nyears_per_unit = 0.0\n").unwrap();
    let err = run_err(
        xylem()
            .args(["field", "--size", "8", "--out"])
            .arg(dir.join("o"))
            .arg("--config")
            .arg(&cfg),
    );
    assert_names(&err, &["bad.toml", "growth.years_per_unit"]);

    let err = run_err(
        xylem()
            .args(["field", "--size", "8", "--out"])
            .arg(dir.join("o2"))
            .arg("--config")
            .arg(dir.join("missing.toml")),
    );
    assert!(err.contains("missing.toml"), "{err}");

    // A folder with the user's files is never written into.
    let user = dir.join("user");
    assert_refuses_users_folder(&["field", "--preset", "far", "--size", "8", "--out"], &user);
    assert_eq!(std::fs::read_dir(&user).unwrap().count(), 1);

    let err = run_err(
        xylem()
            .args(["field", "--preset", "oak", "--size", "8", "--out"])
            .arg(dir.join("o3")),
    );
    assert!(err.contains("knot_alive"), "{err}");
}

/// `args` followed by a folder of the user's (`folder`, made with a notes file in it) is
/// refused as not written by xylem.
fn assert_refuses_users_folder(args: &[&str], folder: &Path) {
    std::fs::create_dir_all(folder).unwrap();
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    let err = run_err(xylem().args(args).arg(folder));
    assert!(err.contains("not written by xylem"), "{err}");
}

#[test]
fn help_shows_examples() {
    for cmd in [
        "field",
        "slice",
        "demo",
        "gallery",
        "run",
        "procedural",
        "sample",
    ] {
        let help = run_ok(xylem().args([cmd, "--help"]));
        assert!(
            help.contains("Example"),
            "{cmd} --help lacks examples:\n{help}"
        );
    }
}

/// The six face images of an output folder by face name, each checked to be `size` px
/// square.
fn face_images(out: &Path, size: u32) -> Vec<(&'static str, image::DynamicImage)> {
    ["A", "B", "C", "D", "E", "F"]
        .into_iter()
        .map(|f| {
            let img = image::open(out.join(format!("faces/{f}.png"))).unwrap();
            assert_eq!((img.width(), img.height()), (size, size), "face {f}");
            (f, img)
        })
        .collect()
}

/// `xylem procedural --size 12 --out OUT`, for more options to be added.
fn procedural_12(out: &Path) -> std::process::Command {
    let mut cmd = xylem();
    cmd.args(["procedural", "--size", "12", "--out"]).arg(out);
    cmd
}

#[test]
fn procedural_writes_images_config_and_volume() {
    let out = scratch("procedural");
    run_ok(
        procedural_12(&out)
            .args(["--volume-size", "6", "--fibre-direction", "--config"])
            .arg(repo("configs/species/oak.toml")),
    );
    for (f, img) in face_images(&out, 12) {
        assert_eq!(img.color(), image::ColorType::Rgb8, "face {f}");
    }
    for f in ["cuts/cut1.png", "cuts/cut2.png", "unfolded.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let copy = xylem::procedural::SpeciesConfig::load(&out.join("config.toml")).unwrap();
    let original =
        xylem::procedural::SpeciesConfig::load(&repo("configs/species/oak.toml")).unwrap();
    assert_eq!(copy, original);
    let volume = xylem::io::npy::read_volume(&out.join("volume.npy")).unwrap();
    assert_eq!((volume.dims, volume.channels), ([6, 6, 6], 3));
    // Voxel (i, j, k) is the model's colour at that voxel centre.
    let model = xylem::procedural::ProceduralWood::new(&original);
    let expected = model.colour(volume.voxel_point(1, 4, 2));
    assert_eq!(volume.voxel(1, 4, 2), &expected.to_array());
    let fibres = xylem::io::npy::read_volume(&out.join("fibre_direction.npy")).unwrap();
    assert_eq!((fibres.dims, fibres.channels), ([6, 6, 6], 3));
    let d = glam::Vec3::from_slice(fibres.voxel(3, 3, 3));
    assert!((d.length() - 1.0).abs() < 1e-4 && d.dot(model.field.pith.dir) > 0.9);
    // Issue 16 item 11: another species into the same folder without --volume does not
    // leave the oak volumes beside the new config.
    run_ok(procedural_12(&out).args(["--preset", "softwood"]));
    assert!(!out.join("volume.npy").exists() && !out.join("fibre_direction.npy").exists());
}

#[test]
fn sample_writes_the_mokume_layout_and_slice_takes_a_species() {
    let out = scratch("sample");
    let stdout = run_ok(
        xylem()
            .args(["sample", "--preset", "softwood", "--size", "16", "--out"])
            .arg(&out),
    );
    assert!(stdout.contains("2 knot crossings"), "{stdout}");
    for f in ["A", "B", "C", "D", "E", "F"] {
        for kind in ["col", "arl"] {
            assert!(out.join(format!("{f}_{kind}.png")).is_file(), "{f}_{kind}");
        }
    }
    assert!(out.join("C_knot.png").is_file() && out.join("F_knot.png").is_file());
    assert!(!out.join("A_knot.png").exists());
    for f in [
        "cut1.png",
        "cut2.png",
        "field.toml",
        "species.toml",
        "photograph.toml",
    ] {
        assert!(out.join("truth").join(f).is_file(), "truth/{f}");
    }
    let err = run_err(
        xylem()
            .args(["sample", "--preset", "oak", "--end-grain", "3", "--out"])
            .arg(out.join("too-light")),
    );
    assert_names(&err, &["--end-grain", "end_grain", "[0.25, 1.5]"]);
    assert!(
        !out.join("too-light").exists(),
        "nothing written for a refused factor"
    );
    // The truth field renders with `xylem field`.
    run_ok(
        xylem()
            .args(["field", "--size", "8", "--out"])
            .arg(out.join("field-render"))
            .arg("--config")
            .arg(out.join("truth/field.toml")),
    );

    let png = out.join("slice.png");
    run_ok(
        xylem()
            .args(["slice", "--plane", "cut2", "--size", "10", "--procedural"])
            .arg(repo("configs/species/walnut.toml"))
            .arg("--out")
            .arg(&png),
    );
    assert_eq!(image::open(&png).unwrap().color(), image::ColorType::Rgb8);
    let err = run_err(
        xylem()
            .args(["slice", "--plane", "cut2", "--out"])
            .arg(out.join("none.png")),
    );
    assert_names(&err, &["--field", "--procedural"]);
}

#[test]
fn gallery_builds_samples_from_species_presets() {
    let out = scratch("gallery");
    run_ok(
        xylem()
            .args([
                "gallery",
                "--size",
                "16",
                "--species",
                "chestnut,softwood",
                "--out",
            ])
            .arg(&out),
    );
    for species in ["chestnut", "softwood"] {
        let dir = out.join(species);
        let cross = image::open(dir.join("unfolded.png")).unwrap();
        assert_eq!((cross.width(), cross.height()), (64, 48));
        for f in [
            "unfolded_arl.png",
            "cuts.png",
            "config.toml",
            "sample/A_col.png",
        ] {
            assert!(dir.join(f).is_file(), "{species}/{f}");
        }
    }
    let err = run_err(
        xylem()
            .args(["gallery", "--size", "16", "--species", "teak", "--out"])
            .arg(out.join("x")),
    );
    assert_names(&err, &["teak", "chestnut"]);
    // Issue 16 item 11: not into a folder of the user's.
    let mine = out.join("mine");
    let gallery = ["gallery", "--size", "16", "--species", "oak", "--out"];
    assert_refuses_users_folder(&gallery, &mine);
    assert!(!mine.join("oak").exists());
}

/// Issue 16 item 1: `xylem report --out` never replaces a file the user has, and refuses
/// to write HTML under a name that is not a page (e.g. the run's own metrics.csv).
#[test]
fn report_keeps_existing_files() {
    let dir = scratch_dir("report-keep");
    let notes = dir.join("notes.html");
    std::fs::write(&notes, "my notes").unwrap();
    let metrics = dir.join("metrics.csv");
    std::fs::write(&metrics, "method,image\n").unwrap();
    let report = |out: &Path| {
        let mut cmd = xylem();
        cmd.args(["report", "--run"])
            .arg(&dir)
            .arg("--out")
            .arg(out);
        cmd
    };
    let err = run_err(&mut report(&notes));
    assert_names(&err, &["notes.html", "--force"]);
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "my notes");
    let err = run_err(&mut report(&metrics));
    assert_names(&err, &["metrics.csv", ".html"]);
    assert_eq!(std::fs::read_to_string(&metrics).unwrap(), "method,image\n");
    run_ok(report(&notes).arg("--force"));
    assert!(std::fs::read_to_string(&notes).unwrap().contains("<html"));
}

/// Issue 16 item 5/6: sizes and step counts that cannot make a picture or would run for
/// days are refused before any work, naming the flag.
#[test]
fn absurd_run_and_synth_options_are_refused_up_front() {
    let dir = scratch("absurd");
    for (args, flag) in [
        (
            vec!["run", "--sample", "S", "--out", "R", "--image-size", "0"],
            "--image-size",
        ),
        (
            vec!["run", "--sample", "S", "--out", "R", "--synth-steps", "0"],
            "--synth-steps",
        ),
        (
            vec!["synth", "--model", "M", "--out", "O", "--steps", "100000"],
            "--steps",
        ),
    ] {
        let err = run_err(xylem().current_dir(std::env::temp_dir()).args(&args));
        assert!(err.contains(flag), "{args:?}: {err}");
    }
    assert!(!dir.exists());
}

/// Issue 16 item 9: `texture2d` refuses a target too small to hold a texture.
#[test]
fn texture2d_refuses_a_one_pixel_target() {
    let dir = scratch_dir("t2d-tiny");
    let target = dir.join("tiny.png");
    image::RgbImage::from_pixel(1, 1, image::Rgb([120, 90, 60]))
        .save(&target)
        .unwrap();
    let err = run_err(
        xylem()
            .args(["texture2d", "--target"])
            .arg(&target)
            .arg("--out")
            .arg(dir.join("out")),
    );
    assert_names(&err, &["tiny.png", "1x1"]);
    assert!(!dir.join("out").exists());
}

/// Issue 15 item 6: with stderr not a terminal (here a pipe), long commands log progress
/// lines; `--quiet` silences them.
#[test]
fn progress_is_logged_to_a_pipe_and_quiet_silences_it() {
    let out = scratch("progress");
    let args = |quiet: bool| {
        let mut cmd = xylem();
        cmd.args(["procedural", "--size", "12", "--volume-size", "6", "-o"])
            .arg(&out)
            .arg("--preset")
            .arg("oak");
        if quiet {
            cmd.arg("--quiet");
        }
        cmd.output().expect("run xylem")
    };
    let logged = args(false);
    assert!(logged.status.success());
    let stderr = String::from_utf8_lossy(&logged.stderr);
    assert!(
        stderr.contains("volume slabs: 0/6 (0%)") || stderr.contains("volume slabs: 1/6"),
        "a first line when the work starts: {stderr}"
    );
    assert!(
        stderr.contains("volume slabs: 6/6 (100%), elapsed") && stderr.contains("done"),
        "a last line when it ends: {stderr}"
    );
    // --json is for the commands with a summary.
    let err = run_err(
        xylem()
            .args(["procedural", "--json", "--preset", "oak", "-o"])
            .arg(&out),
    );
    assert_names(&err, &["--json", "run, fit, train, compare"]);
    let quiet = args(true);
    assert!(quiet.status.success());
    let stderr = String::from_utf8_lossy(&quiet.stderr);
    assert!(!stderr.contains("slabs"), "--quiet: {stderr}");
}

/// Issue 15 items 1 and 4: the format follows the extension; colour is clamped and
/// reported; a fibre direction is not taken for colour; the extra grids go into the .vdb.
#[test]
fn export_infers_the_format_and_guards_colour() {
    let out = scratch("export-cli");
    run_ok(
        xylem()
            .args(["procedural", "--size", "12", "--volume-size", "6"])
            .arg("--fibre-direction")
            .arg("-o")
            .arg(&out)
            .args(["--preset", "oak"]),
    );
    let volume = out.join("volume.npy");
    let fibre = out.join("fibre_direction.npy");
    // `xylem export --volume VOLUME -o OUT/TO`, for more options to be added.
    let export = |volume: &Path, to: &str| {
        let mut cmd = xylem();
        cmd.arg("export")
            .arg("--volume")
            .arg(volume)
            .arg("-o")
            .arg(out.join(to));
        cmd
    };
    let said = run_ok(
        export(&volume, "wood.vdb")
            .arg("--fibre")
            .arg(&fibre)
            .arg("--field")
            .arg(repo("configs/fields/knot_alive.toml")),
    );
    assert_names(&said, &["colour, linear RGB", "clamped"]);
    let vdb = std::fs::read(out.join("wood.vdb")).unwrap();
    for grid in [&b"color"[..], b"growth", b"fibre"] {
        assert!(vdb.windows(grid.len()).any(|w| w == grid), "grid {grid:?}");
    }
    // Directions around a knot point every way: a third of the components are negative.
    let mut swirl = xylem::Volume::zeros([4, 4, 4], 3);
    for (n, v) in swirl.data.chunks_mut(3).enumerate() {
        let a = n as f32 * 0.7;
        v.copy_from_slice(&[a.cos(), a.sin(), 0.0]);
    }
    let swirl_path = out.join("swirl.npy");
    xylem::io::npy::write_volume(&swirl_path, &swirl).unwrap();
    let err = run_err(&mut export(&swirl_path, "swirl.nrrd"));
    assert_names(&err, &["swirl.npy", "--values data"]);
    assert!(!out.join("swirl.nrrd").exists());
    run_ok(export(&swirl_path, "swirl.nrrd").args(["--values", "data"]));
    let err = run_err(&mut export(&volume, "wood.raw"));
    assert_names(&err, &["wood.raw", ".vdb"]);
}

/// Issue 14: `xylem slice --grain-shading FIT` sees a volume with the fit's grain shading (end
/// grain darker by the fitted factor), and without the flag the same slice is plain.
#[test]
fn slice_sees_a_volume_with_a_fits_grain_shading() {
    use xylem::field::GrainShading;
    let dir = scratch("slice-grain-shading");
    std::fs::create_dir_all(dir.path()).unwrap();
    let volume = dir.path().join("v.npy");
    let grey = xylem::Volume::from_data([4, 4, 4], 3, vec![0.5; 4 * 4 * 4 * 3]).unwrap();
    xylem::io::npy::write_volume(&volume, &grey).unwrap();
    let mut field = xylem::presets::load_field_preset("straight").unwrap();
    let mut colour = common::flat_base_colour([0.6; 3]);
    colour.white_balance.grain = Some(GrainShading {
        fibre: [0.0, 1.0, 0.0],
        side: [0.66; 3],
        end: [0.42; 3],
        t_statistic: -3.0,
    });
    field.base_colour = Some(colour);
    let fit = dir.path().join("fit.toml");
    xylem::config::write_config_copy(&fit, &field, "test").unwrap();
    let slice_mean = |plane: &str, shaded: bool| -> f32 {
        let out = dir.path().join(format!("{plane}-{shaded}.png"));
        let mut cmd = xylem();
        cmd.args(["slice", "--size", "8", "--plane", plane, "--volume"])
            .arg(&volume)
            .arg("--out")
            .arg(&out);
        if shaded {
            cmd.arg("--grain-shading").arg(&fit);
        }
        run_ok(&mut cmd);
        let img = image::open(&out).unwrap().to_rgb8();
        img.pixels().map(|p| p[0] as f32).sum::<f32>() / (64.0 * 255.0)
    };
    // Face B (normal +y) is end grain: 0.5 x 0.42 / 0.6; face A side grain: 0.5 x 0.66 / 0.6.
    assert!((slice_mean("B", true) - 0.35).abs() < 0.01);
    assert!((slice_mean("A", true) - 0.55).abs() < 0.01);
    assert!((slice_mean("B", false) - 0.5).abs() < 0.01);
    // A fit without a base colour is a clear error naming the file.
    let bare = dir.path().join("bare.toml");
    field.base_colour = None;
    xylem::config::write_config_copy(&bare, &field, "test").unwrap();
    let err = run_err(
        xylem()
            .args(["slice", "--plane", "A", "--volume"])
            .arg(&volume)
            .arg("--grain-shading")
            .arg(&bare)
            .arg("--out")
            .arg(dir.path().join("x.png")),
    );
    assert_names(&err, &["bare.toml", "[base_colour]"]);
}
