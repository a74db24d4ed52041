//! Reliability suite (issue 16), family "npy and model files": the binary and record files
//! xylem reads back: `.npy` volumes (truncated, crafted headers: another dtype, Fortran
//! order, shapes whose product overflows, data of the wrong length), NRRD and Mitsuba
//! `.vol` volumes, a trained model's `model.toml` (bad grid, G range, white balance,
//! architecture) and `model.bpk` (flipped bytes, another model's weights, truncated), and
//! a training checkpoint (an iteration past the config, crafted state shapes, an optimiser
//! record burn cannot read, a short loss log). Each row is one file and its expected
//! outcome: an error naming the file and what was expected, or the right value. The
//! library loaders are probed directly; the rows where the probe saw the commands panic,
//! hang or leave temporary files (`slice`, `render`, `export`, `synth`) run the binary.

mod common;
mod reliability_support;

use std::path::{Path, PathBuf};

use burn::store::burn_pack::{Bytes, DType, Scalar, Tensor as PackTensor, Writer};
use xylem::Volume;
use xylem::device::DeviceKind;
use xylem::export::Values;
use xylem::io::npy::{read_npy, read_volume, write_npy};
use xylem::nca::model_dir::{ModelMeta, TrainedModel};
use xylem::nca::train::Trainer;

use reliability_support::{
    Expect, Tally, copy_dir, error, judge_result, set, tiny_data, tiny_model, xylem,
};

/// A `.npy` file with the header dictionary `dict` (padded as numpy does), format
/// `version` and `data` after it.
fn npy(dict: &str, version: u8, data: &[u8]) -> Vec<u8> {
    let len_bytes = if version == 1 { 2 } else { 4 };
    let mut text = dict.to_string();
    let unpadded = 6 + 2 + len_bytes + text.len() + 1;
    text.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    text.push('\n');
    let mut out = b"\x93NUMPY".to_vec();
    out.extend_from_slice(&[version, 0]);
    if version == 1 {
        out.extend_from_slice(&(text.len() as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    }
    out.extend_from_slice(text.as_bytes());
    out.extend_from_slice(data);
    out
}

fn dict(descr: &str, fortran: &str, shape: &str) -> String {
    format!("{{'descr': '{descr}', 'fortran_order': {fortran}, 'shape': {shape}, }}")
}

/// 2 x 2 x 2 x 3 float32 values 0, 0.01, ...
fn floats(n: usize) -> Vec<u8> {
    (0..n)
        .flat_map(|i| (i as f32 * 0.01).to_le_bytes())
        .collect()
}

/// A version 1.0 npy with the given header fields.
fn npy1(descr: &str, fortran: &str, shape: &str, data: &[u8]) -> Vec<u8> {
    npy(&dict(descr, fortran, shape), 1, data)
}

/// A version 1.0 npy of C-ordered little-endian float32 values of `shape`.
fn f4(shape: &str, data: &[u8]) -> Vec<u8> {
    npy1("<f4", "False", shape, data)
}

fn good_npy() -> Vec<u8> {
    f4("(2, 2, 2, 3)", &floats(24))
}

/// `bytes` with the byte at `at` set to `value`.
fn patched(bytes: &[u8], at: usize, value: u8) -> Vec<u8> {
    let mut b = bytes.to_vec();
    b[at] = value;
    b
}

struct FileRow {
    name: &'static str,
    bytes: Vec<u8>,
    expect: Expect,
}

fn file_row(name: &'static str, bytes: Vec<u8>, expect: Expect) -> FileRow {
    FileRow {
        name,
        bytes,
        expect,
    }
}

fn npy_rows() -> Vec<FileRow> {
    let good = good_npy();
    let mut extra = good.clone();
    extra.extend_from_slice(&[0, 0, 0, 0]);
    let mut long_header = good.clone();
    long_header[8..10].copy_from_slice(&60000u16.to_le_bytes());
    vec![
        file_row("npy: a good volume", good.clone(), Expect::Fine),
        file_row(
            "npy: format 2.0 header",
            npy(&dict("<f4", "False", "(2, 2, 2, 3)"), 2, &floats(24)),
            Expect::Fine,
        ),
        file_row(
            "npy: data cut in half",
            good[..good.len() - 48].to_vec(),
            error(&["npy shape [2, 2, 2, 3] needs 96 bytes of data, file has 48"]),
        ),
        file_row(
            "npy: 4 bytes too many",
            extra,
            error(&["needs 96 bytes of data, file has 100"]),
        ),
        file_row(
            "npy: cut inside the header",
            good[..20].to_vec(),
            error(&["truncated npy header"]),
        ),
        file_row(
            "npy: header length past the end",
            long_header,
            error(&["truncated npy header"]),
        ),
        file_row(
            "npy: a text file",
            b"x,y,z\n1,2,3\n".to_vec(),
            error(&["not a .npy file", "magic"]),
        ),
        file_row("npy: empty", Vec::new(), error(&["not a .npy file"])),
        file_row(
            "npy: float64",
            npy1("<f8", "False", "(2, 2, 2, 3)", &floats(48)),
            error(&["little-endian float32", "'<f4'"]),
        ),
        file_row(
            "npy: big-endian float32",
            npy1(">f4", "False", "(2, 2, 2, 3)", &floats(24)),
            error(&["little-endian float32"]),
        ),
        file_row(
            "npy: dtype '<f4x' (a substring match passed it)",
            npy1("<f4x", "False", "(2, 2, 2, 3)", &floats(24)),
            error(&["little-endian float32"]),
        ),
        file_row(
            "npy: descr given twice",
            npy(
                "{'descr': '<f8', 'descr': '<f4', 'fortran_order': False, 'shape': (2, 2, 2, 3), }",
                1,
                &floats(24),
            ),
            error(&["little-endian float32"]),
        ),
        file_row(
            "npy: Fortran order",
            npy1("<f4", "True", "(2, 2, 2, 3)", &floats(24)),
            error(&["C order", "fortran_order False"]),
        ),
        file_row(
            "npy: shape product overflows (4611686018427387904, 4, 1, 1)",
            f4("(4611686018427387904, 4, 1, 1)", &[]),
            error(&["npy shape", "too large to address"]),
        ),
        file_row(
            "npy: shape of 17 GB (1073741824, 1073741824, 4, 4)",
            f4("(1073741824, 1073741824, 4, 4)", &[]),
            error(&["too large to address"]),
        ),
        file_row(
            "npy: shape of 16 GB, no data",
            f4("(1073741824, 4, 1, 1)", &[]),
            error(&["needs 17179869184 bytes of data, file has 0"]),
        ),
        file_row(
            "npy: negative shape entry",
            f4("(-1, 2, 2, 3)", &floats(24)),
            error(&["npy shape entry \"-1\" is not a size"]),
        ),
        file_row(
            "npy: shape entry 1e3",
            f4("(1e3, 2, 2, 3)", &floats(24)),
            error(&["\"1e3\" is not a size"]),
        ),
        file_row(
            "npy: no shape",
            npy("{'descr': '<f4', 'fortran_order': False, }", 1, &floats(24)),
            error(&["npy header has no shape"]),
        ),
        file_row(
            "npy: 3-D array",
            f4("(2, 2, 6)", &floats(24)),
            error(&["volume must have shape [X, Y, Z, C]", "[2, 2, 6]"]),
        ),
        file_row(
            "npy: empty axis",
            f4("(0, 2, 2, 3)", &[]),
            error(&["empty axis", "all > 0"]),
        ),
        file_row(
            "npy: version 9",
            patched(&good, 6, 9),
            error(&["unsupported npy version 9"]),
        ),
    ]
}

fn volume_of(dims: [usize; 3], c: usize) -> Volume {
    let n = dims.iter().product::<usize>() * c;
    Volume::from_data(dims, c, (0..n).map(|i| i as f32 / n as f32).collect()).unwrap()
}

fn nrrd_rows(dir: &Path) -> Vec<FileRow> {
    let path = dir.join("good.nrrd");
    xylem::export::nrrd::write_nrrd(&path, &volume_of([2, 3, 2], 3), Values::Data).unwrap();
    let good = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&good).into_owned();
    let split = text.find("\n\n").unwrap();
    let with_header = |from: &str, to: &str, data: &[u8]| {
        let header = text[..split + 2].replace(from, to);
        let mut out = header.into_bytes();
        out.extend_from_slice(data);
        out
    };
    let data = &good[split + 2..];
    vec![
        file_row("nrrd: written by xylem", good.clone(), Expect::Fine),
        file_row(
            "nrrd: a zero size",
            with_header("sizes: 3 2 3 2", "sizes: 0 2 3 2", &[]),
            error(&["sizes [0, 2, 3, 2]", "every size > 0"]),
        ),
        file_row(
            "nrrd: sizes whose product overflows",
            with_header(
                "sizes: 3 2 3 2",
                "sizes: 3 4611686018427387904 4611686018427387904 2",
                data,
            ),
            error(&["data bytes for sizes"]),
        ),
        file_row(
            "nrrd: double data",
            with_header("type: float", "type: double", data),
            error(&["only raw little-endian float NRRD"]),
        ),
        file_row(
            "nrrd: gzip encoding",
            with_header("encoding: raw", "encoding: gzip", data),
            error(&["only raw little-endian float NRRD"]),
        ),
        file_row(
            "nrrd: data cut short",
            good[..good.len() - 5].to_vec(),
            error(&["data bytes for sizes [3, 2, 3, 2]"]),
        ),
        file_row(
            "nrrd: no blank line",
            b"NRRD0004\ntype: float\n".to_vec(),
            error(&["does not end with a blank line"]),
        ),
        file_row(
            "nrrd: 5 sizes",
            with_header("sizes: 3 2 3 2", "sizes: 3 2 3 2 1", data),
            error(&["expected 3 or 4 sizes"]),
        ),
    ]
}

fn vol_rows(dir: &Path) -> Vec<FileRow> {
    let path = dir.join("good.vol");
    xylem::export::mitsuba::write_vol(&path, &volume_of([2, 3, 2], 3)).unwrap();
    let good = std::fs::read(&path).unwrap();
    let with_dims = |dims: [i32; 4]| {
        let mut b = good.clone();
        for (i, d) in dims.iter().enumerate() {
            b[8 + 4 * i..12 + 4 * i].copy_from_slice(&d.to_le_bytes());
        }
        b
    };
    vec![
        file_row("vol: written by xylem", good.clone(), Expect::Fine),
        file_row(
            "vol: dimensions 2^31 - 1 (the byte count overflowed)",
            with_dims([i32::MAX, i32::MAX, i32::MAX, 3]),
            error(&[
                "data bytes for 2147483647x2147483647x2147483647x3",
                "addressed",
            ]),
        ),
        file_row(
            "vol: negative dimension",
            with_dims([-2, 3, 2, 3]),
            error(&["bad dimensions [-2, 3, 2]"]),
        ),
        file_row(
            "vol: data cut short",
            good[..good.len() - 4].to_vec(),
            error(&["data bytes for 2x3x2x3 float32 values (expected 144)"]),
        ),
        file_row(
            "vol: not a volume",
            b"VOX 123".to_vec(),
            error(&["not a Mitsuba volume"]),
        ),
        file_row(
            "vol: half-float encoding",
            patched(&good, 4, 2),
            error(&["only float32 encoding"]),
        ),
    ]
}

#[test]
fn damaged_volume_files_give_clear_errors() {
    let dir = reliability_support::scratch("rel-files-volumes");
    let mut tally = Tally::default();
    for (i, r) in npy_rows().into_iter().enumerate() {
        let path = dir.join(format!("row{i}.npy"));
        std::fs::write(&path, &r.bytes).unwrap();
        let result = read_volume(&path);
        tally.add(judge_result(r.name, &result, &r.expect));
        match &result {
            Ok(v) => {
                assert_eq!((v.dims, v.channels), ([2, 2, 2], 3), "{}", r.name);
                assert_eq!(v.data[23], 23.0f32 * 0.01, "{}", r.name);
            }
            Err(e) => assert!(e.to_string().contains(&path.display().to_string()), "{e}"),
        }
    }
    for (i, r) in nrrd_rows(&dir).into_iter().enumerate() {
        let path = dir.join(format!("row{i}.nrrd"));
        std::fs::write(&path, &r.bytes).unwrap();
        let result = xylem::export::nrrd::read_nrrd(&path);
        tally.add(judge_result(r.name, &result, &r.expect));
        if let Ok(v) = &result {
            assert_eq!(v, &volume_of([2, 3, 2], 3), "{}", r.name);
        }
    }
    for (i, r) in vol_rows(&dir).into_iter().enumerate() {
        let path = dir.join(format!("row{i}.vol"));
        std::fs::write(&path, &r.bytes).unwrap();
        let result = xylem::export::mitsuba::read_vol(&path);
        tally.add(judge_result(r.name, &result, &r.expect));
        if let Ok((v, bbox)) = &result {
            assert_eq!(v, &volume_of([2, 3, 2], 3), "{}", r.name);
            assert_eq!(bbox, &[-0.5, -0.5, -0.5, 0.5, 0.5, 0.5]);
        }
    }
    // A pool of zero slots is a valid array (read_npy), not a volume.
    let path = dir.join("empty-pool.npy");
    write_npy(&path, &[0, 12, 8, 8, 8], &[]).unwrap();
    let result = read_npy(&path);
    tally.add(judge_result(
        "npy: an empty pool array",
        &result,
        &Expect::Fine,
    ));
    tally.print("npy, NRRD and .vol files (library)");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// No temporary file is left beside the output when a command fails.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// The volumes the probe saw panic or hang the commands: each is now one clear error.
#[test]
fn commands_refuse_crafted_volumes() {
    let dir = reliability_support::scratch("rel-files-cli");
    let overflow = dir.join("overflow.npy");
    std::fs::write(&overflow, f4("(4611686018427387904, 4, 1, 1)", &[])).unwrap();
    let huge = dir.join("huge.npy");
    std::fs::write(&huge, f4("(1073741824, 1073741824, 4, 4)", &[])).unwrap();
    let mut tally = Tally::default();
    let mut cases: Vec<(String, Vec<std::ffi::OsString>, Expect)> = Vec::new();
    for (label, file) in [("overflow", &overflow), ("17 GB", &huge)] {
        cases.push((
            format!("export of a {label} shape"),
            vec![
                "export".into(),
                "--volume".into(),
                file.into(),
                "--out".into(),
                dir.join("x.vol").into(),
            ],
            error(&[&file.display().to_string(), "too large to address"]),
        ));
        cases.push((
            format!("render of a {label} shape"),
            vec![
                "render".into(),
                "--volume".into(),
                file.into(),
                "--size".into(),
                "8".into(),
                "--out".into(),
                dir.join("r.png").into(),
            ],
            error(&["too large to address"]),
        ));
        cases.push((
            format!("slice of a {label} shape"),
            vec![
                "slice".into(),
                "--volume".into(),
                file.into(),
                "--plane".into(),
                "cut1".into(),
                "--size".into(),
                "8".into(),
                "--out".into(),
                dir.join("s.png").into(),
            ],
            error(&["too large to address"]),
        ));
    }
    let fifo_made = std::process::Command::new("mkfifo")
        .arg(dir.join("fifo.npy"))
        .arg(dir.join("fifo.toml"))
        .status()
        .is_ok_and(|s| s.success());
    if fifo_made {
        cases.push((
            "slice of a FIFO named .npy (it hung)".into(),
            vec![
                "slice".into(),
                "--volume".into(),
                dir.join("fifo.npy").into(),
                "--plane".into(),
                "cut1".into(),
                "--out".into(),
                dir.join("f.png").into(),
            ],
            error(&["fifo.npy", "not a regular file", "expected a .npy file"]),
        ));
        reliability_support::write_tiny_sample(&dir.join("S"), 16);
        cases.push((
            "run with a FIFO as --nca-config (it hung)".into(),
            vec![
                "run".into(),
                "--sample".into(),
                dir.join("S").into(),
                "--nca-config".into(),
                dir.join("fifo.toml").into(),
                "--out".into(),
                dir.join("run").into(),
            ],
            error(&["fifo.toml", "not a regular file"]),
        ));
        cases.push((
            "field with a FIFO as its config (it hung)".into(),
            vec![
                "field".into(),
                "--config".into(),
                dir.join("fifo.toml").into(),
                "--out".into(),
                dir.join("field").into(),
            ],
            error(&["fifo.toml", "not a regular file"]),
        ));
    }
    // Meshes: a NaN vertex rendered only the background with exit code 0.
    for (file, text, expect) in [
        (
            "nan.obj",
            "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n",
            error(&["nan.obj", "vertex 3", "expected finite coordinates"]),
        ),
        (
            "index.obj",
            "v 0 0 0\nv 1 0 0\nf 1 2 9\n",
            error(&["index.obj", "cannot read as OBJ", "out of bounds"]),
        ),
        ("empty.obj", "garbage\n", error(&["empty.obj", "no faces"])),
    ] {
        std::fs::write(dir.join(file), text).unwrap();
        cases.push((
            format!("render of a mesh: {file}"),
            vec![
                "render".into(),
                "--field".into(),
                reliability_support::repo("configs/fields/minimal.toml").into(),
                "--mesh".into(),
                dir.join(file).into(),
                "--size".into(),
                "8".into(),
                "--out".into(),
                dir.join("m.png").into(),
            ],
            expect,
        ));
    }
    for (name, args, expect) in &cases {
        let outcome = tally.judge_call(name, xylem().args(args), expect);
        assert!(outcome.seconds < 10.0, "{name}: {:.1} s", outcome.seconds);
    }
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    for f in ["x.vol", "s.png", "r.png", "m.png"] {
        assert!(!dir.join(f).exists(), "{f} written by a refused command");
    }
    tally.print("volumes, meshes and FIFOs (CLI)");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `dir/model` with `model.toml` changed by `edit` (a copy).
fn model_copy(dir: &Path, name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let to = dir.join(name);
    copy_dir(&dir.join("model"), &to);
    let text = std::fs::read_to_string(to.join("model.toml")).unwrap();
    std::fs::write(to.join("model.toml"), edit(&text)).unwrap();
    to
}

/// An edit of `model.toml` that sets `key` (dotted) to the TOML value `value`.
fn setting(key: &'static str, value: &'static str) -> Box<dyn Fn(&str) -> String> {
    Box::new(move |t| set(t, key, Some(value)))
}

fn without_hash(text: &str) -> String {
    set(text, "weights_hash", None)
}

#[test]
fn damaged_models_and_checkpoints_give_clear_errors() {
    let dir = reliability_support::scratch("rel-files-model");
    let (sample, cfg) = tiny_model(&dir);
    let device = DeviceKind::Flex.device();
    let mut tally = Tally::default();

    // model.toml and model.bpk.
    type Edit = Box<dyn Fn(&str) -> String>;
    let meta_rows: Vec<(&str, Edit, Expect)> = vec![
        (
            "model: as trained",
            Box::new(|t| t.to_string()),
            Expect::Fine,
        ),
        (
            "model.toml: grid = 0",
            setting("grid", "0"),
            error(&["model.toml", "`grid` = 0", "[4, 1024]"]),
        ),
        (
            "model.toml: grid = 100000",
            setting("grid", "100000"),
            error(&["`grid` = 100000"]),
        ),
        (
            "model.toml: white_balance = [0, 0, 0] (gave a +-inf volume)",
            setting("normalisation.white_balance", "[0.0, 0.0, 0.0]"),
            error(&["normalisation.white_balance[0]", "> 0"]),
        ),
        (
            "model.toml: white_balance inf",
            setting("normalisation.white_balance", "[inf, 1.0, 1.0]"),
            error(&["normalisation.white_balance[0]", "inf"]),
        ),
        (
            "model.toml: NaN colour_projection",
            setting(
                "normalisation.colour_projection",
                "[[nan, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
            ),
            error(&["normalisation.colour_projection", "finite in [-1, 1]"]),
        ),
        (
            "model.toml: NaN g_range",
            setting("normalisation.g_range", "[nan, 300.0]"),
            error(&["normalisation.g_range", "low < high"]),
        ),
        (
            "model.toml: equal g_range",
            setting("normalisation.g_range", "[5.0, 5.0]"),
            error(&["normalisation.g_range", "[5, 5]"]),
        ),
        (
            "model.toml: g_range of 3 values",
            setting("normalisation.g_range", "[1.0, 2.0, 3.0]"),
            error(&["normalisation.g_range: 3 values given, expected 2"]),
        ),
        (
            "model.toml: hidden 0",
            setting("spec.hidden", "0"),
            error(&["spec.hidden", "[1, 1024]"]),
        ),
        (
            "model.toml: hidden other than the weights",
            setting("spec.hidden", "16"),
            error(&["model.bpk", "not a burnpack model of this architecture"]),
        ),
        (
            "model.toml: a face G",
            setting("faces", "[\"G\"]"),
            error(&["model.toml", "unknown variant `G`"]),
        ),
        (
            "model.toml: unknown key",
            setting("temperature", "3"),
            error(&["model.toml", "unknown field `temperature`"]),
        ),
        (
            "model.toml: another weights_hash",
            setting("weights_hash", "\"0123456789abcdef\""),
            error(&["model.bpk", "content hash", "differs from weights_hash"]),
        ),
        (
            "model.toml: no weights_hash (an older model) loads",
            Box::new(without_hash),
            Expect::Fine,
        ),
    ];
    for (i, (name, edit, expect)) in meta_rows.iter().enumerate() {
        let m = model_copy(&dir, &format!("meta{i}"), edit);
        let result = ModelMeta::load(&m).and_then(|_| TrainedModel::load(&m, &device));
        tally.add(judge_result(name, &result, expect));
        if let Ok(model) = &result {
            assert!(model.model.matches(&model.meta.spec), "{name}");
        }
    }
    let weights = std::fs::read(dir.join("model/model.bpk")).unwrap();
    let mut flipped = weights.clone();
    let at = flipped.len() - 20;
    flipped[at] ^= 0x40;
    let bpk_rows: Vec<(&str, Vec<u8>, bool, Expect)> = vec![
        (
            "model.bpk: one flipped bit (loaded, gave colours in -2..0.85)",
            flipped.clone(),
            true,
            error(&[
                "model.bpk",
                "content hash",
                "the weights were damaged or replaced",
            ]),
        ),
        (
            "model.bpk: truncated, no hash to check",
            weights[..weights.len() / 2].to_vec(),
            false,
            error(&["model.bpk", "not a burnpack model"]),
        ),
        (
            "model.bpk: a text file, no hash to check",
            b"weights".to_vec(),
            false,
            error(&["model.bpk", "not a burnpack model"]),
        ),
    ];
    for (i, (name, bytes, hashed, expect)) in bpk_rows.into_iter().enumerate() {
        let m = model_copy(&dir, &format!("bpk{i}"), |t| {
            if hashed {
                t.to_string()
            } else {
                without_hash(t)
            }
        });
        std::fs::write(m.join("model.bpk"), bytes).unwrap();
        tally.add(judge_result(
            name,
            &TrainedModel::load(&m, &device),
            &expect,
        ));
    }
    // Another architecture's weights under this model.toml.
    let other = dir.join("other");
    std::fs::create_dir_all(&other).unwrap();
    let mut wide = cfg.model.clone();
    wide.hidden = 16;
    xylem::nca::model_dir::save_weights(
        &xylem::nca::Nca::init(&wide, 1, &device),
        &other.join("model.bpk"),
    )
    .unwrap();
    let m = model_copy(&dir, "swapped", without_hash);
    std::fs::copy(other.join("model.bpk"), m.join("model.bpk")).unwrap();
    tally.add(judge_result(
        "model.bpk: another model's weights",
        &TrainedModel::load(&m, &device),
        &error(&[
            "model.bpk",
            "not a burnpack model of this architecture",
            "shape mismatch",
        ]),
    ));
    let m = model_copy(&dir, "nofit", |t| t.to_string());
    std::fs::remove_file(m.join("fit.toml")).unwrap();
    tally.add(judge_result(
        "model folder without fit.toml",
        &TrainedModel::load(&m, &device),
        &error(&["fit.toml"]),
    ));
    tally.add(judge_result(
        "a folder that is not a model",
        &TrainedModel::load(&sample, &device),
        &error(&["no model.bpk here", "xylem train"]),
    ));

    // The checkpoint, restored into a trainer of the same config.
    let data = tiny_data(&sample, &cfg);
    let mut trainer = Trainer::new(&cfg, &data, DeviceKind::Flex).unwrap();
    type Damage = Box<dyn Fn(&Path)>;
    let edit_progress = |key: &'static str, value: &'static str| -> Damage {
        Box::new(move |c: &Path| {
            let p = c.join("checkpoint/progress.toml");
            let text = std::fs::read_to_string(&p).unwrap();
            std::fs::write(&p, set(&text, key, Some(value))).unwrap();
        })
    };
    let write_optimiser =
        |tensors: Vec<PackTensor>, scalars: Vec<(&'static str, Scalar)>| -> Damage {
            let mut writer = Writer::new(tensors);
            for (k, v) in scalars {
                writer = writer.with_scalar(k, v);
            }
            let bytes = writer.into_bytes().unwrap().to_vec();
            Box::new(move |c: &Path| {
                std::fs::write(c.join("checkpoint/optimiser.bpk"), &bytes).unwrap();
            })
        };
    let moment = |param_id: Option<u64>, shape: Vec<usize>| {
        let n: usize = shape.iter().product();
        PackTensor::new(
            "moment_1".into(),
            DType::F32,
            shape,
            param_id,
            Bytes::from_bytes_vec(vec![0u8; 4 * n]),
        )
    };
    let w1 = trainer_param_id(&dir);
    let checkpoint_rows: Vec<(&str, Damage, Expect)> = vec![
        (
            "checkpoint: as saved",
            Box::new(|_: &Path| {}),
            Expect::Fine,
        ),
        (
            "checkpoint: iteration = 999999",
            edit_progress("iteration", "999999"),
            error(&[
                "progress.toml",
                "iteration = 999999",
                "at most the config's 2 iterations",
            ]),
        ),
        (
            "checkpoint: state_dims whose product overflows (it panicked)",
            edit_progress("state_dims", "[12, 4294967296, 4294967296, 1]"),
            error(&["progress.toml", "state_dims", "expected [12, 8, 8, 8]"]),
        ),
        (
            "checkpoint: a pool slot the config does not have",
            edit_progress("pool_offsets", "[[0, 0, 0]]"),
            error(&["progress.toml", "pool_offsets has 1 entries", "(0)"]),
        ),
        (
            "checkpoint: an optimiser tensor without a parameter id (it panicked)",
            write_optimiser(vec![moment(None, vec![2])], vec![]),
            error(&["optimiser.bpk", "belongs to no parameter"]),
        ),
        (
            "checkpoint: an optimiser state of rank 10 (it panicked)",
            write_optimiser(vec![], vec![("77.__rank", Scalar::UInt(10))]),
            error(&["optimiser.bpk", "77.__rank", "not the rank of a parameter"]),
        ),
        (
            "checkpoint: an optimiser state of another shape",
            write_optimiser(vec![moment(Some(w1), vec![3, 3])], vec![]),
            error(&["optimiser.bpk", "shape [3, 3]"]),
        ),
        (
            "checkpoint: optimiser.bpk of random bytes",
            Box::new(|c: &Path| {
                std::fs::write(c.join("checkpoint/optimiser.bpk"), [7u8; 100]).unwrap()
            }),
            error(&["optimiser.bpk"]),
        ),
        (
            "checkpoint: loss.csv shorter than the iteration (left a gap)",
            Box::new(|c: &Path| {
                let p = c.join("checkpoint/loss.csv");
                let text = std::fs::read_to_string(&p).unwrap();
                let kept: Vec<&str> = text.lines().take(2).collect();
                std::fs::write(&p, kept.join("\n") + "\n").unwrap();
            }),
            error(&["loss.csv", "has 1 rows", "at iteration 2"]),
        ),
        (
            "checkpoint: loss.csv with another header",
            Box::new(|c: &Path| {
                std::fs::write(c.join("checkpoint/loss.csv"), "step,loss\n0,1\n").unwrap()
            }),
            error(&["loss.csv", "unexpected header"]),
        ),
        (
            "checkpoint: pool.npy missing",
            Box::new(|c: &Path| std::fs::remove_file(c.join("checkpoint/pool.npy")).unwrap()),
            error(&["pool.npy"]),
        ),
        (
            "checkpoint: pool.npy of another shape",
            Box::new(|c: &Path| {
                write_npy(
                    &c.join("checkpoint/pool.npy"),
                    &[1, 12, 8, 8, 8],
                    &vec![0.0; 6144],
                )
                .unwrap()
            }),
            error(&["pool.npy", "does not match progress.toml"]),
        ),
    ];
    for (i, (name, damage, expect)) in checkpoint_rows.iter().enumerate() {
        let root = dir.join(format!("ckpt{i}"));
        copy_dir(&dir.join("model/checkpoint"), &root.join("checkpoint"));
        damage(&root);
        let result = xylem::nca::train::snapshot::load(&root, &mut trainer);
        tally.add(judge_result(name, &result, expect));
        if let Ok(rows) = &result {
            assert_eq!((rows.len(), trainer.iteration), (2, 2), "{name}");
        }
    }
    tally.print("model and checkpoint files (library)");

    // The commands on damaged models: synth refuses them up front.
    let mut cli = Tally::default();
    // `xylem synth --steps 2 --model MODEL --out DIR/OUT`.
    let synth = |model: &Path, out: &str| {
        let mut cmd = xylem();
        cmd.args(["synth", "--steps", "2", "--model"])
            .arg(model)
            .arg("--out")
            .arg(dir.join(out));
        cmd
    };
    for (name, edit, expect) in [
        (
            "synth: model.toml grid = 0 (it panicked)",
            "0",
            error(&["model.toml", "`grid` = 0"]),
        ),
        (
            "synth: model.toml grid = 1024, no --size",
            "1024",
            error(&[
                "synthesis size",
                "needs ~",
                "GB, this machine has",
                "smaller --size",
            ]),
        ),
    ] {
        let m = model_copy(&dir, &format!("synth-{edit}"), |t| {
            without_hash(&set(t, "grid", Some(edit)))
        });
        let outcome = cli.judge_call(name, &mut synth(&m, &format!("out-{edit}")), &expect);
        assert!(outcome.seconds < 10.0, "{name}: {:.1} s", outcome.seconds);
    }
    let m = model_copy(&dir, "synth-flipped", |t| t.to_string());
    std::fs::write(m.join("model.bpk"), &flipped).unwrap();
    cli.judge_call(
        "synth: flipped weights",
        &mut synth(&m, "out-flipped"),
        &error(&["model.bpk", "differs from weights_hash"]),
    );
    cli.judge_call(
        "synth: the tiny model",
        synth(&dir.join("model"), "out-good").args(["--size", "8"]),
        &Expect::Fine,
    );
    let volume = read_volume(&dir.join("out-good/volume.npy")).unwrap();
    assert_eq!((volume.dims, volume.channels), ([8, 8, 8], 3));
    assert!(volume.data.iter().all(|v| v.is_finite()));
    cli.print("model files (CLI)");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The parameter id of `w1` in the tiny model's weights (keys its optimiser state).
fn trainer_param_id(dir: &Path) -> u64 {
    let meta = ModelMeta::load(&dir.join("model")).unwrap();
    let model = xylem::nca::model_dir::load_weights(
        &meta.spec,
        &dir.join("model/model.bpk"),
        &DeviceKind::Flex.device(),
    )
    .unwrap();
    model.w1.id.val()
}
