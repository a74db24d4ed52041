//! Reliability suite (issue 16), family "configs": every TOML config a user writes (growth
//! field, species, NCA training, fit, render, style loss, texture2d) fed the mistakes the
//! probe made: wrong types, unknown keys and sections, arrays of the wrong length (the
//! issue's `steps = [12, 15, 19]` trained as `[12, 15]`), out-of-range, negative and
//! non-finite numbers, duplicate keys, broken syntax, absurd sizes. Each row is one file
//! and its expected outcome: an error naming the file, the key and what is expected
//! (checked by substrings), or the right value. Loading goes through the library's
//! `*Config::load` (what every command calls); the rows where the CLI adds a check of its
//! own (memory estimates, knot limits end to end) run the binary.

mod common;
mod reliability_support;

use std::path::Path;

use xylem::field::FieldConfig;
use xylem::fit::FitConfig;
use xylem::loss::{LossConfig, Texture2dConfig};
use xylem::nca::TrainConfig;
use xylem::procedural::SpeciesConfig;
use xylem::render::RenderConfig;

use reliability_support::{Expect, Tally, error, judge_result, repo, set, xylem};
use xylem::config::ConfigFile;

const FIELD: &str = "[pith]\norigin = [0.0, 0.0, -2.5]\ndirection = [0.0, 1.0, 0.1]\n\
                     [growth]\nyears_per_unit = 12.0\n";

fn shipped(path: &str) -> String {
    std::fs::read_to_string(repo(path)).unwrap()
}

#[derive(Clone, Copy, Debug)]
enum Loader {
    Field,
    Species,
    Nca,
    Fit,
    Render,
    Loss,
    Texture2d,
}

impl Loader {
    fn load(self, path: &Path) -> xylem::Result<()> {
        match self {
            Loader::Field => FieldConfig::load(path).map(drop),
            Loader::Species => SpeciesConfig::load(path).map(drop),
            Loader::Nca => TrainConfig::load(path).map(drop),
            Loader::Fit => FitConfig::load(path).map(drop),
            Loader::Render => RenderConfig::load(path).map(drop),
            Loader::Loss => LossConfig::load(path).map(drop),
            Loader::Texture2d => Texture2dConfig::load(path).map(drop),
        }
    }
}

struct Row {
    name: &'static str,
    loader: Loader,
    text: String,
    expect: Expect,
}

fn row(name: &'static str, loader: Loader, text: impl Into<String>, expect: Expect) -> Row {
    Row {
        name,
        loader,
        text: text.into(),
        expect,
    }
}

fn field_rows() -> Vec<Row> {
    use Loader::Field as F;
    let knots: String = (0..100)
        .map(|_| "[[knots]]\norigin = [0.0, 0.0, 0.0]\ndirection = [1.0, 0.0, 0.0]\n")
        .collect();
    let grid: String = (0..100_000).map(|_| "8, ").collect();
    let one_knot =
        format!("{FIELD}[[knots]]\norigin = [0.0, 0.0, 0.0]\ndirection = [1.0, 0.0, 0.0]\n");
    vec![
        row("field: the minimal file", F, FIELD, Expect::Fine),
        row(
            "field: years_per_unit a string",
            F,
            set(FIELD, "growth.years_per_unit", Some("\"twelve\"")),
            error(&["years_per_unit", "invalid type", "expected f32"]),
        ),
        row(
            "field: unknown key",
            F,
            set(FIELD, "growth.colour", Some("3")),
            error(&["unknown field `colour`", "years_per_unit"]),
        ),
        row(
            "field: unknown section",
            F,
            format!("{FIELD}[bark]\nthickness = 1\n"),
            error(&["unknown field `bark`", "pith"]),
        ),
        row(
            "field: direction of 4 values",
            F,
            set(FIELD, "pith.direction", Some("[0.0, 1.0, 0.1, 4.0]")),
            error(&["pith.direction", "4 values given, expected 3"]),
        ),
        row(
            "field: direction of 2 values",
            F,
            set(FIELD, "pith.direction", Some("[0.0, 1.0]")),
            error(&["direction", "invalid length 2", "length 3"]),
        ),
        row(
            "field: direction [1e30, 1e30, 0] (length overflows)",
            F,
            set(FIELD, "pith.direction", Some("[1e30, 1e30, 0.0]")),
            error(&["pith.direction", "components within +-1e6"]),
        ),
        row(
            "field: zero direction",
            F,
            set(FIELD, "pith.direction", Some("[0.0, 0.0, 0.0]")),
            error(&["pith.direction", "not zero"]),
        ),
        row(
            "field: direction a string",
            F,
            set(FIELD, "pith.direction", Some("\"up\"")),
            error(&["direction", "invalid type: string", "array of length 3"]),
        ),
        row(
            "field: years_per_unit nan",
            F,
            set(FIELD, "growth.years_per_unit", Some("nan")),
            error(&["growth.years_per_unit", "NaN", "> 0 and <= 10000"]),
        ),
        row(
            "field: years_per_unit inf",
            F,
            set(FIELD, "growth.years_per_unit", Some("inf")),
            error(&["growth.years_per_unit", "inf"]),
        ),
        row(
            "field: years_per_unit negative",
            F,
            set(FIELD, "growth.years_per_unit", Some("-3.0")),
            error(&["growth.years_per_unit", "-3"]),
        ),
        row(
            "field: grid [100000, 16, 16]",
            F,
            set(FIELD, "growth.grid", Some("[100000, 16, 16]")),
            error(&["growth.grid[0]", "100000", "[1, 64]"]),
        ),
        row(
            "field: grid of 100000 entries",
            F,
            format!("{FIELD}grid = [{grid}]\n"),
            error(&["growth.grid", "100000 values given, expected 3"]),
        ),
        row(
            "field: grid with a negative entry",
            F,
            set(FIELD, "growth.grid", Some("[-1, 16, 16]")),
            error(&["grid", "invalid value: integer `-1`"]),
        ),
        row(
            "field: origin 1e9 away",
            F,
            set(FIELD, "pith.origin", Some("[1e9, 0.0, 0.0]")),
            error(&["pith.origin", "within +-100"]),
        ),
        row(
            "field: rates of the wrong count",
            F,
            set(FIELD, "growth.rates", Some("[1.0, 2.0]")),
            error(&["growth.rates", "has 2 values", "2048"]),
        ),
        row(
            "field: a NaN rate",
            F,
            set(
                &set(FIELD, "growth.grid", Some("[1, 4, 2]")),
                "growth.rates",
                Some("[1.0, 1.0, 1.0, nan, 1.0, 1.0, 1.0, 1.0]"),
            ),
            error(&["growth.rates", "[3] = NaN", "finite"]),
        ),
        row(
            "field: rings that decrease",
            F,
            format!("{FIELD}[growth.rings]\nat = [3.0, 2.0]\nfirst_year = 1\n"),
            error(&["growth.rings.at", "increase strictly"]),
        ),
        row(
            "field: height_range upside down",
            F,
            set(FIELD, "growth.height_range", Some("[1.0, 0.0]")),
            error(&["growth.height_range", "low < high"]),
        ),
        row(
            "field: 100 knots",
            F,
            format!("{FIELD}{knots}"),
            error(&["`knots` = 100", "[0, 64]"]),
        ),
        row(
            "field: knot speed 0",
            F,
            set(&one_knot, "knots[0].speed", Some("0.0")),
            error(&["knots[0].speed", "[0.005, 1]"]),
        ),
        row(
            "field: knot reach reversed",
            F,
            set(&one_knot, "knots[0].reach", Some("[6.0, 3.0]")),
            error(&["knots[0].reach", "0 < near < far"]),
        ),
        row(
            "field: missing key",
            F,
            "[pith]\norigin = [0.0, 0.0, -2.5]\n",
            error(&["missing field `direction`"]),
        ),
        row("field: empty file", F, "", error(&["missing field `pith`"])),
        row(
            "field: a key given twice",
            F,
            format!("{FIELD}years_per_unit = 3.0\n"),
            error(&["duplicate key", "years_per_unit"]),
        ),
        row(
            "field: broken syntax",
            F,
            format!("{FIELD} = oops\n"),
            error(&["TOML parse error at line 6"]),
        ),
    ]
}

fn species_rows() -> Vec<Row> {
    use Loader::Species as S;
    let oak = shipped("configs/species/oak.toml");
    let five_rays = {
        let ray = "[[rays]]\ncell_mm = [5.0, 0.6, 1.5]\nsize_mm = [3.0, 0.16, 0.8]\n\
                   size_variation = 0.5\noccurrence = 0.5\ncolour = [0.6, 0.45, 0.29]\n\
                   opacity = 0.35\n";
        format!("{oak}\n{}", ray.repeat(3))
    };
    vec![
        row("species: oak as shipped", S, oak.clone(), Expect::Fine),
        row(
            "species: 5 ray layers",
            S,
            five_rays,
            error(&["rays", "has 5 layers", "at most 4"]),
        ),
        row(
            "species: ray colour out of range",
            S,
            set(&oak, "rays[0].colour", Some("[2.0, 0.0, 0.0]")),
            error(&["rays[0].colour", "values in [0, 1]"]),
        ),
        row(
            "species: pore cell of 0 mm",
            S,
            set(&oak, "pores.cell_mm", Some("[0.0, 0.42, 10.0]")),
            error(&["pores.cell_mm", "> 0"]),
        ),
        row(
            "species: ring years reversed",
            S,
            set(&oak, "rings.years", Some("[40.0, 20.0]")),
            error(&["rings.years", "low < high"]),
        ),
        row(
            "species: colour stop of 5 values",
            S,
            set(
                &oak,
                "rings.earlywood.stops",
                Some("[[0.0, 0.76, 0.60, 0.42, 9.0], [1.0, 0.84, 0.71, 0.53]]"),
            ),
            error(&["rings.earlywood.stops[0]", "5 values given, expected 4"]),
        ),
        row(
            "species: unknown key",
            S,
            set(&oak, "rings.colour", Some("1")),
            error(&["unknown field `colour`"]),
        ),
        row(
            "species: seed negative",
            S,
            set(&oak, "seed", Some("-1")),
            error(&["seed", "invalid value: integer `-1`"]),
        ),
        row(
            "species: name a number",
            S,
            set(&oak, "name", Some("3")),
            error(&["name", "invalid type: integer `3`"]),
        ),
        row(
            "species: growth distortion amplitude inf",
            S,
            set(&oak, "growth.distortion.amplitude", Some("inf")),
            error(&["growth.distortion.amplitude", "inf"]),
        ),
    ]
}

fn nca_rows() -> Vec<Row> {
    use Loader::Nca as N;
    let quick = shipped("configs/nca/quick.toml");
    vec![
        row("nca: quick as shipped", N, quick.clone(), Expect::Fine),
        row(
            "nca: steps of 3 values",
            N,
            set(&quick, "schedule.steps", Some("[12, 15, 19]")),
            error(&["schedule.steps: 3 values given, expected 2"]),
        ),
        row(
            "nca: steps reversed",
            N,
            set(&quick, "schedule.steps", Some("[16, 8]")),
            error(&["schedule.steps", "min <= max"]),
        ),
        row(
            "nca: steps 0",
            N,
            set(&quick, "schedule.steps", Some("[0, 0]")),
            error(&["schedule.steps", "= 0", "[1, 10000]"]),
        ),
        row(
            "nca: steps up to 100000",
            N,
            set(&quick, "schedule.steps", Some("[8, 100000]")),
            error(&["schedule.steps", "max <= 10000"]),
        ),
        row(
            "nca: iterations 0",
            N,
            set(&quick, "schedule.iterations", Some("0")),
            error(&["schedule.iterations", "= 0"]),
        ),
        row(
            "nca: learning rate nan",
            N,
            set(&quick, "schedule.learning_rate", Some("nan")),
            error(&["schedule.learning_rate", "NaN"]),
        ),
        row(
            "nca: learning rate a string",
            N,
            set(&quick, "schedule.learning_rate", Some("\"fast\"")),
            error(&["learning_rate", "invalid type: string"]),
        ),
        row(
            "nca: volume 2048",
            N,
            set(&quick, "volume.size", Some("2048")),
            error(&["volume.size", "2048", "[4, 1024]"]),
        ),
        row(
            "nca: crop above the volume",
            N,
            set(&quick, "volume.crop", Some("256")),
            error(&["volume.crop", "at most volume.size"]),
        ),
        row(
            "nca: hidden 0",
            N,
            set(&quick, "model.hidden", Some("0")),
            error(&["model.hidden", "[1, 1024]"]),
        ),
        row(
            "nca: a conditioning channel twice",
            N,
            set(&quick, "model.conditioning", Some("[\"g\", \"g\"]")),
            error(&["model.conditioning", "twice"]),
        ),
        row(
            "nca: unknown conditioning channel",
            N,
            set(&quick, "model.conditioning", Some("[\"rgb\"]")),
            error(&["unknown variant `rgb`"]),
        ),
        row(
            "nca: unknown face loss",
            N,
            set(&quick, "loss.face", Some("\"vgg\"")),
            error(&["unknown variant `vgg`"]),
        ),
        row(
            "nca: inner planes without the guided loss",
            N,
            set(
                &set(&quick, "loss.face", Some("\"style\"")),
                "loss.inner_planes",
                Some("3"),
            ),
            error(&["loss.inner_planes", "guided"]),
        ),
        row(
            "nca: low-band blocks that do not divide the crop",
            N,
            set(
                &set(&quick, "loss.low_band", Some("1.0")),
                "loss.low_band_block",
                Some("5"),
            ),
            error(&["loss.low_band_block", "divide the crop side"]),
        ),
        row(
            "nca: unknown low-band reference",
            N,
            set(&quick, "loss.low_band_reference", Some("\"median\"")),
            error(&["unknown variant `median`", "crop_mean"]),
        ),
        row(
            "nca: negative low-band weight",
            N,
            set(&quick, "loss.low_band", Some("-1.0")),
            error(&["loss.low_band", "low-band loss weight"]),
        ),
        row(
            "nca: negative guide weight for wood without vessels",
            N,
            set(
                &quick,
                "loss.guided.guide_weight_without_vessels",
                Some("-2.0"),
            ),
            error(&[
                "loss.guided.guide_weight_without_vessels",
                "= -2",
                "[0, 100]",
            ]),
        ),
        row(
            "nca: fibre cells that the vessel gate never uses",
            N,
            set(
                &quick,
                "model.grain_noise.without_vessels",
                Some("{ across_mm = 0.2, along_mm = 3.0 }"),
            ),
            error(&[
                "model.grain_noise.without_vessels",
                "min_vessel_fraction = 0",
            ]),
        ),
        row(
            "nca: pool of a million",
            N,
            set(&quick, "pool.size", Some("1000000")),
            error(&["pool.size", "[0, 4096]"]),
        ),
        row(
            "nca: checkpoint every 0 minutes",
            N,
            set(&quick, "checkpoint.minutes", Some("0.0")),
            error(&["checkpoint.minutes", "> 0"]),
        ),
        row(
            "nca: slab of 1 voxel",
            N,
            set(&quick, "memory.slab_voxels", Some("1")),
            error(&["memory.slab_voxels", "[1024, 1073741824]"]),
        ),
        row(
            "nca: unknown engine",
            N,
            format!("{quick}\n[compute]\nengine = \"gpu\"\n"),
            error(&["unknown variant `gpu`", "fused"]),
        ),
        row(
            "nca: style loss of 99 octaves",
            N,
            set(&quick, "loss.style.octaves", Some("99")),
            error(&["loss.style.octaves", "[1, 8]"]),
        ),
        row(
            "nca: even kernel size",
            N,
            set(&quick, "loss.style.filters.kernel_sizes", Some("[4]")),
            error(&["loss.style.filters.kernel_sizes", "contains 4"]),
        ),
        row(
            "nca: unknown key in [volume]",
            N,
            set(&quick, "volume.depth", Some("3")),
            error(&["unknown field `depth`"]),
        ),
        row(
            "nca: a negative seed",
            N,
            set(&quick, "seed", Some("-2")),
            error(&["seed", "invalid value: integer `-2`"]),
        ),
    ]
}

fn other_rows() -> Vec<Row> {
    let fit = shipped("configs/fit/default.toml");
    let render = shipped("configs/render/default.toml");
    let loss = shipped("configs/loss/default.toml");
    let t2d =
        xylem::config::to_toml(&Texture2dConfig::with_loss(LossConfig::default_config())).unwrap();
    use Loader::{Fit, Loss, Render, Texture2d};
    vec![
        row("fit: an empty file is the defaults", Fit, "", Expect::Fine),
        row("fit: as shipped", Fit, fit.clone(), Expect::Fine),
        row(
            "fit: grid of 0 heights",
            Fit,
            set(&fit, "distortion.grid", Some("[0, 16, 16]")),
            error(&["distortion.grid[0]", "[1, 64]"]),
        ),
        row(
            "fit: no pith distances",
            Fit,
            set(&fit, "pith.distances", Some("[]")),
            error(&["pith.distances", "has 0 values"]),
        ),
        row(
            "fit: threshold 2",
            Fit,
            set(&fit, "contours.threshold", Some("2.0")),
            error(&["contours.threshold", "(0, 1]"]),
        ),
        row(
            "fit: a million bar nodes",
            Fit,
            set(&fit, "colour.bar_nodes", Some("1000000")),
            error(&["colour.bar_nodes", "[2, 4096]"]),
        ),
        row(
            "fit: knots.fit a string",
            Fit,
            set(&fit, "knots.fit", Some("\"yes\"")),
            error(&["fit", "invalid type: string", "boolean"]),
        ),
        row(
            "fit: unknown section",
            Fit,
            format!("{fit}\n[extra]\nx = 1\n"),
            error(&["unknown field `extra`"]),
        ),
        row("render: as shipped", Render, render.clone(), Expect::Fine),
        row(
            "render: 1000 samples per axis",
            Render,
            set(&render, "samples_per_axis", Some("1000")),
            error(&["samples_per_axis", "[1, 16]"]),
        ),
        row(
            "render: background of 5 values",
            Render,
            set(&render, "background", Some("[0.9, 0.9, 0.9, 0.9, 0.9]")),
            error(&["background: 5 values given, expected 3"]),
        ),
        row(
            "render: field of view 0",
            Render,
            set(&render, "camera.fov_deg", Some("0.0")),
            error(&["camera.fov_deg", "[1, 170]"]),
        ),
        row(
            "render: up along the view",
            Render,
            set(&render, "camera.up", Some("[-2.1, -1.79, -2.75]")),
            error(&["camera.up", "parallel"]),
        ),
        row(
            "render: zero light direction",
            Render,
            set(&render, "light.direction", Some("[0.0, 0.0, 0.0]")),
            error(&["light.direction", "not zero"]),
        ),
        row(
            "render: no turntable views",
            Render,
            set(&render, "turntable_views", Some("0")),
            error(&["turntable_views", "[1, 64]"]),
        ),
        row(
            "render: NaN rotation",
            Render,
            set(&render, "carve.rotate_deg", Some("[nan, 0.0, 0.0]")),
            error(&["carve.rotate_deg", "NaN"]),
        ),
        row("loss: as shipped", Loss, loss.clone(), Expect::Fine),
        row(
            "loss: 0 octaves",
            Loss,
            set(&loss, "octaves", Some("0")),
            error(&["octaves", "[1, 8]"]),
        ),
        row(
            "loss: every weight 0",
            Loss,
            set(
                &set(
                    &set(
                        &set(
                            &set(&loss, "weights.gram", Some("0.0")),
                            "weights.mean",
                            Some("0.0"),
                        ),
                        "weights.covariance",
                        Some("0.0"),
                    ),
                    "weights.swd",
                    Some("0.0"),
                ),
                "weights.colour",
                Some("0.0"),
            ),
            error(&["weights.swd", "all weights are 0"]),
        ),
        row(
            "loss: an empty filter bank",
            Loss,
            set(
                &set(&loss, "filters.random", Some("0")),
                "filters.orientations",
                Some("0"),
            ),
            error(&["filters.random", "the bank is empty"]),
        ),
        row(
            "loss: a billion projections",
            Loss,
            set(&loss, "swd.projections", Some("1000000000")),
            error(&["swd.projections", "[1, 512]"]),
        ),
        row(
            "loss: unknown nonlinearity",
            Loss,
            set(&loss, "filters.nonlinearity", Some("\"tanh\"")),
            error(&["unknown variant `tanh`"]),
        ),
        row(
            "texture2d: as written",
            Texture2d,
            t2d.clone(),
            Expect::Fine,
        ),
        row(
            "texture2d: size 1",
            Texture2d,
            set(&t2d, "size", Some("1")),
            error(&["size", "[8, 2048]"]),
        ),
        row(
            "texture2d: steps 0",
            Texture2d,
            set(&t2d, "steps", Some("0")),
            error(&["steps", "[1, 1000000]"]),
        ),
        row(
            "texture2d: negative learning rate",
            Texture2d,
            set(&t2d, "learning_rate", Some("-1.0")),
            error(&["learning_rate", "> 0"]),
        ),
    ]
}

#[test]
fn bad_configs_give_clear_errors() {
    let dir = reliability_support::scratch("rel-configs");
    let mut rows = field_rows();
    rows.extend(species_rows());
    rows.extend(nca_rows());
    rows.extend(other_rows());
    let mut tally = Tally::default();
    for (i, r) in rows.iter().enumerate() {
        let path = dir.join(format!("row{i}.toml"));
        std::fs::write(&path, &r.text).unwrap();
        let result = r.loader.load(&path);
        tally.add(judge_result(r.name, &result, &r.expect));
        if let Err(e) = &result {
            assert!(
                e.to_string().contains(&path.display().to_string()),
                "{}: the error does not name the file: {e}",
                r.name
            );
        }
    }
    // Bytes that are not text.
    let path = dir.join("binary.toml");
    std::fs::write(&path, [0x93, 0xff, 0x00, 0x12, 0x80]).unwrap();
    let result = FieldConfig::load(&path);
    tally.add(judge_result(
        "field: not UTF-8",
        &result,
        &error(&["binary.toml", "valid UTF-8"]),
    ));
    // A missing file and a folder given as the config.
    let result = TrainConfig::load(&dir.join("missing.toml"));
    tally.add(judge_result(
        "nca: missing file",
        &result,
        &error(&["missing.toml", "No such file"]),
    ));
    let result = FitConfig::load(&dir);
    tally.add(judge_result(
        "fit: a folder as the config",
        &result,
        &error(&["rel-configs"]),
    ));
    tally.print("configs (library)");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The right value, not only no error: what the probe saw accepted silently now either
/// fails or means what it says.
#[test]
fn accepted_configs_mean_what_they_say() {
    let mut tally = Tally::default();
    let origin = Path::new("<test>");
    // `[1, 1, 0]` is the direction [1e30, 1e30, 0] was meant as; it stays that direction.
    let cfg = FieldConfig::parse(
        &set(FIELD, "pith.direction", Some("[1.0, 1.0, 0.0]")),
        origin,
    )
    .unwrap();
    assert_eq!(cfg.pith.direction, [1.0, 1.0, 0.0]);
    tally.add(reliability_support::Verdict::RightResult);
    // Defaults are filled in and written back in full: the copy reads as the same config.
    for (loader, text) in [
        ("field", FIELD.to_string()),
        ("nca", shipped("configs/nca/quick.toml")),
    ] {
        let copy = match loader {
            "field" => {
                let a = FieldConfig::parse(&text, origin).unwrap();
                let b = FieldConfig::parse(&xylem::config::to_toml(&a).unwrap(), origin).unwrap();
                a == b
            }
            _ => {
                let a = TrainConfig::parse(&text, origin).unwrap();
                let b = TrainConfig::parse(&xylem::config::to_toml(&a).unwrap(), origin).unwrap();
                a == b
            }
        };
        assert!(copy, "{loader}: the config copy reads differently");
        tally.add(reliability_support::Verdict::RightResult);
    }
    tally.print("configs (right results)");
}

/// Sizes the validation lets through but the machine cannot hold are refused by the
/// commands up front with the estimate, and the limits hold end to end.
#[test]
fn absurd_sizes_are_refused_before_work_starts() {
    let dir = reliability_support::scratch("rel-configs-cli");
    let (sample, _) = reliability_support::tiny_sample_and_nca(&dir, 16);
    let huge = dir.join("huge.toml");
    std::fs::write(
        &huge,
        "seed = 1\n[volume]\nsize = 512\ncrop = 512\n[schedule]\niterations = 3\n\
         steps = [64, 64]\n[pool]\nsize = 0\n[memory]\nsegment_steps = 0\n[loss]\n\
         face = \"moments\"\n",
    )
    .unwrap();
    let knots: String = (0..100)
        .map(|_| "[[knots]]\norigin = [0.0, 0.0, 0.0]\ndirection = [1.0, 0.0, 0.0]\n")
        .collect();
    let many = dir.join("many_knots.toml");
    std::fs::write(&many, format!("{FIELD}{knots}")).unwrap();

    let mut tally = Tally::default();
    let outcome = tally.judge_call(
        "nca: 512^3 crops of 64 steps (~12 TB of tape)",
        xylem()
            .args(["train", "--sample"])
            .arg(&sample)
            .arg("--fit")
            .arg(repo("configs/fields/distorted.toml"))
            .arg("--config")
            .arg(&huge)
            .arg("--out")
            .arg(dir.join("t")),
        &error(&["crop", "needs ~", "GB, this machine has", "smaller crop"]),
    );
    assert!(
        outcome.seconds < 20.0,
        "refused only after {:.0} s",
        outcome.seconds
    );
    tally.judge_call(
        "field: 100 knots end to end",
        xylem()
            .args(["field", "--size", "8", "--config"])
            .arg(&many)
            .arg("--out")
            .arg(dir.join("f")),
        &error(&["many_knots.toml", "`knots` = 100", "[0, 64]"]),
    );
    tally.judge_call(
        "species: a missing file",
        xylem()
            .args(["slice", "--plane", "cut1", "--size", "8", "--procedural"])
            .arg(dir.join("missing.toml"))
            .arg("--out")
            .arg(dir.join("s.png")),
        &error(&["missing.toml"]),
    );
    tally.print("configs (CLI)");
    std::fs::remove_dir_all(&dir).unwrap();
}
